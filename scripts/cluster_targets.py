#!/usr/bin/python3
"""Issue 48's targets for cluster cuts, measured and judged: docs/lodgen.md's figure `cluster-targets`.

  PYTHONPATH=build/python /usr/bin/python3 scripts/cluster_targets.py build [--views 200] [--mesh armadillo.off]

Makes (once; cached in BUILD/cluster-targets/MESH) `acuity lodgen MESH --clusters` and `acuity profile` of
it with 42 directions per group, then prints, for the cut with the loss per view cell
(the profile's ClusterViews section, read here whatever the directions: acuity.clusters.load(...,
view_cells=True)) and for the cut with each group's loss over
all views (as before the cells; `acuity.clusters.load(..., view_cells=False)`):
  - the share of the finest triangles a 30-degree object draws with the gaze on its centre, q = 1 (and
    at the --lenient qualities, whose cuts are judged at q = 1: whether what the loss forbids is seen);
  - how many times more triangles each half of a 40-degree object holds with the gaze on its edge than
    with the gaze on the other edge;
  - the judge: random still views (the object turned at random, 10-40 degrees across, the gaze within
    20 degrees of its centre, q = 1), the cut rendered against the finest mesh by the snapshot renderer
    (orthographic, framed by the object's sphere, at least 2 pixels per display pixel at its distance,
    at most 1024 across: above 30 degrees its finest band, 256 cycles per diameter, stops short of the
    display's Nyquist frequency, 8.4 cpd) and the lost contrast mapped over the image by the profiles' analyser
    (acuity.spectra.lost_contrast_maps); each map sample scored against the threshold of the model the
    cut took (--model; Default by default) at that band's frequency [cpd] (an object diameter at its sphere's nearest point, as the object rule
    and its judge take it) and the sample's own eccentricity from the gaze (less the rule's 1 degree of gaze
    uncertainty), bands above the display's Nyquist frequency there not counted; a view is invisible when
    no sample exceeds 1 threshold.
The eye: at the origin looking down -Z, 90 degrees of field of view over 1920 px (the acuity.Eye default).
Deterministic for a seed; runs programs with argument vectors, never a shell.
"""
import argparse
import math
import os
import subprocess
import sys
import time

import numpy as np

import acuity

FOCAL_PX = 960.0  # 1920 px over 90 degrees
UNCERTAINTY_DEG = 1.0  # SchedulerConfig::gaze_uncertainty_deg
GROUP_VIEWS = 42  # directions per group (cells read with view_cells=True: from 42 they are not quite a bound)
MAX_PIXELS = 1024  # the judge's images at most this many pixels across (bands up to 256 cycles per diameter)


def run(argv):
    r = subprocess.run([str(a) for a in argv], capture_output=True, text=True)
    if r.returncode != 0:
        sys.exit(f"{' '.join(map(str, argv))} failed:\n{r.stderr}")
    return r.stdout


def files(build, mesh, work):
    """The hierarchy and its profile, made once."""
    os.makedirs(work, exist_ok=True)
    tool = os.path.join(build, "tools", "acuity")
    src = os.path.join(build, "cgal-data", "data", "meshes", mesh)
    glb, prof = os.path.join(work, "c.glb"), os.path.join(work, "c.acuity")
    seconds = None
    if not os.path.exists(prof):
        t = time.time()
        run([tool, "lodgen", src, "--clusters", "-o", glb, "-q"])
        run([tool, "profile", glb, "-o", prof, "--group-views", str(GROUP_VIEWS), "--view-cells"])
        seconds = time.time() - t
    return glb, prof, seconds


def quat_matrix(q):
    x, y, z, w = q
    return np.array([[1 - 2 * (y * y + z * z), 2 * (x * y - z * w), 2 * (x * z + y * w)],
                     [2 * (x * y + z * w), 1 - 2 * (x * x + z * z), 2 * (y * z - x * w)],
                     [2 * (x * z - y * w), 2 * (y * z + x * w), 1 - 2 * (x * x + y * y)]])


