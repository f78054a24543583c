"""The acuity command end to end: lodgen output passes the Khronos glTF validator; bad input fails
cleanly with a message naming the file and leaves no output; profile and inspect agree."""
import base64
import io
import json
import os
import re
import shutil
import struct
import subprocess
import sys

import numpy as np
import pytest

ACUITY = os.environ.get("ACUITY_BIN", "")
MESHES = os.environ.get("ACUITY_MESH_DIR", "")
NODE_MODULES = os.environ.get("ACUITY_NODE_MODULES", "")
VALIDATE = os.path.join(os.path.dirname(__file__), "..", "gltf_validate.mjs")



def run(*args):
    assert os.path.exists(ACUITY), "ACUITY_BIN must name the built acuity command (ctest sets it)"
    return subprocess.run([ACUITY, *map(str, args)], capture_output=True, text=True, timeout=600)


def textured_gltf(path):
    """A 16 x 16 grid with texture coordinates and a PNG checkerboard, as .gltf with data URIs."""
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    n = 16
    u, v = np.meshgrid(np.linspace(0, 1, n + 1), np.linspace(0, 1, n + 1))
    pos = np.stack([u.ravel(), 0.1 * np.sin(6 * u.ravel()) * np.cos(5 * v.ravel()), v.ravel()], 1).astype(np.float32)
    uv = np.stack([u.ravel(), v.ravel()], 1).astype(np.float32)
    idx = []
    for r in range(n):
        for c in range(n):
            a = r * (n + 1) + c
            idx += [a, a + n + 1, a + 1, a + 1, a + n + 1, a + n + 2]
    idx = np.array(idx, np.uint32)
    png = io.BytesIO()
    plt.imsave(png, (np.indices((8, 8)).sum(0) % 2).astype(float), cmap="gray", format="png")
    buf = pos.tobytes() + uv.tobytes() + idx.tobytes()
    views = [(0, pos.nbytes, 34962), (pos.nbytes, uv.nbytes, 34962), (pos.nbytes + uv.nbytes, idx.nbytes, 34963)]
    doc = {
        "asset": {"version": "2.0"},
        "buffers": [{"byteLength": len(buf), "uri": "data:application/octet-stream;base64," + base64.b64encode(buf).decode()}],
        "bufferViews": [{"buffer": 0, "byteOffset": o, "byteLength": l, "target": t} for o, l, t in views],
        "accessors": [
            {"bufferView": 0, "componentType": 5126, "count": len(pos), "type": "VEC3",
             "min": pos.min(0).tolist(), "max": pos.max(0).tolist()},
            {"bufferView": 1, "componentType": 5126, "count": len(uv), "type": "VEC2"},
            {"bufferView": 2, "componentType": 5125, "count": len(idx), "type": "SCALAR"},
        ],
        "images": [{"uri": "data:image/png;base64," + base64.b64encode(png.getvalue()).decode()}],
        "textures": [{"source": 0}],
        "materials": [{"pbrMetallicRoughness": {"baseColorTexture": {"index": 0}, "baseColorFactor": [0.9, 0.8, 0.7, 1]}}],
        "meshes": [{"name": "grid", "primitives": [{"attributes": {"POSITION": 0, "TEXCOORD_0": 1}, "indices": 2, "material": 0}]}],
        "nodes": [{"name": "grid", "mesh": 0, "translation": [1, 2, 3]}, {"name": "grid_instance", "mesh": 0, "translation": [-1, 0, 0]}],
        "scenes": [{"nodes": [0, 1]}],
        "scene": 0,
    }
    path.write_text(json.dumps(doc))


def validator_reports(outputs):
    """The Khronos validator's report on each file (node and tests/node's gltf-validator, which
    scripts/bootstrap.sh installs: missing means failing)."""
    assert shutil.which("node"), "node is needed (scripts/bootstrap.sh)"
    assert os.path.isdir(os.path.join(NODE_MODULES, "gltf-validator")), f"{NODE_MODULES}/gltf-validator: run scripts/bootstrap.sh deps"
    env = dict(os.environ, NODE_PATH=NODE_MODULES)
    res = subprocess.run(["node", VALIDATE, *outputs], capture_output=True, text=True, env=env, timeout=300)
    assert res.returncode == 0, res.stderr
    reports = [json.loads(line) for line in res.stdout.splitlines()]
    assert len(reports) == len(outputs)
    return reports


