"""The acuity-osg viewer end to end, headless (run under xvfb-run -a by CTest): a scene made at test
time by `acuity lodgen` from a CGAL mesh (MSFT_lod) and the same mesh as a plain OFF (chained on the
fly), profiles built into a folder; the written PNGs are real pictures (not blank, the level colours
and the gaze ring present), levels.csv holds one valid level per object and frame, frames.csv one
frame-time line per frame, and a stereo run draws both halves. A --shadow run draws a shadowed scene
(osgShadow) and writes each object's level in the light's map to shadow_levels.csv.

Also runs the hello_osg example on that scene and checks that docs/integrations.md shows it verbatim.

Usage: check_viewer.py ACUITY ACUITY_OSG MESH_DIR WORK_DIR HELLO_OSG SOURCE_DIR"""
import csv
import os
import shutil
import subprocess
import sys

import numpy as np
from matplotlib.image import imread

ACUITY, VIEWER, MESHES, WORK, HELLO, SOURCE = sys.argv[1:7]
PALETTE = [(0.15, 0.35, 1.0), (0.0, 0.85, 0.9), (0.2, 0.85, 0.2), (0.95, 0.9, 0.1), (1.0, 0.55, 0.1), (0.9, 0.15, 0.1)]
BACKGROUND = np.array([0.08, 0.09, 0.11])


def run(args, timeout=300):
    r = subprocess.run(args, capture_output=True, text=True, timeout=timeout)
    assert r.returncode == 0, f"{args}\n{r.stdout}\n{r.stderr}"
    return r.stdout


def hue_matches(img, colour):
    """Pixels whose colour is a shade (headlight factor 0.25..1) of the palette colour."""
    c = np.array(colour)
    brightness = img.max(axis=2, keepdims=True) / max(c.max(), 1e-6)
    lit = brightness[..., 0] > 0.2
    shade = c * brightness
    return lit & (np.abs(img - shade).max(axis=2) < 0.04)