def gaze_towards(d):
    g = acuity.Gaze()
    d = np.asarray(d, float) / np.linalg.norm(d)
    g.direction = tuple(float(x) for x in d)
    g.valid = True
    return g


def placed(sphere, span_deg, rotation=np.eye(3), direction=(0.0, 0.0, -1.0)):
    """The object's position [m] putting its sphere's centre along `direction` from the eye at the
    distance where it spans span_deg; returns (position, centre, distance)."""
    r = sphere[3]
    d = r / math.sin(math.radians(span_deg / 2))
    centre = d * np.asarray(direction, float) / np.linalg.norm(direction)
    return tuple(centre - rotation @ np.asarray(sphere[:3], float)), centre, d


def halves(cut, pos):
    x = cut.positions[cut.indices].mean(axis=1)[:, 0] + pos[0]
    left = int(np.count_nonzero(x < 0))
    return left, len(x) - left


def targets(h, sphere, model, q=1.0):
    eye = acuity.Eye()
    pos, _, _ = placed(sphere, 30)
    centre = h.select(eye, gaze_towards((0, 0, -1)), pos, (0, 0, 0, 1), quality=q, model=model)
    pos, _, _ = placed(sphere, 40)
    edge = math.tan(math.radians(20))
    on_left = h.select(eye, gaze_towards((-edge, 0, -1)), pos, (0, 0, 0, 1), quality=q, model=model)
    on_right = h.select(eye, gaze_towards((edge, 0, -1)), pos, (0, 0, 0, 1), quality=q, model=model)
    l_left, r_left = halves(on_left, pos)
    l_right, r_right = halves(on_right, pos)
    return centre.triangles / h.finest_triangles, l_left / max(l_right, 1), r_right / max(r_left, 1)


def make_view_axes(d):
    """render_snapshot's image axes for direction d (object to camera): make_view's canonical up (the
    object's +Y made orthogonal to d, or +Z when looking along Y) and right = -d x up."""
    up = np.array([0.0, 1.0, 0.0])
    if abs(d[1]) > 0.999:
        up = np.array([0.0, 0.0, 1.0])
    up = up - np.dot(up, d) * d
    up /= np.linalg.norm(up)
    return -np.cross(d, up), up