def glb_json(path):
    """A .glb's JSON chunk."""
    data = open(path, "rb").read()
    length = struct.unpack_from("<I", data, 12)[0]
    return json.loads(data[20:20 + length])


def test_lodgen_output_passes_the_khronos_validator(tmp_path):
    inputs = [os.path.join(MESHES, m) for m in ("elephant.off", "camel.off", "fandisk.off", "ChineseDragon-10kv.off", "cow.off")]
    textured = tmp_path / "textured.gltf"
    textured_gltf(textured)
    outputs = []
    for i, src in enumerate(inputs + [str(textured)]):
        out = tmp_path / f"out{i}.glb"
        r = run("lodgen", src, "-o", out, "--levels", "4", "-q")
        assert r.returncode == 0, r.stderr
        outputs.append(str(out))
    for rep in validator_reports(outputs):
        assert rep["errors"] == 0, rep
    # The textured scene keeps its texture and both instances.
    doc = glb_json(outputs[-1])
    assert len(doc["images"]) == 1 and len(doc["scenes"][0]["nodes"]) == 2
    assert "MSFT_lod" in doc["extensionsUsed"]
    top = doc["nodes"][doc["scenes"][0]["nodes"][0]]
    assert len(top["extensions"]["MSFT_lod"]["ids"]) == 3
    assert len(top["extras"]["MSFT_screencoverage"]) == 4


def test_lodgen_clusters_output_passes_the_khronos_validator(tmp_path):
    """`lodgen --clusters`: ACUITY_cluster_hierarchy beside the finest mesh, no validator error or
    warning (the extension is optional: a reader without it draws the primitive, the finest mesh)."""
    outputs = []
    for i, name in enumerate(("fandisk.off", "camel.off")):
        out = tmp_path / f"clusters{i}.glb"
        r = run("lodgen", os.path.join(MESHES, name), "--clusters", "-o", out, "-q")
        assert r.returncode == 0, r.stderr
        outputs.append(str(out))
        summary = json.load(open(f"{out}.json"))["meshes"][0]["clusters"]
        assert summary["groups"] > 10 and summary["levels"] >= 4, summary
    for rep in validator_reports(outputs):
        assert rep["errors"] == 0 and rep["warnings"] == 0, rep
    doc = glb_json(outputs[0])
    assert "ACUITY_cluster_hierarchy" in doc["extensionsUsed"]
    assert "ACUITY_cluster_hierarchy" not in doc.get("extensionsRequired", [])
    prim = doc["meshes"][0]["primitives"][0]
    ext = prim["extensions"]["ACUITY_cluster_hierarchy"]
    assert doc["accessors"][ext["indices"]]["count"] > doc["accessors"][prim["indices"]]["count"]
    assert doc["bufferViews"][ext["clusters"]]["byteLength"] == 16 * ext["clusterCount"]
    assert doc["bufferViews"][ext["groups"]]["byteLength"] == 32 * ext["groupCount"]
    # --clusters and --refine exclude each other.
    r = run("lodgen", os.path.join(MESHES, "fandisk.off"), "--clusters", "--refine", "1", "-o", tmp_path / "x.glb")
    assert r.returncode != 0


@pytest.mark.parametrize("name,text", [
    ("truncated.off", "OFF\n3 1 0\n0 0 0\n1 0"),
    ("absurd.off", "OFF\n3 1000000000 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n"),
    ("nan.obj", "v nan 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n"),
    ("truncated.ply", "ply\nformat ascii 1.0\nelement vertex 3\n"),
    ("empty.stl", ""),
    ("broken.gltf", '{"asset": {"version": "2.0"}, "meshes": [{"primitives": [{"attributes": {"POSITION": 3}}]}]'),
    ("short.glb", "glTF"),
])
def test_bad_input_fails_cleanly(tmp_path, name, text):
    src = tmp_path / name
    src.write_text(text)
    out = tmp_path / "out.glb"
    r = run("lodgen", src, "-o", out, "-q")
    assert r.returncode != 0
    assert name in r.stderr and "acuity:" in r.stderr
    assert not out.exists() and not list(tmp_path.glob("out.glb*"))


