#!/usr/bin/env python3
"""Runs `acuity lodgen` over every third-party asset lodgen should handle and prints a Markdown table:
a summary (counts, the slowest asset, the normal deviation of level 1 over every mesh), then per asset
the result (a chain: meshes, triangles, levels; or the error's first line), the wall time, and the
worst measured errors. Assets: Debian's assimp-testmodels (the glTF 2.0 files, PLY/Wuson.ply)
and the controller models of npm @webxr-input-profiles/assets (installed by `scripts/bootstrap.sh deps`
into assets/third_party/node_modules).

Run: python3 scripts/lodgen_sweep.py build/tools/acuity [OUT_DIR]   (docs/lodgen.md holds its output as a
figure: scripts/regenerate_docs.py --only lodgen-sweep)
Exit status 1 when an asset neither gets a chain nor a clear error (a crash, a timeout at 60 s).
"""
import glob
import json
import os
import subprocess
import sys
import tempfile
import time

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
ASSIMP = "/usr/share/assimp/models"
WEBXR = os.path.join(ROOT, "assets/third_party/node_modules/@webxr-input-profiles/assets/dist/profiles")
LIMIT = 60  # seconds per asset (issue 15)


def assets():
    found = sorted(glob.glob(ASSIMP + "/glTF2/**/*.gltf", recursive=True) + glob.glob(ASSIMP + "/glTF2/**/*.glb", recursive=True))
    found.append(ASSIMP + "/PLY/Wuson.ply")
    found += sorted(glob.glob(WEBXR + "/**/*.glb", recursive=True))
    return found


def main():
    acuity = sys.argv[1] if len(sys.argv) > 1 else os.path.join(ROOT, "build/tools/acuity")
    out_dir = sys.argv[2] if len(sys.argv) > 2 else tempfile.mkdtemp(prefix="acuity_sweep_")
    os.makedirs(out_dir, exist_ok=True)
    rows, bad, level1 = [], 0, []  # level1: level 1's normal deviation of every mesh that has one
    for i, path in enumerate(assets()):
        out = os.path.join(out_dir, "%03d.glb" % i)
        start = time.monotonic()
        try:
            p = subprocess.run([acuity, "lodgen", path, "-o", out, "-q"], capture_output=True, text=True, timeout=LIMIT)
            seconds = time.monotonic() - start
            if p.returncode == 0:
                summary = json.load(open(out + ".json"))
                meshes = summary["meshes"]
                tris = sum(m["levels"][0]["triangles"] for m in meshes)
                levels = max(len(m["levels"]) for m in meshes)
                h = max(l["hausdorff_diameters"] for m in meshes for l in m["levels"])
                n = max(l["normal_deviation_degrees"] for m in meshes for l in m["levels"])
                level1 += [m["levels"][1]["normal_deviation_degrees"] for m in meshes if len(m["levels"]) > 1]
                capped = any(not l["measured_fully"] for m in meshes for l in m["levels"])
                result = "chain: %d meshes, %d triangles, up to %d levels; worst Hausdorff %.4f, normal p99 %.1f deg%s" % (
                    len(meshes), tris, levels, h, n, " (time-capped)" if capped else "")
            else:
                lines = [l for l in p.stderr.splitlines() if l.strip()]
                message = lines[-1] if lines else "(no message)"
                clear = message.startswith("acuity: ") and p.returncode == 1
                if not clear:
                    bad += 1
                result = ("error: " if clear else "UNCLEAR FAILURE (exit %d): " % p.returncode) + message.removeprefix("acuity: ").strip()
        except subprocess.TimeoutExpired:
            seconds = LIMIT
            bad += 1
            result = "TIMEOUT after %d s" % LIMIT
        rows.append((os.path.relpath(path, "/usr/share/assimp/models") if path.startswith(ASSIMP) else os.path.relpath(path, WEBXR), seconds, result))
        print("%s: %.1f s: %s" % (rows[-1][0], seconds, result), file=sys.stderr, flush=True)
    slowest = max(rows, key=lambda r: r[1])
    print("%d assets, %d chains, %d clear errors, %d unclear; slowest %.1f s (%s)" % (
        len(rows), sum(r[2].startswith("chain") for r in rows), sum(r[2].startswith("error") for r in rows), bad,
        slowest[1], slowest[0]))
    if level1:
        level1.sort()
        rank = lambda q: level1[min(len(level1) - 1, int(q * len(level1)))]  # nearest rank
        print("\nLevel 1 (half the triangles) of the %d meshes with more than one level: normal deviation (p99 angle) "
              "median %.0f deg, 90th percentile %.0f deg, worst %.0f deg" % (len(level1), rank(0.5), rank(0.9), level1[-1]))
    print("\n| asset | seconds | result |\n|---|---|---|")
    for name, seconds, result in rows:
        print("| %s | %.1f | %s |" % (name, seconds, result.replace("|", "/")))
    return 1 if bad else 0


if __name__ == "__main__":
    sys.exit(main())
