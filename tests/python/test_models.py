"""acuity.models from Python: numpy broadcasting, independent formulas, errors."""
import math

import numpy as np
import pytest

import acuity.models as m


def test_scalars_in_scalar_out():
    assert isinstance(m.geisler_perry_cutoff(0.0), float)
    assert m.geisler_perry_cutoff(0.0) == pytest.approx(39.2347, abs=5e-5)


def test_broadcasting_matches_elementwise():
    f = np.logspace(-1, 1.5, 7)[:, None]
    e = np.array([0.0, 5.0, 20.0])[None, :]
    out = m.threshold(f, e, 1.0)
    assert out.shape == (7, 3)
    for i in range(7):
        for j in range(3):
            assert out[i, j] == m.threshold(float(f[i, 0]), float(e[0, j]), 1.0)


def test_default_model_against_numpy_formula():
    f = np.logspace(-1.5, 1.8, 40)
    e, v = 12.0, 4.0
    c0, c1, c2 = 1.14, 0.67, 1.7
    peak = 45.9 / (2 * np.pi * c1 * (c2 * v + 2))
    rho = np.maximum(f, peak)
    k = 6.1 + 7.3 * np.abs(np.log10(c2 * v / 3)) ** 3
    s = c0 * c2 * v * (2 * np.pi * c1 * rho) ** 2 * np.exp(-4 * np.pi * c1 * rho * (c2 * v + 2) / 45.9) * k
    expected = np.exp(0.106 * f * e / 2.3) / s
    np.testing.assert_allclose(m.threshold(f, e, v), expected, rtol=1e-12)


def test_inverse_on_arrays():
    c = np.logspace(-2, 0, 9)
    f = m.max_visible_frequency(c, 10.0, 2.0)
    assert np.all(f > 0)
    np.testing.assert_allclose(m.threshold(f, 10.0, 2.0), c, rtol=1e-9)


def test_models_and_fits_by_name():
    gp = m.threshold(8.0, 10.0, 0.15, model="geisler-perry")
    assert gp == pytest.approx(math.exp(0.106 * 8 * (10 + 2.3) / 2.3) / 64, rel=1e-13)
    assert m.daly_csf(2.0, 1.0, fit="laird2006") != m.daly_csf(2.0, 1.0)
    with pytest.raises(ValueError, match="unknown model"):
        m.threshold(1.0, 1.0, 1.0, model="kelly")
    with pytest.raises(ValueError, match="unknown fit"):
        m.daly_csf(1.0, 1.0, fit="daly")


def test_params_override():
    p = m.ModelParams()
    p.ct0 = 0.01
    assert m.geisler_perry_cutoff(0.0, params=p) == pytest.approx(math.log(100) / 0.106, rel=1e-12)
    assert m.geisler_perry_cutoff(0.0) == pytest.approx(39.2347, abs=5e-5)


def test_hard_cases():
    out = m.threshold(np.array([0.0, 1e6, np.nan, np.inf]), 180.0, np.array([0.0, 1e6, 1.0, 1.0]))
    assert np.isfinite(out[[0, 1, 3]]).all()
    assert np.isnan(out[2])
    assert m.max_visible_frequency(1 / 128, 0.0, 0.15, model="geisler-perry") == 0.0


def test_reddy_and_mar():
    assert m.reddy_eccentricity(45.0) == 0.035624256837098696
    np.testing.assert_allclose(m.mar(np.array([0.0, 10.0])), [1 / 48, 0.22 + 1 / 48])
    assert m.reddy_cutoff(0.5, 3.0) == 60.0


def test_guenter_layers():
    g = m.guenter_layers(51, 59, 1920, 9 / 16, 0.022, 3)
    assert g["e_star"] == pytest.approx(23.4, abs=0.05)
    assert g["omega_star"] == pytest.approx(0.0516, abs=5e-5)
    assert len(g["radius"]) == 3 and g["sampling"][0] == 1.0
    assert g["speedup"] == pytest.approx(g["display_work"] / g["work"])
    with pytest.raises(ValueError):
        m.guenter_layers(51, 59, 1920, 9 / 16, 0.022, 0)