def test_profile_then_inspect(tmp_path):
    chain = tmp_path / "chain.glb"
    assert run("lodgen", os.path.join(MESHES, "elephant.off"), "-o", chain, "--levels", "3", "-q").returncode == 0
    off = os.path.join(MESHES, "elephant.off")
    prof = tmp_path / "e.acuity"
    r = run("profile", off, off, "-o", prof, "--res", "64", "--views", "4")
    assert r.returncode == 0, r.stderr
    j = json.loads(run("inspect", prof, "--json").stdout)
    assert len(j["views"]) == 4 and len(j["levels"]) == 2
    assert 0 < 4 * j["runtime_view_table_bytes"] < j["runtime_table_bytes"]  # and the bounds over all four
    assert max(j["levels"][1]["max_lost_contrast_per_band"]) == 0.0  # a level compared with itself
    bad = tmp_path / "bad.acuity"
    bad.write_bytes(prof.read_bytes()[:-10])
    r = run("inspect", bad)
    assert r.returncode != 0 and "bad.acuity" in r.stderr


def write_off(path, positions, indices):
    path.write_text("OFF\n%d %d 0\n" % (len(positions), len(indices) // 3)
                    + "".join("%r %r %r\n" % tuple(map(float, p)) for p in positions)
                    + "".join("3 %d %d %d\n" % tuple(indices[i:i + 3]) for i in range(0, len(indices), 3)))


def test_profile_without_cell_bounds_is_the_librarys(tmp_path):
    """--no-cell-bounds makes the profile the library makes with bound_cells=False (each view's own
    measurement); the default is the library's bounded one, which stores at least as much loss in
    every entry and more in some (a coarse level of a sphere: two cells of different loss)."""
    import acuity
    n = 12  # a UV sphere, and a coarse level: every other band of latitude dropped
    th, ph = np.meshgrid(np.linspace(0.1, np.pi - 0.1, n), np.linspace(0, 2 * np.pi, 2 * n, endpoint=False), indexing="ij")
    p = np.stack([np.sin(th) * np.cos(ph), np.sin(th) * np.sin(ph), np.cos(th)], -1).reshape(-1, 3).astype(np.float32)
    quads = [(r, c) for r in range(n - 1) for c in range(2 * n)]
    tri = lambda r, c: [r * 2 * n + c, (r + 1) * 2 * n + c, r * 2 * n + (c + 1) % (2 * n),
                        r * 2 * n + (c + 1) % (2 * n), (r + 1) * 2 * n + c, (r + 1) * 2 * n + (c + 1) % (2 * n)]
    fine = np.array([i for r, c in quads for i in tri(r, c)], np.uint32)
    coarse = np.array([i for r, c in quads if c % 2 == 0 for i in tri(r, c)], np.uint32)
    write_off(tmp_path / "fine.off", p, fine)
    write_off(tmp_path / "coarse.off", p, coarse)
    common = [tmp_path / "fine.off", tmp_path / "coarse.off", "--res", "64", "--views", "6", "--jobs", "1"]
    r = run("profile", *common, "-o", tmp_path / "own.acuity", "--no-cell-bounds")
    assert r.returncode == 0, r.stderr
    r = run("profile", *common, "-o", tmp_path / "bounded.acuity")
    assert r.returncode == 0, r.stderr
    own = acuity_profile(tmp_path / "own.acuity").lost
    bounded = acuity_profile(tmp_path / "bounded.acuity").lost
    levels = [(p, fine), (p, coarse)]
    lib_own, _ = acuity.spectra.build_profile(levels, pixels=64, views=6, bound_cells=False, jobs=1)
    lib_bounded, _ = acuity.spectra.build_profile(levels, pixels=64, views=6, jobs=1)
    assert np.array_equal(own, acuity.Profile.from_bytes(lib_own).lost)
    assert np.array_equal(bounded, acuity.Profile.from_bytes(lib_bounded).lost)
    assert own.shape == bounded.shape and (bounded >= own).all() and (bounded > own).any()
    r = run("profile", *common, "-o", tmp_path / "x.acuity", "--no-cell-bounds=maybe")
    assert r.returncode != 0 and not (tmp_path / "x.acuity").exists()


def test_profile_from_user_snapshots(tmp_path):
    """Two views of a level that adds a vertical grating (16 cycles per diameter, contrast 0.2) to
    a flat grey reference: the lost contrast is in band 16, orientation 0, and nowhere else."""
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    n = 64
    x = np.arange(n)[None, :].repeat(n, 0)
    grey = 0.5 ** (1 / 2.2)  # sRGB code for linear 0.5 (close enough: only the ratio matters below)
    flat = np.full((n, n), grey)
    srgb = lambda lin: np.where(lin <= 0.0031308, lin * 12.92, 1.055 * lin ** (1 / 2.4) - 0.055)
    lin_grating = 0.5 * (1 + 0.2 * np.cos(2 * np.pi * 16 * x / n))
    views = []
    for v in range(2):
        a, b = tmp_path / f"v{v}_0.png", tmp_path / f"v{v}_1.png"
        plt.imsave(a, srgb(np.full((n, n), 0.5)), cmap="gray", vmin=0, vmax=1)
        plt.imsave(b, srgb(lin_grating), cmap="gray", vmin=0, vmax=1)
        views.append({"direction": [0, 0, 1] if v == 0 else [1, 0, 0], "up": [0, 1, 0], "images": [a.name, b.name]})
    manifest = tmp_path / "manifest.json"
    manifest.write_text(json.dumps({"pixels_per_diameter": n, "levels": [{"triangles": 1000}, {"triangles": 10}], "views": views}))
    out = tmp_path / "snap.acuity"
    r = run("profile", "--snapshots", manifest, "-o", out)
    assert r.returncode == 0, r.stderr
    p = acuity_profile(out)
    lost = p.lost[0]  # level 1: (views, orientations, bands)
    b = list(p.bands).index(16.0)
    assert lost[:, 0, b] == pytest.approx([0.2, 0.2], rel=0.08)  # 8-bit quantisation
    assert lost.sum() - lost[:, 0, b].sum() < 0.05
    # A manifest naming a missing image fails and says which.
    views[1]["images"][1] = "missing.png"
    manifest.write_text(json.dumps({"pixels_per_diameter": n, "levels": [{}, {}], "views": views}))
    r = run("profile", "--snapshots", manifest, "-o", tmp_path / "bad.acuity")
    assert r.returncode != 0 and "missing.png" in r.stderr
    assert not (tmp_path / "bad.acuity").exists()


def acuity_profile(path):
    import acuity
    return acuity.Profile.load(str(path))


def test_profile_reads_lodgens_gltf(tmp_path):
    """lodgen's .glb goes straight into profile: the levels, their triangle counts and their
    geometric errors (recovered from MSFT_screencoverage) arrive in the profile."""
    chain = tmp_path / "e.glb"
    assert run("lodgen", os.path.join(MESHES, "elephant.off"), "-o", chain, "--levels", "3", "-q").returncode == 0
    summary = json.loads((tmp_path / "e.glb.json").read_text())
    prof = tmp_path / "e.acuity"
    r = run("profile", chain, "-o", prof, "--res", "64", "--views", "6")
    assert r.returncode == 0, r.stderr
    j = json.loads(run("inspect", prof, "--json").stdout)
    levels = summary["meshes"][0]["levels"]
    assert [l["triangles"] for l in j["levels"]] == [l["triangles"] for l in levels]
    for got, want in zip(j["levels"][1:], levels[1:]):
        assert got["geometric_error"] == pytest.approx(want["hausdorff_diameters"], rel=1e-4)
    assert max(j["levels"][2]["max_lost_contrast_per_band"]) > 0


def test_simulate_then_explain_a_plain_mesh_scene(tmp_path):
    """A glTF of plain meshes (no LOD levels): simulate chains and profiles them on the fly, runs the
    rules and writes its outputs (and, --large-object, the mesh drawn large as a cluster hierarchy);
    explain reports the level simulate recorded for that frame."""
    scene = tmp_path / "grid.gltf"
    textured_gltf(scene)
    out, profiles = tmp_path / "out", tmp_path / "profiles"
    common = ["--profiles", profiles, "--res", "64", "--seconds", "1", "--seed", "3"]
    r = run("simulate", scene, *common, "--validate", "4", "--images", "1", "--no-plots", "-o", out,
            "--large-object", "grid")
    assert r.returncode == 0, r.stderr
    assert "visible losses" in r.stdout and "tuned to" in r.stdout
    check_large_object(r.stdout, r.stderr, "grid", 512, 60)
    frames = (out / "frames.csv").read_text().splitlines()
    assert len(frames) == 61 and frames[0].startswith("frame,seconds,saccade")
    assert (out / "frame_0030.png").read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    assert (profiles / "grid.acuity").exists()  # built here, reused next time
    # acuity runs no other program; the plots come from the script over the CSVs it wrote.
    assert "plot_simulation.py" not in r.stdout and not (out / "triangles.png").exists()
    script = os.path.join(os.path.dirname(__file__), "..", "..", "scripts", "plot_simulation.py")
    p = subprocess.run([sys.executable, script, str(out)], capture_output=True, text=True, timeout=300)
    assert p.returncode == 0, p.stderr
    for png in ("triangles.png", "sweep.png"):
        assert (out / png).read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    rows = [l.split(",") for l in (out / "levels.csv").read_text().splitlines()]
    header = rows[0]
    recorded = next(row for row in rows[1:] if row[0] == "30" and row[2] == "grid")
    e = run("explain", scene, *common, "--frame", "30", "--object", "grid")
    assert e.returncode == 0, e.stderr
    assert "profile from" not in e.stdout  # quiet about assets
    assert f"chosen: level {recorded[header.index('perceptual')]} " in e.stdout, e.stdout
    assert "retinal velocity" in e.stdout and "eccentricity" in e.stdout
    bad = run("explain", scene, *common, "--frame", "30", "--object", "nothing")
    assert bad.returncode != 0 and "no object 'nothing'" in bad.stderr


def check_large_object(stdout, stderr, name, finest, frames):
    """simulate --large-object's block (sim::large_object_text, as the demo prints it): the mesh as a
    cluster hierarchy, each span's object rule and cluster cut, triangles per frame and judged."""
    assert f"{name}-clusters.acuity" in stderr  # its profile, made (and cached) once
    text = stdout[stdout.index("A large object spanning the gaze"):]
    head = re.search(rf"{name}, (\d+) triangles as (\d+) clusters in (\d+) groups .* for (\d+) frames", text)
    assert head, text
    assert int(head[1]) == finest and int(head[2]) >= 4 and int(head[3]) >= 1 and int(head[4]) == frames, text
    rows = re.findall(r"(?:(\d+) deg)?\s+(object rule|cluster cut) \([^)]*\)\s+(\d+)\s+([\d.]+)%\s+(\d+) of (\d+)",
                      text)
    assert [(x[0], x[1]) for x in rows] == [("40", "object rule"), ("", "cluster cut"),
                                           ("20", "object rule"), ("", "cluster cut")], text
    for _, _, triangles, share, visible, judged in rows:
        assert 0 < int(triangles) <= finest and float(share) == pytest.approx(100 * int(triangles) / finest, abs=0.1)
        assert int(judged) == 10 and int(visible) <= int(judged)


def test_simulate_large_object_refused(tmp_path):
    """--large-object names a mesh of the scene and needs --profiles (where its profile is cached)."""
    scene = tmp_path / "grid.gltf"
    textured_gltf(scene)
    bad = run("simulate", scene, "--profiles", tmp_path / "p", "--res", "32", "--seconds", "0.1", "--validate", "0",
              "--images", "0", "--no-plots", "--large-object", "nothing")
    assert bad.returncode != 0 and "--large-object: the scene has no asset 'nothing' (it has grid)" in bad.stderr
    alone = run("simulate", scene, "--res", "32", "--seconds", "0.1", "--large-object", "grid")
    assert alone.returncode != 0 and "--profiles" in alone.stderr


def test_simulate_bad_track_fails_cleanly(tmp_path):
    scene = tmp_path / "grid.gltf"
    textured_gltf(scene)
    gaze = tmp_path / "gaze.csv"
    gaze.write_text("t,x,y,z\n0,0,0,-1\n0.1,zero,0,-1\n")
    out = tmp_path / "out"
    r = run("simulate", scene, "--res", "64", "--seconds", "1", "--gaze", gaze, "-o", out, "--no-plots")
    assert r.returncode != 0
    assert "gaze.csv:3: column 'x': 'zero' is not a finite number" in r.stderr
    assert not out.exists()
