"""acuity.clusters (issue 48 item 5): a hierarchy from `acuity lodgen --clusters` and its profile
(`acuity profile` of the same glb: each group's loss measured, issue 48 item 2), or the fallback, the
profile of a chain of the same mesh; its cuts follow the gaze. Measured here (printed with -s, not asserted beyond
"some saving"): the fraction of the finest triangles drawn with the gaze on the centre of an object
spanning 30 degrees at q = 1, and how many times more triangles each half of a 40-degree object holds
with the gaze on its edge than with the gaze on the other edge."""
import json
import math
import os
import subprocess

import numpy as np
import pytest

import acuity

ACUITY = os.environ.get("ACUITY_BIN", "")
MESHES = os.environ.get("ACUITY_MESH_DIR", "")
HERE = os.path.dirname(os.path.abspath(__file__))


def run(*args):
    assert os.path.exists(ACUITY), "ACUITY_BIN must name the built acuity command (ctest sets it)"
    r = subprocess.run([ACUITY, *map(str, args)], capture_output=True, text=True, timeout=900)
    assert r.returncode == 0, r.stderr
    return r


@pytest.fixture(scope="module")
def armadillo(tmp_path_factory):
    """A closed mesh's hierarchy, its measured profile and the profile of its chain, as the commands
    make them: elephant.off (5.6k triangles) with quick profiles (64 px; 6 views of level 0, 64 px
    windows and 12 directions per group), or, when ACUITY_CLUSTER_FILES names a folder, its c.glb,
    c.acuity, chain.glb and chain.acuity (docs/lodgen.md measures armadillo.off so)."""
    given = os.environ.get("ACUITY_CLUSTER_FILES", "")
    if given:
        return {"glb": os.path.join(given, "c.glb"), "measured": os.path.join(given, "c.acuity"),
                "chain": os.path.join(given, "chain.glb"), "profile": os.path.join(given, "chain.acuity")}
    d = tmp_path_factory.mktemp("clusters")
    mesh = os.path.join(MESHES, "elephant.off")
    run("lodgen", mesh, "--clusters", "-o", d / "c.glb", "-q")
    run("profile", d / "c.glb", "-o", d / "c.acuity", "--res", "64", "--views", "6", "--window-pixels", "64",
        "--group-views", "12", "--view-cells")
    run("lodgen", mesh, "-o", d / "chain.glb", "-q")
    run("profile", d / "chain.glb", "-o", d / "chain.acuity", "--res", "64", "--views", "6")
    return {"glb": d / "c.glb", "measured": d / "c.acuity", "chain": d / "chain.glb",
            "profile": d / "chain.acuity"}


def load(a):
    """The hierarchy with its measured loss (the profile of the glb itself)."""
    h = acuity.clusters.load(str(a["glb"]), str(a["measured"]))
    assert h.measured
    return h


def placed(a, span_deg):
    """The eye at the origin looking down -Z; the object's sphere centred on the axis, spanning span_deg.
    Returns (eye, position, radius): the object's position that puts its sphere centre there."""
    sphere = acuity.Profile.load(str(a["profile"])).sphere
    r = sphere[3]
    d = r / math.sin(math.radians(span_deg / 2))
    eye = acuity.Eye()
    return eye, (-sphere[0], -sphere[1], -sphere[2] - d), r, d


def gaze_towards(x, z):
    g = acuity.Gaze()
    n = math.hypot(x, z)
    g.direction = (x / n, 0.0, z / n)
    g.valid = True
    return g