def check_png(path, stereo=False):
    img = imread(path)[..., :3]
    h, w, _ = img.shape
    not_background = np.abs(img - BACKGROUND).max(axis=2) > 0.03
    frac = not_background.mean()
    assert 0.01 < frac < 0.95, f"{path}: {frac:.3f} of the pixels differ from the background"
    levels = [k for k, c in enumerate(PALETTE) if hue_matches(img, c).sum() > 50]
    assert levels, f"{path}: no level colour found"
    if stereo:
        for half in (not_background[:, : w // 2], not_background[:, w // 2:]):
            assert half.mean() > 0.005, f"{path}: an eye's half is empty"
    return img, levels


def read_csv(path):
    with open(path, newline="") as f:
        rows = list(csv.reader(f))
    return rows[0], rows[1:]


def main():
    shutil.rmtree(WORK, ignore_errors=True)
    os.makedirs(WORK)
    mesh = os.path.join(MESHES, "eight.off")
    glb = os.path.join(WORK, "eight.glb")
    run([ACUITY, "lodgen", mesh, "-o", glb, "--levels", "4", "-q"])
    profiles = os.path.join(WORK, "profiles")

    # 1. lodgen's MSFT_lod glTF, 36 objects in a grid, debug colours and the gaze ring.
    out = os.path.join(WORK, "mono")
    frames = 24
    stdout = run([VIEWER, glb, "--profiles", profiles, "--res", "64", "--objects", "36", "--headless", "--frames", str(frames),
                  "--out", out, "--debug", "--png-every", "8", "--width", "480", "--height", "270", "--gaze-source", "fixed"])
    assert "frame time [ms" in stdout and "acuity" in stdout, stdout
    assert os.path.exists(os.path.join(profiles, "eight.acuity")), "the profile was saved into --profiles"
    pngs = sorted(p for p in os.listdir(out) if p.endswith(".png"))
    assert pngs == ["frame_00000.png", "frame_00008.png", "frame_00016.png"], pngs
    seen = set()
    for p in pngs:
        img, levels = check_png(os.path.join(out, p))
        seen.update(levels)
        # The fixed gaze looks straight ahead: the white ring sits at the centre.
        h, w, _ = img.shape
        white = (img.min(axis=2) > 0.9)
        ys, xs = np.nonzero(white)
        assert len(xs) > 20, f"{p}: no gaze ring"
        assert abs(xs.mean() - w / 2) < 4 and abs(ys.mean() - h / 2) < 4, f"{p}: ring at {xs.mean()}, {ys.mean()}"
    header, rows = read_csv(os.path.join(out, "levels.csv"))
    assert len(header) == 37 and len(rows) == frames
    levels = np.array([[int(x) for x in r[1:]] for r in rows])
    assert levels.min() >= 0 and levels.max() <= 3, "levels within the 4-level chain"
    assert [int(r[0]) for r in rows] == list(range(frames))
    header, rows = read_csv(os.path.join(out, "frames.csv"))
    assert header == ["frame", "time_s", "frame_ms", "cull_ms", "acuity_ms", "transforms_ms", "draw_ms", "triangles", "changed"]
    assert len(rows) == frames
    t = np.array([[float(x) for x in r] for r in rows])
    assert np.all(t[:, 2] > 0) and np.all(t[:, 3] > 0) and np.all(t[:, 4] > 0), "frame, cull and acuity times are measured"
    assert np.all(t[:, 4] <= t[:, 3] + 1e-6), "acuity runs inside the cull"
    assert np.all(t[:, 5] <= t[:, 4]), "the transform walk is part of acuity's time"
    # The triangles reported are those of the levels written: 634 / 316 / 158 / 78 per level.
    tri = np.array([634, 316, 158, 78])
    assert np.array_equal(t[:, 7].astype(int), tri[levels].sum(axis=1))

    # 2. The plain mesh, chained on the fly by lodgen (the path `simulate` takes), in stereo.
    out2 = os.path.join(WORK, "stereo")
    stdout = run([VIEWER, mesh, "--profiles", os.path.join(WORK, "profiles_plain"), "--res", "64", "--objects", "9", "--headless",
                  "--frames", "3", "--out", out2, "--stereo", "--debug", "--width", "480", "--height", "240"])
    assert "stereo" in stdout
    check_png(os.path.join(out2, "frame_00000.png"), stereo=True)

    # 3. OSG's threaded models (one cull thread per eye camera) choose the same levels as the
    #    single-threaded viewer: the kit runs the scheduler once per frame whichever cull comes first.
    common = [glb, "--profiles", profiles, "--objects", "25", "--headless", "--frames", "20", "--stereo", "--png-every", "0",
              "--width", "320", "--height", "160", "--gaze-source", "generated", "-q"]
    run([VIEWER] + common + ["--out", os.path.join(WORK, "single")])
    run([VIEWER] + common + ["--out", os.path.join(WORK, "threaded"), "--threading", "cull-per-camera"])
    _, single = read_csv(os.path.join(WORK, "single", "levels.csv"))
    _, threaded = read_csv(os.path.join(WORK, "threaded", "levels.csv"))
    assert single == threaded and len(single) == 20

    # 4. A shadowed scene: osgShadow's ShadowMap under a directional light, over a ground. Its light
    #    camera is the kit's view of class 0; its orthographic map gives every object of the grid (the
    #    same mesh at the same scale) one footprint level once the camera is placed (frame 1 on), and a
    #    map of 64 texels a coarser one than a map of 512.
    shadow = {}
    for texels in (512, 64):
        out3 = os.path.join(WORK, f"shadow{texels}")
        run([VIEWER, glb, "--profiles", profiles, "--objects", "25", "--headless", "--frames", "6", "--out", out3,
             "--shadow", str(texels), "--png-every", "5", "--width", "320", "--height", "180", "--gaze-source", "fixed",
             "-q"])
        header, rows = read_csv(os.path.join(out3, "shadow_levels.csv"))
        assert header == read_csv(os.path.join(out3, "levels.csv"))[0] and len(rows) == 6
        levels = np.array([[int(x) for x in r[1:]] for r in rows])
        assert levels.min() >= 0 and levels.max() <= 3
        assert np.all(levels[1:] == levels[1, 0]), f"one footprint level for every object: {levels}"
        shadow[texels] = levels[1, 0]
        img = imread(os.path.join(out3, "frame_00005.png"))[..., :3]
        assert (np.abs(img - BACKGROUND).max(axis=2) > 0.03).mean() > 0.2, "the shadowed scene was drawn"
    assert shadow[64] > shadow[512], shadow

    # 5. A bad input fails loudly.
    r = subprocess.run([VIEWER, os.path.join(WORK, "profiles", "eight.acuity"), "--headless", "--frames", "1"],
                       capture_output=True, text=True, timeout=60)
    assert r.returncode != 0 and "acuity-osg:" in r.stderr, r.stderr
    # 6. The documented example runs, and the documentation shows exactly its source.
    stdout = run([HELLO, os.path.join(profiles, "eight.acuity"), glb, "--frames", "5"])
    assert "triangles" in stdout, stdout
    with open(os.path.join(SOURCE, "integrations", "osg", "examples", "hello_osg.cpp")) as f:
        code = f.read().rstrip("\n")
    with open(os.path.join(SOURCE, "docs", "integrations.md")) as f:
        doc = f.read()
    block = doc.split("<!-- hello_osg.cpp begin -->\n```cpp\n")[1].split("\n```\n<!-- hello_osg.cpp end -->")[0]
    assert block == code, "docs/integrations.md's copy of hello_osg.cpp is stale"
    print(f"ok: level colours seen {sorted(seen)}; PNGs in {out}")


if __name__ == "__main__":
    main()
