"""acuity.spectra and acuity.lodgen from Python, against analytic answers."""
import os

import numpy as np
import pytest

import acuity

MESHES = os.environ.get("ACUITY_MESH_DIR", "")


def test_lost_contrast_of_a_grating():
    n = 128
    y, x = np.mgrid[0:n, 0:n]
    reference = np.full((n, n), 0.5, np.float32)
    level = (0.5 * (1 + 0.2 * np.cos(2 * np.pi * 16 * x / n))).astype(np.float32)
    lost, bands = acuity.spectra.lost_contrast(level, reference)
    b = list(bands).index(16.0)
    assert lost.shape == (8, len(bands))
    assert lost[0, b] == pytest.approx(0.2, rel=0.05)
    assert lost.sum() - lost[0, b] < 0.01
    same, _ = acuity.spectra.lost_contrast(reference, reference)
    assert not same.any()


def test_lost_contrast_maps_show_where_the_loss_lies():
    """A grating patch in the left half: the map of its band holds the loss there (its maximum is
    lost_contrast's), the right half holds almost none."""
    n = 128
    y, x = np.mgrid[0:n, 0:n]
    reference = np.full((n, n), 0.5, np.float32)
    window = np.exp(-((x - 32) ** 2 + (y - 64) ** 2) / (2 * 10.0 ** 2))
    level = (0.5 * (1 + 0.2 * window * np.cos(2 * np.pi * 16 * x / n))).astype(np.float32)
    lost, bands = acuity.spectra.lost_contrast(level, reference)
    maps, map_bands = acuity.spectra.lost_contrast_maps(level, reference)
    assert list(map_bands) == list(bands) and len(maps) == len(bands)
    for b, m in enumerate(maps):
        assert m.shape[0] == 8 and m.shape[1] == m.shape[2] and n % m.shape[1] == 0
        assert np.allclose(m.max(axis=(1, 2)), lost[:, b], rtol=1e-6, atol=1e-9)
    b = list(bands).index(16.0)
    m = maps[b][0]
    half = m.shape[1] // 2
    assert m[:, :half].max() == pytest.approx(lost[0, b]) and m[:, half + half // 4:].max() < 0.05 * lost[0, b]


def test_render_and_features_of_a_sphere_chain():
    import math
    # An octahedron-based sphere: coarse levels lose contrast the finest does not.
    t = (1 + 5 ** 0.5) / 2
    p = np.array([[-1, t, 0], [1, t, 0], [-1, -t, 0], [1, -t, 0], [0, -1, t], [0, 1, t], [0, -1, -t], [0, 1, -t],
                  [t, 0, -1], [t, 0, 1], [-t, 0, -1], [-t, 0, 1]], np.float32)
    p /= np.linalg.norm(p, axis=1)[:, None]
    f = np.array([0, 11, 5, 0, 5, 1, 0, 1, 7, 0, 7, 10, 0, 10, 11, 1, 5, 9, 5, 11, 4, 11, 10, 2, 10, 7, 6, 7, 1, 8,
                  3, 9, 4, 3, 4, 2, 3, 2, 6, 3, 6, 8, 3, 8, 9, 4, 9, 5, 2, 4, 11, 6, 2, 10, 8, 6, 7, 9, 8, 1], np.uint32)
    img = acuity.spectra.render(p, f, direction=(0, 0, 1), pixels=64, supersample=2)
    assert img.shape == (64, 64)
    assert img[0, 0] == pytest.approx(0.5)           # background in the corner
    assert 0.5 < img[32, 32] < 0.85                   # lit albedo 0.8 at the centre
    assert np.array_equal(img, acuity.spectra.render(p, f, direction=(0, 0, 1), pixels=64, supersample=2))
    assert len(acuity.spectra.reddy_features(img)) == 8
    data, report = acuity.spectra.build_profile([(p, f), (p, f)], pixels=64)
    prof = acuity.Profile.from_bytes(data)
    assert report["views_kept"] == 1 and prof.level_count == 2  # identical levels: one view suffices
    assert not prof.lost.any()
    assert report["views_sampled"] == 162 and report["bound_pessimism"] == 0  # cell bounds: nothing lost anywhere
    # A coarse level: the bounded profile stores at least the unbounded one's values, per view.
    coarse = np.array([0, 4, 8, 1, 5, 9], np.uint32)  # two triangles of the 20: lost contrast everywhere
    bounded, rb = acuity.spectra.build_profile([(p, f), (p, coarse)], pixels=64, views=6)
    own, ro = acuity.spectra.build_profile([(p, f), (p, coarse)], pixels=64, views=6, bound_cells=False)
    assert ro["views_sampled"] == 6 and rb["views_sampled"] == 6 + 162
    lb, lo = acuity.Profile.from_bytes(bounded).lost, acuity.Profile.from_bytes(own).lost
    assert lb.shape == lo.shape and (lb >= lo).all() and (lb > lo).any()


def test_lodgen_build_returns_the_summary(tmp_path):
    assert os.path.exists(os.path.join(MESHES, "elephant.off")), "ACUITY_MESH_DIR: libcgal-demo meshes needed"
    out = tmp_path / "e.glb"
    s = acuity.lodgen.build(os.path.join(MESHES, "elephant.off"), str(out), levels=3)
    assert out.exists()
    levels = s["meshes"][0]["levels"]
    assert [l["triangles"] for l in levels] == [5558, 2779, 1390] or abs(levels[1]["triangles"] - 2779) <= 56
    assert levels[0]["hausdorff_diameters"] == 0 and levels[2]["hausdorff_diameters"] >= levels[1]["hausdorff_diameters"] > 0
    with pytest.raises(ValueError, match="no-such-file"):
        acuity.lodgen.build(str(tmp_path / "no-such-file.off"))