def test_load_finest_and_the_cut_arrays(armadillo):
    h = load(armadillo)
    f = h.finest()
    assert f.positions.dtype == np.float32 and f.positions.ndim == 2 and f.positions.shape[1] == 3
    assert f.indices.dtype == np.uint32 and f.indices.shape == (h.finest_triangles, 3)
    assert f.indices.max() < f.positions.shape[0]
    assert f.clusters.dtype == np.uint32 and f.triangles == h.finest_triangles
    assert h.loss.shape == (h.group_count, len(h.bands)) and np.all(np.isfinite(h.loss)) and np.all(h.loss >= 0)
    assert np.all(np.diff(h.bands) > 0) and h.loss.max() > 0
    assert f.normals.dtype == np.float32 and f.normals.shape == f.positions.shape
    # The loss per view cell (the profile's ClusterViews section): measured from 12 directions here, so
    # not read by default (kMinCellSamples: 162); view_cells=True reads its 12 cells, each at most the
    # loss over all views, which is their largest.
    assert h.view_directions.shape == (0, 3)
    cells = acuity.clusters.load(str(armadillo["glb"]), str(armadillo["measured"]), view_cells=True)
    assert cells.view_directions.shape == (12, 3)
    assert np.allclose(np.linalg.norm(cells.view_directions, axis=1), 1, atol=1e-5)
    assert cells.view_loss.shape == (h.group_count, 12, len(h.bands))
    assert np.all(cells.view_loss <= h.loss[:, None, :]) and np.array_equal(cells.view_loss.max(axis=1), h.loss)
    # `acuity inspect` shows the section: per band the largest loss over groups.
    shown = json.loads(run("inspect", armadillo["measured"], "--json").stdout)["clusters"]
    assert shown["groups"] == h.group_count and shown["bands_cpod"] == pytest.approx(h.bands.tolist())
    assert shown["max_lost_contrast_per_band"] == pytest.approx(h.loss.max(axis=0).tolist())
    eye, pos, _, _ = placed(armadillo, 30)
    cut = h.select(eye, gaze_towards(0, -1), pos, (0, 0, 0, 1))
    assert cut.indices.shape == (cut.triangles, 3) and len(cut.clusters) > 0
    assert 0 < cut.groups_evaluated <= h.group_count
    # The cut's triangles are its clusters' (each cluster's triangles once).
    assert len(set(cut.clusters.tolist())) == len(cut.clusters)


def test_the_fallback_a_chain_profile(armadillo):
    """Without a measured profile, the chain profile's loss is derived per group (provisional_group_loss):
    coarser groups lose no less in any band than the groups that made their members (it grows with
    error, and errors grow up the hierarchy): the last group is a top one."""
    h = acuity.clusters.load(str(armadillo["glb"]), str(armadillo["profile"]))
    assert not h.measured
    assert h.loss.shape[0] == h.group_count and np.all(h.loss >= 0) and np.all(h.loss <= 1)
    assert np.all(h.loss[-1] >= h.loss.min(axis=0))
    eye, pos, _, _ = placed(armadillo, 30)
    assert h.select(eye, gaze_towards(0, -1), pos, (0, 0, 0, 1)).triangles > 0


def test_bad_input_is_a_clear_error(armadillo):
    with pytest.raises(ValueError, match="no mesh with a cluster hierarchy"):
        acuity.clusters.load(str(armadillo["chain"]), str(armadillo["profile"]))
    with pytest.raises(ValueError, match="profile a chain of the same mesh"):
        acuity.clusters.load(str(armadillo["glb"]), os.path.join(HERE, "..", "data", "profile_v1.acuity"))
    other = os.path.join(HERE, "..", "fuzz", "corpus", "profile", "clusters.acuity")  # another hierarchy's
    with pytest.raises(ValueError, match="measured another hierarchy"):
        acuity.clusters.load(str(armadillo["glb"]), other)
    h = load(armadillo)
    eye, pos, _, _ = placed(armadillo, 30)
    g = gaze_towards(0, -1)
    with pytest.raises(ValueError, match="invalid input"):
        h.select(eye, g, (math.nan, 0, 0), (0, 0, 0, 1))
    with pytest.raises(ValueError, match="invalid input"):
        h.select(eye, g, pos, (0, 0, 0, 1), scale=0.0)
    with pytest.raises(ValueError, match="invalid input"):
        h.select(eye, g, pos, (0, 0, 0.5, 0.5))
    with pytest.raises(ValueError, match="quality"):
        h.select(eye, g, pos, (0, 0, 0, 1), quality=0.0)


def test_gaze_on_the_centre_of_a_30_degree_object(armadillo):
    """The issue's target: <= 0.5 of the finest triangles at q = 1 (reported, not asserted: with the
    measured loss, as with the provisional one, it is not met, docs/lodgen.md). Asserted: q orders
    the cuts."""
    h = load(armadillo)
    eye, pos, _, _ = placed(armadillo, 30)
    cut = h.select(eye, gaze_towards(0, -1), pos, (0, 0, 0, 1), quality=1.0)
    fraction = cut.triangles / h.finest_triangles
    print(f"\n30 deg, gaze on the centre, q = 1: {cut.triangles} of {h.finest_triangles} finest triangles "
          f"= {fraction:.3f}; {cut.groups_evaluated} of {h.group_count} groups evaluated")
    # A more lenient q never draws more; a stricter one never fewer; a very lenient one draws less.
    assert h.select(eye, gaze_towards(0, -1), pos, (0, 0, 0, 1), quality=2.0).triangles <= cut.triangles
    assert h.select(eye, gaze_towards(0, -1), pos, (0, 0, 0, 1), quality=0.5).triangles >= cut.triangles
    assert h.select(eye, gaze_towards(0, -1), pos, (0, 0, 0, 1), quality=1000.0).triangles < h.finest_triangles


