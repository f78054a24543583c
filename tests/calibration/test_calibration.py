"""scripts/calibration.py's machinery on a few conditions (the suite itself: docs/spectra.md).

Asserts what the suite relies on, never today's scores: the stimulus reads its contrast, the
scheduler sees the geometry the suite means, scores are finite, 0 at zero contrast and linear in it.
"""
import math
import os
import sys

import numpy as np
import pytest

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "scripts"))
import calibration  # noqa: E402

import acuity  # noqa: E402

SUBSET = [(8.0, 4.0, 0.0, 0.0, 0.0), (2.0 ** 1.5, 2.0, 10.0, 3.0, 11.25), (1.0, 4.0, 20.0, 10.0, 0.0),
          (16.0, 1.0, 0.0, 0.0, 11.25)]


def test_the_suite_spans_what_the_issue_asks():
    c = calibration.conditions()
    assert len(c) >= 35
    f = [x[0] for x in c]
    assert min(f) == pytest.approx(0.5) and max(f) == pytest.approx(16.0)
    assert {x[2] for x in c} == {"on", "between"}
    assert {x[3] for x in c} == {0.0, 11.25}  # on an analysis orientation and half-way between two
    assert min(x[1] for x in c) == 0.5 and max(x[1] for x in c) == 4.0
    assert max(x[4] for x in c) == 40.0 and max(x[5] for x in c) == 10.0
    for f, size, place, _, _, _ in c:  # f D on a band centre (a power of two) or half-way between two
        half = 2 * math.log2(f * size)
        assert half == pytest.approx(round(half), abs=1e-9)
        assert (round(half) % 2 == 0) == (place == "on")


def test_a_narrowband_patch_reads_its_contrast_in_its_band():
    patch, background = calibration.gabor(8.0, 4.0, 0.01)  # 32 cycles per diameter: a band centre
    lost, bands = acuity.spectra.lost_contrast(patch, background, orientations=8)
    b = int(np.argmin(np.abs(np.asarray(bands) - 32.0)))
    assert lost[0, b] == pytest.approx(0.01, rel=0.03)  # orientation 0: the frequency vector along +x
    assert lost[0, b] == lost.max()
    patch, background = calibration.gabor(8.0, 4.0, 0.01, angle=22.5)  # orientation 1: up from +x
    lost, bands = acuity.spectra.lost_contrast(patch, background, orientations=8)
    assert lost[1, b] == pytest.approx(0.01, rel=0.03) and lost[1, b] == lost.max()


@pytest.mark.parametrize("f,size,e,v,angle", SUBSET)
def test_scores_are_finite_and_the_geometry_is_the_suites(f, size, e, v, angle):
    r = calibration.measure(f, size, e, v, angle=angle)
    assert r["threshold"] < 1
    for path in ("exact", "tabulated"):
        assert math.isfinite(r[path]) and r[path] > 0
        ex = r[path + "_explain"]
        assert ex["angular_diameter_deg"] == pytest.approx(size, rel=1e-4)
        assert ex["eccentricity_deg"] == pytest.approx(max(0.0, e - size / 2), abs=1e-3)
        assert ex["retinal_velocity_deg_s"] == pytest.approx(max(v, 0.15) if v else 0.0, abs=1e-3)


@pytest.mark.parametrize("f,size,e,v,angle", SUBSET)
def test_zero_contrast_scores_zero_and_the_score_is_linear_in_contrast(f, size, e, v, angle):
    zero = calibration.measure(f, size, e, v, contrast=0.0, angle=angle)
    one = calibration.measure(f, size, e, v, contrast=0.004, angle=angle)
    two = calibration.measure(f, size, e, v, contrast=0.008, angle=angle)
    for path in ("exact", "tabulated"):
        assert zero[path] == 0.0
        assert two[path] == pytest.approx(2.0 * one[path], rel=1e-3)


def test_the_table_has_every_condition():
    results = [calibration.measure(f, s, e, v, angle=a) for f, s, e, v, a in SUBSET]
    text = calibration.table(results)
    assert text.count("\n") == 1 + len(SUBSET)
    assert "within 0.7-1.4" in calibration.statistics([r["exact"] for r in results])
