#!/usr/bin/python3
"""The prediction chain on stimuli with known answers (issue 47 item 2): prints docs/spectra.md's table.

  PYTHONPATH=build/python python3 scripts/calibration.py            the table (markdown) on stdout
  PYTHONPATH=build/python python3 scripts/calibration.py --csv      one line per condition and path
  PYTHONPATH=build/python python3 scripts/calibration.py --model default   the default chain's reading

Each condition is a Gabor patch, contrast c exp(-r^2 / 2 sigma^2) cos(2 pi f x) on a uniform
background, the whole object: its window of 6 sigma is the bounding sphere's diameter D (so sigma =
D / 6) and the snapshot (256 px) frames exactly that diameter. The carrier's frequency f [cpd] lies
on an analysis band's centre (f D a power of two cycles per diameter) or half-way between two (f D
= 2^(k + 1/2)), its orientation on an analysis orientation (0 deg: vertical bars) or half-way
between two (11.25 deg). It is shown at stelaCSF's threshold contrast for the eccentricity the scheduler can
know (the gaze's angle to the nearest point of the sphere, gaze uncertainty 0): c = 1 / S with S =
stela_csf(f, f v, 50 cd/m^2, pi sigma^2, e_near) at the more sensitive of the temporal and nasal
meridians, v the patch's drift across its bars on the retina (the eye holds still: the gaze reports
zero velocity). Then the whole chain: the image and the background go through
acuity.spectra.lost_contrast (8 orientations, octave bands) -> a one-view, two-level profile ->
the scheduler (perceptual rule, q = 1, model stela-csf at 50 cd/m^2, gaze uncertainty 0, a display of
91 px/deg so that the display never limits) -> level 1's score (keep_scores: lost / CT pooled over
orientations and bands, docs/design.md section 5), on the exact and the tabulated path. 1 is calibrated; above 1 the chain
is strict (it calls the patch visible at a contrast below its threshold: triangles given away);
below 1 it under-predicts (a visible loss let through). Conditions whose threshold contrast
exceeds 1 (no contrast shows them) are left out of the statistics and marked "-".

Deterministic: the same build prints the same bytes.
"""
import argparse
import math
import sys

import numpy as np

import acuity

LUMINANCE = 50.0       # [cd/m^2], the stimulus's and the chain's
PIXELS = 256           # snapshot size [px] across the bounding sphere's diameter
ORIENTATIONS = 8
PX_PER_DEG = 91.0      # the display: fine enough never to limit
DISTANCE = 2.0         # [m] from the eye to the patch's centre
BACKGROUND = 0.5       # the snapshots' luminance units (only ratios matter)
SIZES = (0.5, 1.0, 2.0, 4.0)               # window D [deg]
ECCENTRICITIES = (0.0, 10.0, 20.0, 40.0)   # gaze to the patch's centre [deg]
SPEEDS = (0.0, 3.0, 10.0)                  # retinal drift across the bars [deg/s]
ANGLES = (0.0, 90.0 / ORIENTATIONS)        # the carrier's orientation: on an analysis orientation, between two
LOWEST, HIGHEST = 0.5, 16.0                # carrier range [cpd]
MIN_CYCLES = 4.0                           # f D >= 4: at least 2/3 of a cycle per sigma, but for the largest
                                           # size, where f D >= 2 reaches 0.5 cpd


def carriers(size):
    """(f [cpd], 'on' | 'between') for a window of `size` degrees: f D on or between octave band centres."""
    out = []
    for half in range(-4, 20):
        cycles = 2.0 ** (half / 2)
        f = cycles / size
        if (cycles >= MIN_CYCLES or (size == max(SIZES) and cycles >= 2.0)) and cycles <= PIXELS / 4 and LOWEST <= f * 1.0001 and f <= HIGHEST * 1.0001:
            out.append((f, "on" if half % 2 == 0 else "between"))
    return out


def conditions():
    """Every (f, size, placement, angle, eccentricity, speed) of the suite, in table order."""
    return [(f, size, place, angle, e, v) for size in SIZES for f, place in carriers(size) for angle in ANGLES
            for e in ECCENTRICITIES for v in SPEEDS]


def gabor(f_cpd, size_deg, contrast, angle=0.0, pixels=PIXELS):
    """(patch, background) images: the patch's window of size_deg spans the image; the carrier's
    frequency vector at `angle` [deg] from image +x towards up (0: vertical bars)."""
    x = (np.arange(pixels) + 0.5) / pixels - 0.5  # [diameters]
    xx, yy = np.meshgrid(x * size_deg, x * size_deg)  # [deg]; yy grows downwards (row 0 at the top)
    sigma = size_deg / 6.0
    envelope = np.exp(-(xx ** 2 + yy ** 2) / (2 * sigma ** 2))
    a = math.radians(angle)
    carrier = np.cos(2 * np.pi * f_cpd * (xx * math.cos(a) - yy * math.sin(a)))
    patch = BACKGROUND * (1.0 + contrast * envelope * carrier)
    return patch.astype(np.float32), np.full((pixels, pixels), BACKGROUND, np.float32)