def judge(h, sphere, finest, rng, count, model, q=1.0):
    """Random still views of the cuts at quality q, each scored at q = 1; returns (scores, drawn shares,
    spans)."""
    eye = acuity.Eye()
    nyquist_axis = 0.5 * FOCAL_PX * math.pi / 180  # cpd on the view axis
    scores, shares, spans = [], [], []
    for _ in range(count):
        span = rng.uniform(10, 40)
        q_rot = rng.normal(size=4)
        q_rot /= np.linalg.norm(q_rot)
        rot = quat_matrix(q_rot)
        # The object's centre somewhere in the central field, the gaze within 20 degrees of it.
        axis = np.array([rng.uniform(-0.3, 0.3), rng.uniform(-0.3, 0.3), -1.0])
        axis /= np.linalg.norm(axis)
        pos, centre, dist = placed(sphere, span, rot, axis)
        off = math.radians(20) * math.sqrt(rng.uniform())
        a = rng.uniform(0, 2 * math.pi)
        t1 = np.cross(axis, [0.0, 1.0, 0.0])
        t1 /= np.linalg.norm(t1)
        t2 = np.cross(axis, t1)
        gaze = math.cos(off) * axis + math.sin(off) * (math.cos(a) * t1 + math.sin(a) * t2)
        cut = h.select(eye, gaze_towards(gaze), pos, tuple(q_rot), quality=q, model=model)
        shares.append(cut.triangles / h.finest_triangles)
        spans.append(span)
        if cut.triangles == h.finest_triangles:
            scores.append(0.0)
            continue
        # The view from the object towards the eye, in object space.
        d = rot.T @ (-centre) / dist
        px = 64
        while px < MAX_PIXELS and px < 2 * span * FOCAL_PX * math.pi / 180:
            px *= 2
        kw = dict(direction=tuple(d), normals=finest.normals if len(finest.normals) else None, pixels=px,
                  supersample=2)
        ref = acuity.spectra.render(finest.positions, finest.indices, **kw)
        img = acuity.spectra.render(cut.positions, cut.indices, **kw)
        if np.array_equal(ref, img):
            scores.append(0.0)
            continue
        maps, bands = acuity.spectra.lost_contrast_maps(img, ref)
        right, up = make_view_axes(d)
        right_w, up_w = rot @ right, rot @ up
        r = sphere[3]
        nearest = dist - r
        diameter_deg = math.degrees(2 * r / nearest)
        worst = 0.0
        for m, f in zip(maps, bands):
            n = m.shape[1]
            s = px / n
            coords = ((np.arange(n) * s + 0.5) / px) * 2 - 1  # image x (columns) and y (rows, downwards)
            x = coords[None, :]
            y = -coords[:, None]
            p = centre[None, None, :] + r * (x[..., None] * right_w + y[..., None] * up_w)
            u = p / np.linalg.norm(p, axis=-1, keepdims=True)
            e = np.degrees(np.arccos(np.clip(u @ gaze, -1, 1)))
            e = np.maximum(e - UNCERTAINTY_DEG, 0)
            off_axis = np.arccos(np.clip(-u[..., 2], -1, 1))
            f_cpd = f / diameter_deg
            visible = f_cpd <= nyquist_axis / np.cos(off_axis) ** 2
            ct = acuity.models.threshold(np.full(e.shape, f_cpd), e, np.zeros(e.shape), model=model)
            ratio = m.max(axis=0) / ct
            worst = max(worst, float(np.max(np.where(visible, ratio, 0))))
        scores.append(worst)
    return np.array(scores), np.array(shares), np.array(spans)


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("build")
    ap.add_argument("--mesh", default="armadillo.off")
    ap.add_argument("--views", type=int, default=200, help="random still views judged")
    ap.add_argument("--seed", type=int, default=48)
    ap.add_argument("--model", default="default", help="threshold model of the cut and of the judge")
    ap.add_argument("--lenient", type=float, nargs="*", default=[4.0, 16.0],
                    help="also the cuts at these qualities q > 1, judged at q = 1: is what the loss forbids visible?")
    args = ap.parse_args()
    work = os.path.join(args.build, "cluster-targets", os.path.splitext(args.mesh)[0])
    glb, prof, seconds = files(args.build, args.mesh, work)
    sphere = acuity.Profile.load(prof).sphere
    cells = acuity.clusters.load(glb, prof, view_cells=True)  # whatever directions measured them
    whole = acuity.clusters.load(glb, prof, view_cells=False)
    finest = cells.finest()
    print(f"{args.mesh}: {cells.finest_triangles} triangles, {cells.cluster_count} clusters, {cells.group_count} "
          f"groups, loss in {len(cells.view_directions)} view cells x {len(cells.bands)} bands; model {args.model}, q = 1"
          + (f" (lodgen + profile {seconds:.0f} s)" if seconds else ""))
    print()
    print("| the cut reads each group's loss | 30 deg, gaze on the centre: share of the finest triangles "
          "| 40 deg, gaze on one edge vs the other: that half | judged invisible (still views) "
          "| worst score | share drawn over the judged views (mean) |")
    print("|---|---|---|---|---|---|")
    rows = [("over all views (before)", whole, 1.0), ("per view cell", cells, 1.0)]
    rows += [(f"per view cell, q = {q:g} (judged at q = 1)", cells, q) for q in args.lenient]
    for name, h, q in rows:
        share, left, right = targets(h, sphere, args.model, q)
        rng = np.random.default_rng(args.seed)
        scores, shares, _ = judge(h, sphere, finest, rng, args.views, args.model, q)
        print(f"| {name} | {share:.3f} | x{left:.2f} left, x{right:.2f} right "
              f"| {np.count_nonzero(scores <= 1)} of {len(scores)} ({np.mean(scores <= 1):.1%}) "
              f"| {scores.max():.2f} | {shares.mean():.3f} |")
    print("\nissue 48's targets: <= 0.5; >= x2 each; >= 97.5%")


if __name__ == "__main__":
    main()