def test_the_gaze_away_draws_less(armadillo):
    """An object spanning 2 degrees draws fewer triangles with the gaze 30 degrees away than on it, and
    no more with the gaze farther still."""
    h = load(armadillo)
    eye, pos, _, _ = placed(armadillo, 2)
    on = h.select(eye, gaze_towards(0, -1), pos, (0, 0, 0, 1)).triangles
    away = h.select(eye, gaze_towards(math.tan(math.radians(30)), -1), pos, (0, 0, 0, 1)).triangles
    farther = h.select(eye, gaze_towards(math.tan(math.radians(40)), -1), pos, (0, 0, 0, 1)).triangles
    print(f"\n2 deg, q = 1: gaze on it {on / h.finest_triangles:.3f} of the finest triangles, 30 deg away "
          f"{away / h.finest_triangles:.3f}, 40 deg away {farther / h.finest_triangles:.3f}")
    assert away < on and farther <= away


def halves(cut, pos):
    """Triangles of the cut whose centroid lies left (x < the sphere centre) and right, in world x."""
    centroid_x = cut.positions[cut.indices].mean(axis=1)[:, 0] + pos[0]
    left = int(np.count_nonzero(centroid_x < 0))
    return left, len(centroid_x) - left


def test_gaze_on_one_edge_of_a_40_degree_object(armadillo):
    """The issue's target: each half holds >= 2x the triangles with the gaze on its edge than with the
    gaze on the other edge (reported, not asserted: not met with the measured loss either). Asserted: a
    half never holds fewer with the gaze on its own edge."""
    h = load(armadillo)
    eye, pos, r, d = placed(armadillo, 40)
    edge = math.tan(math.radians(20))  # the sphere's silhouette, 20 degrees either side
    for q in (1.0, 16.0):
        on_left = h.select(eye, gaze_towards(-edge, -1), pos, (0, 0, 0, 1), quality=q)
        on_right = h.select(eye, gaze_towards(edge, -1), pos, (0, 0, 0, 1), quality=q)
        l_left, r_left = halves(on_left, pos)
        l_right, r_right = halves(on_right, pos)
        print(f"\n40 deg, q = {q}: gaze on the left edge draws {on_left.triangles} (left half {l_left}, right "
              f"{r_left}); on the right edge {on_right.triangles} (left {l_right}, right {r_right}); left half "
              f"x{l_left / max(l_right, 1):.2f}, right half x{r_right / max(r_left, 1):.2f}")
        assert l_left >= l_right and r_right >= r_left


def test_explain_names_each_groups_limit(armadillo):
    """h.explain: per group the score over the eyes and bands, its limiting band, and whether select()
    refines it; a refined group's own test says visible (score > 1)."""
    h = load(armadillo)
    eye, pos, _, _ = placed(armadillo, 30)
    g = gaze_towards(0, -1)
    x = h.explain(eye, g, pos, (0, 0, 0, 1))
    for key in ("score", "band", "eye", "flags", "visible", "frequency_cpd", "threshold", "distance_m",
                "eccentricity_deg"):
        assert x[key].shape == (h.group_count,), key
    assert np.all(x["band"] < len(h.bands)) and np.all(x["threshold"] > 0)
    refined = x["visible"] == 1
    assert refined.any() and np.all(x["score"][refined] > 1)
    cut = h.select(eye, g, pos, (0, 0, 0, 1))
    assert (cut.triangles < h.finest_triangles) == (not refined.all())