def true_threshold(f, sigma, e_near, v):
    """stelaCSF's threshold contrast of the Gabor patch: the more sensitive of the temporal and nasal meridians."""
    s = max(float(acuity.models.stela_csf(f, f * v, LUMINANCE, math.pi * sigma ** 2, e_near, vf)) for vf in (0.0, 180.0))
    return 1.0 / s if s > 0 else math.inf


def one_view_profile(lost, bands, radius, detail=None):
    """A two-level profile of one view looking from +Z: level 1 loses `lost` ([orientations, bands]);
    detail: (area, offset, turn) for its Detail section, or None for none."""
    t, b = lost.shape
    extra = {} if detail is None else {"detail_area": detail[0].reshape(1, 1, t, b),
                                       "detail_offset": detail[1].reshape(1, 1, t, b),
                                       "detail_turn": detail[2].reshape(1, 1, t, b)}
    return acuity.Profile.from_bytes(acuity.spectra.encode_profile(
        sphere=[0, 0, 0, radius], triangles=[2000, 1000], geometric_error=[0.0, 0.001],
        view_directions=np.array([[0, 0, 1]], np.float32),
        orientations=np.arange(t) * 180.0 / t, bands=np.asarray(bands, np.float32),
        lost=lost.reshape(1, 1, t, b), features=np.zeros((2, 1, t), np.float32), snapshot_pixels=PIXELS, **extra))


MODEL = "stela-csf"  # the rule's threshold model (--model)


def chain_config(evaluation, params=None):
    config = acuity.SchedulerConfig()
    config.max_objects = 4
    config.max_profiles = 4
    config.model = MODEL
    config.evaluation = evaluation
    p = params or acuity.models.ModelParams()
    p.luminance = LUMINANCE
    config.params = p
    config.quality = 1.0
    config.gaze_uncertainty_deg = 0.0
    config.keep_scores = True
    return config


def radius_for(size_deg):
    """Sphere radius [m] at DISTANCE whose angular diameter (2 asin(r / d)) is size_deg."""
    return DISTANCE * math.sin(math.radians(size_deg / 2))


def score(lost, bands, size_deg, e_centre, v, evaluation, params=None, detail=None, angle=0.0):
    """The chain's level-1 score and explain() of a patch whose loss is `lost` (and `detail`), seen at
    e_centre [deg] from the gaze, drifting at v [deg/s] on the retina across its bars (along `angle`
    from image +x towards up: the view from +Z has world +X right and +Y up)."""
    s = acuity.Scheduler(chain_config(evaluation, params))
    radius = radius_for(size_deg)
    pid = s.add_profile(one_view_profile(lost, bands, radius, detail))
    ids = s.add_objects(np.array([pid]), np.array([[0.0, 0.0, -DISTANCE]]), np.array([[0, 0, 0, 1]], np.float32),
                        np.array([1.0]))
    speed = DISTANCE * math.radians(v)  # [m/s] across the line of sight
    a = math.radians(angle)
    s.set_velocities(ids, np.array([[speed * math.cos(a), speed * math.sin(a), 0.0]]))
    eye = acuity.Eye()
    half = math.degrees(math.atan(1.0))  # 45 deg half-angles; the viewport sets the pixels per degree
    eye.fov_deg = [-half, half, half, -half]
    px = int(round(2 * math.tan(math.radians(half)) * PX_PER_DEG * 180 / math.pi))
    eye.viewport = [px, px]
    g = acuity.Gaze()
    g.valid = True
    g.confidence = 1.0
    g.direction = [math.sin(math.radians(e_centre)), 0.0, -math.cos(math.radians(e_centre))]
    g.has_velocity = True  # the eye holds still: the retinal drift is the patch's own
    frame = acuity.Frame()
    frame.eyes = [eye]
    frame.gaze = [g]
    frame.dt = 1 / 90
    s.run_frame(frame)
    return float(s.scores(int(ids[0]))[1]), s.explain(int(ids[0]))


def measure(f, size_deg, e_centre, v, contrast=None, params=None, evaluations=("exact", "tabulated"), detail=True,
            angle=0.0):
    """One condition through the chain: dict with the true threshold, the contrast shown and each path's
    score. detail=False leaves the profile's Detail section out (the chain before issue 47's fix)."""
    sigma = size_deg / 6.0
    e_near = max(0.0, e_centre - size_deg / 2)
    ct = true_threshold(f, sigma, e_near, v)
    c = ct if contrast is None else contrast
    out = {"f": f, "size": size_deg, "angle": angle, "e_centre": e_centre, "e_near": e_near, "v": v, "threshold": ct,
           "contrast": c}
    if contrast is None and not ct <= 1.0:
        return out  # no contrast shows it
    patch, background = gabor(f, size_deg, c, angle)
    lost, bands, area, offset, turn = acuity.spectra.lost_contrast(patch, background, orientations=ORIENTATIONS,
                                                                   with_detail=True)
    for ev in evaluations:
        sc, ex = score(lost, bands, size_deg, e_centre, v, getattr(acuity.Evaluation, ev), params,
                       (area, offset, turn) if detail else None, angle)
        out[ev] = sc
        out[ev + "_explain"] = ex
    return out


