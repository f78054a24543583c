"""acuity.sim from Python: the same run as `acuity simulate` (same summary, same files), explain as
`acuity explain`, track tables, and bad options refused by name. acuity.lodgen.build's summary is
the JSON `acuity lodgen` writes."""
import json
import os
import subprocess

import pytest

import acuity

ACUITY = os.environ.get("ACUITY_BIN", "")
MESHES = os.environ.get("ACUITY_MESH_DIR", "")


def cli(*args):
    assert os.path.exists(ACUITY), "ACUITY_BIN must name the built acuity command (ctest sets it)"
    return subprocess.run([ACUITY, *map(str, args)], capture_output=True, text=True, timeout=600)


@pytest.fixture(scope="module")
def scene(tmp_path_factory):
    """A 3-level chain of the elephant, written by acuity.lodgen.build, and a profiles folder."""
    mesh = os.path.join(MESHES, "elephant.off")
    assert os.path.exists(mesh), "ACUITY_MESH_DIR: libcgal-demo meshes needed"
    d = tmp_path_factory.mktemp("sim")
    acuity.lodgen.build(mesh, str(d / "elephant.glb"), levels=3)
    return d


def test_simulate_is_the_commands_run(scene, tmp_path):
    common = dict(seconds=1, seed=3, res=64, validate=6, images=1, profiles=str(scene / "profiles"))
    r = acuity.sim.simulate(str(scene / "elephant.glb"), output=str(tmp_path / "py"), large_object="elephant",
                            **common)
    c = cli("simulate", scene / "elephant.glb", "--seconds", 1, "--seed", 3, "--res", 64, "--validate", 6,
            "--images", 1, "--profiles", scene / "profiles", "--no-plots", "-o", tmp_path / "cli",
            "--large-object", "elephant")
    assert c.returncode == 0, c.stderr
    assert r["summary"] and r["summary"] in c.stdout  # the very text the command prints
    assert r["large_object"]["text"] in c.stdout  # and its large object's block
    assert json.loads(cli("inspect", scene / "profiles" / "elephant-clusters.acuity", "--json").stdout)[
        "snapshot_pixels"] == 64  # made at --res
    assert r["frames"] == 60 and r["objects"] == 1 and r["judged"] == 6
    names = [x["name"] for x in r["rules"] if not x["sweep"]]
    assert names == ["perceptual", "reddy", "distance", "screen-size", "ungated"]
    for rule in r["rules"]:
        assert 0 <= rule["triangles_per_frame"] <= r["all_finest"] + 1e-6
        assert 0 <= rule["visible_losses"] <= r["judged"]
    # Same outputs, byte for byte where deterministic (everything but the timings in summary.json).
    assert {os.path.basename(p) for p in r["written"]} == set(os.listdir(tmp_path / "py"))
    for name in ("frames.csv", "levels.csv", "sweep.csv", "judged.csv", "head.csv", "gaze.csv"):
        assert (tmp_path / "py" / name).read_bytes() == (tmp_path / "cli" / name).read_bytes(), name
    # The frames CSV's triangles agree with the summary's per-frame mean (an independent sum).
    rows = [l.split(",") for l in (tmp_path / "py" / "frames.csv").read_text().splitlines()]
    col = rows[0].index("perceptual")
    perceptual = next(x for x in r["rules"] if x["name"] == "perceptual" and not x["sweep"])
    assert sum(float(row[col]) for row in rows[1:]) / r["frames"] == pytest.approx(
        perceptual["triangles_per_frame"], rel=1e-6)


