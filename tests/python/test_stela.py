"""stelaCSF: the numpy transcription (stela_reference.py) against the authors' code run under Octave,
and acuity's C++ model against the transcription."""
import math

import numpy as np
import pytest

import acuity.models as m
import stela_reference as ref

# shared/reference/vision-models.md section 4.1: gfxdisp/stelaCSF 052b15e under GNU Octave, printed
# to 6 significant digits: (rho cpd, omega Hz, L cd/m^2, A deg^2, e deg) -> S, vis_field 0.
OCTAVE = [
    ((4, 0, 100, 1, 0), 157.000), ((1, 0, 100, 1, 0), 59.1348), ((8, 0, 100, 1, 0), 120.603),
    ((16, 0, 100, 1, 0), 49.5496), ((32, 0, 100, 1, 0), 11.0234), ((4, 8, 100, 1, 0), 84.4718),
    ((4, 0, 10, 1, 0), 90.3300), ((4, 0, 1, 1, 0), 30.6402), ((4, 0, 100, 1, 10), 13.7718),
    ((4, 0, 100, 1, 30), 0.105967), ((2, 5, 50, math.pi, 5), 76.8853),
]


@pytest.mark.parametrize("cond,expected", OCTAVE)
def test_transcription_matches_the_authors_code(cond, expected):
    assert float(ref.sensitivity(*cond)) == pytest.approx(expected, rel=4e-6)


def test_acuity_matches_the_transcription_on_a_grid():
    rho = np.logspace(-1.5, 1.8, 12)[:, None, None, None, None]
    omega = np.array([0.0, 0.7, 5.0, 25.0])[None, :, None, None, None]
    lum = np.array([0.05, 3.0, 100.0])[None, None, :, None, None]
    area = np.array([0.1, 2.0, 300.0])[None, None, None, :, None]
    ecc = np.array([0.0, 4.0, 25.0])[None, None, None, None, :]
    for vis_field in (0.0, 90.0, 180.0, 240.0):
        expected = ref.sensitivity(rho, omega, lum, area, ecc, vis_field)
        got = m.stela_csf(rho, omega, lum, area, ecc, vis_field)
        np.testing.assert_allclose(got, expected, rtol=1e-11)


def test_threshold_model_is_the_most_sensitive_meridian_at_f_times_retinal_speed_less_drift():
    f = np.logspace(-1, 1.6, 25)
    for e in (0.0, 6.0, 20.0):
        for v in (0.0, 0.15, 2.0, 9.0):
            omega = f * (max(v, 0.15) - 0.15)
            s = np.maximum(ref.sensitivity(f, omega, 100.0, 1e300, e, 180.0),
                           ref.sensitivity(f, omega, 100.0, 1e300, e, 0.0))
            np.testing.assert_allclose(m.threshold(f, e, v, model="stela-csf"), 1 / s, rtol=1e-11)


def test_luminance_and_area_are_parameters():
    p = m.ModelParams()
    assert p.luminance == 100.0 and math.isinf(p.area)
    p.luminance, p.area, p.drift = 50.0, math.pi, 0.0
    ct = m.threshold(2.0, 5.0, 2.5, model="stela-csf", params=p)  # omega = 2 x 2.5 = 5 Hz
    assert ct == pytest.approx(1 / float(ref.sensitivity(2.0, 5.0, 50.0, math.pi, 5.0, 180.0)), rel=1e-12)
    f = m.max_visible_frequency(0.05, 5.0, 2.5, model="stela-csf", params=p)
    assert m.threshold(f, 5.0, 2.5, model="stela-csf", params=p) == pytest.approx(0.05, rel=1e-9)


def test_unknown_model_names_the_known_ones():
    with pytest.raises(ValueError, match="stela-csf"):
        m.threshold(1.0, 1.0, 1.0, model="stela")