def test_memory_holds_a_group_before_it_coarsens(armadillo):
    """select(memory=h.new_memory(), dt=..., hysteresis_seconds=...): each group refines at once and
    coarsens only after the hysteresis, as an object would; without memory it coarsens at once."""
    h = load(armadillo)
    m = h.new_memory()
    assert m.dtype == np.uint8 and m.size == 12 * h.group_count and not m.any()
    g = gaze_towards(0, -1)
    eye, near, _, _ = placed(armadillo, 30)
    _, far, _, _ = placed(armadillo, 2)
    hold = dict(memory=m, dt=1 / 60, hysteresis_seconds=0.5)
    first = h.select(eye, g, near, (0, 0, 0, 1), **hold)
    assert m.any() and first.triangles == h.select(eye, g, near, (0, 0, 0, 1)).triangles
    away = gaze_towards(math.tan(math.radians(30)), -1)  # the 2-degree object 30 degrees from the gaze
    free = h.select(eye, away, far, (0, 0, 0, 1))
    held = h.select(eye, away, far, (0, 0, 0, 1), **hold)
    assert free.triangles < first.triangles and held.triangles == first.triangles
    for _ in range(20):  # 0.35 s in all: still held
        later = h.select(eye, away, far, (0, 0, 0, 1), **hold)
    assert later.triangles == first.triangles
    for _ in range(40):  # 1 s in all: past the hysteresis
        later = h.select(eye, away, far, (0, 0, 0, 1), **hold)
    assert later.triangles == free.triangles
    with pytest.raises(ValueError, match="memory"):
        h.select(eye, away, far, (0, 0, 0, 1), memory=np.zeros(3, np.uint8))


def open_edges(cut):
    """The edges of the cut's triangles used once, between welded positions (exact)."""
    _, weld = np.unique(cut.positions, axis=0, return_inverse=True)
    t = weld.reshape(-1)[cut.indices]
    e = np.sort(np.concatenate([t[:, [0, 1]], t[:, [1, 2]], t[:, [2, 0]]]), axis=1)
    edges, counts = np.unique(e, axis=0, return_counts=True)
    return {tuple(x) for x in edges[counts == 1]}


def test_triangle_budget_coarsens_the_cut_to_fit(armadillo):
    """select(..., triangle_budget=N): a budget at or above the cut changes nothing; below it the cut
    draws at most N (the roots allow it here: no eye inside a group), opens no edge the finest mesh
    lacks, and counts what it coarsened past visibility; a smaller budget never draws more."""
    h = load(armadillo)
    eye, pos, _, _ = placed(armadillo, 30)
    g = gaze_towards(0, -1)
    cut = h.select(eye, g, pos, (0, 0, 0, 1))
    same = h.select(eye, g, pos, (0, 0, 0, 1), triangle_budget=cut.triangles)
    assert same.triangles == cut.triangles and same.budget_coarsened == 0
    assert np.array_equal(same.clusters, cut.clusters)
    finest_open = open_edges(h.finest())
    drawn = []
    for fraction in (0.8, 0.5, 0.25):
        budget = int(cut.triangles * fraction)
        b = h.select(eye, g, pos, (0, 0, 0, 1), triangle_budget=budget)
        assert b.triangles <= budget and b.budget_coarsened > 0
        assert b.budget_forced > 0 and b.flags & acuity.FLAG_BUDGET_FORCED
        assert open_edges(b) <= finest_open
        drawn.append(b.triangles)
    print(f"\n30 deg, gaze on the centre: the perceptual cut {cut.triangles}; budgets of 0.8, 0.5, 0.25 "
          f"of it draw {drawn}")
    assert drawn == sorted(drawn, reverse=True)


def test_view_cells_are_written_only_when_asked(armadillo, tmp_path):
    """`acuity profile` of a cluster file measured from fewer than 162 directions per group writes no
    ClusterViews section (the cut would not read it) unless --view-cells asks: the same groups' loss,
    12 x bands x 4 bytes per group fewer (and the section's header)."""
    sizes, loaded = {}, {}
    for name, extra in (("plain", []), ("asked", ["--view-cells"])):
        out = tmp_path / f"{name}.acuity"
        run("profile", armadillo["glb"], "-o", out, "--res", "64", "--views", "6", "--window-pixels", "64",
            "--group-views", "12", *extra)
        sizes[name] = os.path.getsize(out)
        loaded[name] = acuity.clusters.load(str(armadillo["glb"]), str(out), view_cells=True)
    h, asked = loaded["plain"], loaded["asked"]
    assert h.view_directions.shape == (0, 3) and asked.view_directions.shape == (12, 3)
    assert np.array_equal(h.loss, asked.loss)
    saved = sizes["asked"] - sizes["plain"]
    print(f"\nClusterViews at 12 directions: {saved} bytes, {saved / h.group_count:.1f} per group")
    assert saved >= 12 * len(h.bands) * 4 * h.group_count