def test_simulate_large_object(scene):
    """large_object: the asset also drawn large as a cluster hierarchy under the run's gaze (as
    `acuity simulate --large-object`, the same library call; the test above compares their text),
    its profile made at res and cached beside the chain's (made again here: the test above cached it
    at 64). A mesh the scene lacks, or no profiles, is refused."""
    glb, profiles = str(scene / "elephant.glb"), scene / "profiles"
    common = dict(seed=3, validate=0, images=0, res=32, profiles=str(profiles), large_object="elephant")
    r = acuity.sim.simulate(glb, seconds=0.25, **common)
    big = r["large_object"]
    # One object in the scene: its finest triangles are the run's all-finest per frame.
    assert big["asset"] == "elephant" and big["finest"] == r["all_finest"] and big["frames"] == r["frames"] == 15
    assert big["clusters"] > big["groups"] >= 1 and big["bands"] >= 1
    assert [s["deg"] for s in big["spans"]] == [40, 20]
    for span in big["spans"]:
        assert 0 < span["cut"] <= big["finest"] and 0 < span["object_rule"] <= big["finest"]
        frames = [j["frame"] for j in span["judged"]]
        assert frames == sorted(set(frames)) and len(frames) == 10 and frames[-1] < r["frames"]
        for j in span["judged"]:
            assert 0 < j["cut_triangles"] <= big["finest"] and j["cut_score"] >= 0 and j["object_score"] >= 0
    text = big["text"]
    assert text.startswith("\nA large object spanning the gaze") and text not in r["summary"]
    assert f"elephant, {big['finest']} triangles as {big['clusters']} clusters in {big['groups']} groups" in text
    # Its profile is the one made at this res (the scene's profiles' --res), not the default 256.
    c = cli("inspect", profiles / "elephant-clusters.acuity", "--json")
    assert c.returncode == 0, c.stderr
    assert json.loads(c.stdout)["snapshot_pixels"] == 32
    with pytest.raises(RuntimeError, match=r"large_object: the scene has no asset 'nothing' \(it has elephant\)"):
        acuity.sim.simulate(glb, seconds=0.05, **{**common, "large_object": "nothing"})
    with pytest.raises(ValueError, match="large_object needs profiles"):
        acuity.sim.simulate(glb, res=64, seconds=0.05, large_object="elephant")


def test_explain_and_tracks(scene, tmp_path):
    common = dict(seconds=1, seed=3, res=64, profiles=str(scene / "profiles"))
    text = acuity.sim.explain(str(scene / "elephant.glb"), 30, "0", **common)
    c = cli("explain", scene / "elephant.glb", "--seconds", 1, "--seed", 3, "--res", 64, "--profiles",
            scene / "profiles", "--frame", 30, "--object", 0)
    assert c.returncode == 0, c.stderr
    assert text == c.stdout and "chosen: level" in text
    with pytest.raises(RuntimeError, match="nothing"):
        acuity.sim.explain(str(scene / "elephant.glb"), 30, "nothing", **common)
    # A track: read back by name, and a bad one refused naming file and line.
    (tmp_path / "gaze.csv").write_text("t,x,y,z\n0,0,0,-1\n0.5,0.1,0,-1\n")
    t = acuity.sim.read_table(str(tmp_path / "gaze.csv"))
    assert t["columns"] == ["t", "x", "y", "z"] and t["rows"] == [[0, 0, 0, -1], [0.5, 0.1, 0, -1]]
    (tmp_path / "bad.csv").write_text("t,x,y,z\n0,0,nan,-1\n")
    with pytest.raises(RuntimeError, match=r"bad.csv:2: column .y."):
        acuity.sim.read_table(str(tmp_path / "bad.csv"))


def test_bad_options_are_refused_by_name(scene):
    glb = str(scene / "elephant.glb")
    for kw, match in ((dict(seconds=0), "seconds"), (dict(fps=float("nan")), "fps"), (dict(fov=200), "fov"),
                      (dict(viewport=8), "viewport"), (dict(saccade_speed=float("inf")), "saccade"),
                      (dict(evaluation="fast"), "evaluation"),
                      (dict(model="daly"), "model")):
        with pytest.raises(ValueError, match=match):
            acuity.sim.simulate(glb, validate=0, images=0, res=64, **kw)
    with pytest.raises(TypeError, match="colour"):
        acuity.sim.simulate(glb, colour=1)
    with pytest.raises(ValueError, match="no-such"):
        acuity.sim.simulate(str(scene / "no-such.glb"))


def test_lodgen_summary_is_the_commands_json(scene, tmp_path):
    mesh = os.path.join(MESHES, "elephant.off")
    s = acuity.lodgen.build(mesh, str(tmp_path / "py.glb"), levels=3)
    c = cli("lodgen", mesh, "-o", tmp_path / "cli.glb", "--levels", 3, "--quiet")
    assert c.returncode == 0, c.stderr
    j = json.loads((tmp_path / "cli.glb.json").read_text())
    for m in (s, j):
        m.pop("seconds"), m.pop("output")
        for mesh_summary in m["meshes"]:
            for level in mesh_summary["levels"]:
                level.pop("seconds")
    assert s == j
    assert (tmp_path / "py.glb").read_bytes() == (tmp_path / "cli.glb").read_bytes()