def statistics(scores):
    s = np.array([x for x in scores if x is not None])
    if s.size == 0:
        return "no conditions"
    inside = np.count_nonzero((s >= 0.7) & (s <= 1.4))
    return (f"{s.size} conditions: geometric mean {math.exp(np.mean(np.log(s))):.2f}, range {s.min():.2f}-{s.max():.2f}, "
            f"within 0.7-1.4: {inside} ({100.0 * inside / s.size:.0f}%), below 0.5: {np.count_nonzero(s < 0.5)}, "
            f"above 1.4: {np.count_nonzero(s > 1.4)}")


def table(results):
    cols = [(e, v) for e in ECCENTRICITIES for v in SPEEDS]
    lines = ["| f [cpd] | D [deg] | band | orientation | " + " | ".join(f"e {e:g}, v {v:g}" for e, v in cols) + " |",
             "|---|---|---|---|" + "---|" * len(cols)]
    rows = {}
    for r in results:
        rows.setdefault((r["size"], r["f"], r["angle"]), {})[(r["e_centre"], r["v"])] = r
    for (size, f, angle), cells in rows.items():
        place = "on" if abs(math.log2(f * size) - round(math.log2(f * size))) < 1e-6 else "between"
        text = []
        for key in cols:
            r = cells.get(key, {})
            if "exact" not in r:
                text.append("-")
            elif abs(r["exact"] - r["tabulated"]) <= 0.005 * r["exact"]:
                text.append(f"{r['exact']:.2f}")
            else:
                text.append(f"{r['exact']:.2f} / {r['tabulated']:.2f}")
        turn = "on" if angle == 0 else f"between ({angle:g} deg)"
        lines.append(f"| {f:.3g} | {size:g} | {place} | {turn} | " + " | ".join(text) + " |")
    return "\n".join(lines)


def main():
    global MODEL
    p = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    p.add_argument("--csv", action="store_true", help="one line per condition instead of the table")
    p.add_argument("--model", default=MODEL,
                   help="the rule's threshold model (default: stela-csf, the one calibrated here; 'default' "
                        "shows how the default chain reads the same patches)")
    a = p.parse_args()
    MODEL = a.model
    results = [measure(f, size, e, v, angle=angle) for f, size, _, angle, e, v in conditions()]
    if a.csv:
        print("f_cpd,size_deg,angle_deg,e_centre_deg,e_near_deg,v_deg_s,threshold,exact,tabulated,limiting_cpd")
        for r in results:
            lim = r["exact_explain"]["levels"][1]["frequency_cpd"] if "exact" in r else math.nan
            print(f"{r['f']:.4g},{r['size']:g},{r['angle']:g},{r['e_centre']:g},{r['e_near']:g},{r['v']:g},{r['threshold']:.5g},"
                  f"{r.get('exact', math.nan):.4g},{r.get('tabulated', math.nan):.4g},{lim:.4g}")
        return
    shown = [r for r in results if "exact" in r]
    print(f"Gabor patches at stelaCSF's threshold contrast (50 cd/m^2, area pi sigma^2, the nearest point's "
          f"eccentricity), level 1's score through lost_contrast -> one-view profile -> perceptual rule "
          f"({MODEL}, q = 1, gaze uncertainty 0, {PX_PER_DEG:g} px/deg). Columns: e = the gaze's angle to the "
          f"patch's centre [deg], v = drift across the bars [deg/s]; a cell holds the exact path's score, and "
          f"the tabulated path's after a slash where they differ by more than 0.5%; - : threshold contrast above 1. "
          f"Band and orientation: where the carrier lies among the analysis bands and orientations.")
    print()
    print(table(results))
    print()
    print(f"- exact: {statistics([r['exact'] for r in shown])}")
    print(f"- tabulated: {statistics([r['tabulated'] for r in shown])}")
    print(f"- exact, the patches of at least 2/3 cycle per sigma (f D >= 4): "
          f"{statistics([r['exact'] for r in shown if r['f'] * r['size'] >= MIN_CYCLES * 0.9999])}")
    before = [measure(r["f"], r["size"], r["e_centre"], r["v"], evaluations=("exact",), detail=False,
                      angle=r["angle"])["exact"] for r in shown]
    print(f"- exact, the profile without its Detail section (band centres, unbounded area: the chain before "
          f"issue 47's fix): {statistics(before)}")


if __name__ == "__main__":
    sys.exit(main())
