"""acuity bake and acuity.bake end to end: the CLI's statuses and exit code, the same bytes as
`acuity lodgen` + `acuity profile`, SHA-256 against hashlib, Python's lodgen.build placing nodes as
the CLI does, local vs a real 2-worker dask LocalCluster (Python and the CLI's --dask), and a bake
killed mid-way resumed without corruption. Dask (python3-distributed) is required: without it these
tests fail, they are never skipped."""
import hashlib
import json
import os
import shutil
import signal
import subprocess
import sys
import time

import numpy as np
import pytest
from dask.distributed import Client, LocalCluster  # required (scripts/bootstrap.sh installs python3-distributed)

import acuity
import acuity.bake
from test_cli import textured_gltf

ACUITY = os.environ.get("ACUITY_BIN", "")
SMALL = ["--res", "32", "--views", "6"]
SMALL_OPTIONS = {"pixels": 32, "views": 6}


def run(*args, timeout=300):
    assert os.path.exists(ACUITY), "ACUITY_BIN must name the acuity command"
    return subprocess.run([ACUITY, *map(str, args)], capture_output=True, text=True, timeout=timeout)


def write_off(path, subdivisions=2, scale=(1.0, 1.0, 1.0)):
    """An octahedron subdivided onto the unit sphere (8 x 4^s triangles: small, closed, manifold),
    scaled into an ellipsoid, as OFF."""
    v = [np.array(p, float) for p in ((1, 0, 0), (-1, 0, 0), (0, 1, 0), (0, -1, 0), (0, 0, 1), (0, 0, -1))]
    f = [(0, 2, 4), (2, 1, 4), (1, 3, 4), (3, 0, 4), (2, 0, 5), (1, 2, 5), (3, 1, 5), (0, 3, 5)]
    for _ in range(subdivisions):
        cache, nf = {}, []
        def mid(a, b):
            key = (min(a, b), max(a, b))
            if key not in cache:
                m = v[a] + v[b]
                v.append(m / np.linalg.norm(m))
                cache[key] = len(v) - 1
            return cache[key]
        for a, b, c in f:
            ab, bc, ca = mid(a, b), mid(b, c), mid(c, a)
            nf += [(a, ab, ca), (ab, b, bc), (ca, bc, c), (ab, bc, ca)]
        f = nf
    with open(path, "w") as out:
        out.write("OFF\n%d %d 0\n" % (len(v), len(f)))
        for p in v:
            out.write("%r %r %r\n" % tuple(float(x) * s for x, s in zip(p, scale)))
        for t in f:
            out.write("3 %d %d %d\n" % t)


def library(root, count=2):
    """root/in: `count` ellipsoids (512 triangles each), a broken OFF and a file that is not an asset."""
    src = root / "in"
    (src / "props").mkdir(parents=True)
    for i in range(count):
        write_off(src / ("props" if i % 2 else ".") / ("shape%d.off" % i), 3, (1.0, 1.0 + 0.3 * i, 1.0))
    (src / "broken.off").write_text("OFF\n3 1 0\n0 0 0\n1 0 nan\n0 1 0\n3 0 1 2\n")
    (src / "readme.txt").write_text("not an asset\n")
    return src


def files(folder):
    """{relative path: bytes} of every file under folder, the cache left out."""
    out = {}
    for d, dirs, names in os.walk(folder):
        dirs[:] = [x for x in dirs if x != ".cache"]
        for n in names:
            p = os.path.join(d, n)
            out[os.path.relpath(p, folder)] = open(p, "rb").read()
    return out


def without_seconds(index_bytes):
    index = json.loads(index_bytes)
    for a in index["assets"].values():
        a.pop("seconds")
    return index


def test_sha256_agrees_with_hashlib():
    rng = np.random.default_rng(7)
    for n in (0, 1, 55, 56, 63, 64, 65, 119, 120, 1000, 100003):
        data = rng.integers(0, 256, n, dtype=np.uint8).tobytes()
        assert acuity.bake.sha256(data) == hashlib.sha256(data).hexdigest()


def test_cli_bakes_the_good_reports_the_bad_and_matches_lodgen_and_profile(tmp_path):
    src = library(tmp_path)
    r = run("bake", src, "-o", tmp_path / "out", *SMALL, "-j", "2")
    assert r.returncode == 1
    assert "1 of 3 assets failed" in r.stderr
    assert "shape0" in r.stdout and "error" in r.stdout  # the summary table
    assert "3/3" in r.stderr  # the progress bar
    index = json.loads((tmp_path / "out" / "index.json").read_text())
    assert index["assets"]["broken"]["status"] == "error" and "broken.off" in index["assets"]["broken"]["error"]
    assert not (tmp_path / "out" / "broken.glb").exists()
    for name in ("shape0", "props/shape1"):
        a = index["assets"][name]
        assert a["status"] == "ok"
        data = (src / (name + ".off")).read_bytes()
        assert a["input_sha256"] == hashlib.sha256(data).hexdigest()
    # The same bytes as the two commands by hand.
    r1 = run("lodgen", src / "shape0.off", "-o", tmp_path / "by_hand.glb", "-q")
    r2 = run("profile", tmp_path / "by_hand.glb", "-o", tmp_path / "by_hand.acuity", *SMALL)
    assert r1.returncode == 0 and r2.returncode == 0, r1.stderr + r2.stderr
    assert (tmp_path / "out" / "shape0.glb").read_bytes() == (tmp_path / "by_hand.glb").read_bytes()
    assert (tmp_path / "out" / "shape0.acuity").read_bytes() == (tmp_path / "by_hand.acuity").read_bytes()
    # Bad input: a missing folder, OUT inside the input folder. Nothing written.
    r = run("bake", tmp_path / "nope", "-o", tmp_path / "o2")
    assert r.returncode == 1 and "no such file" in r.stderr and not (tmp_path / "o2").exists()
    r = run("bake", src, "-o", src / "baked")
    assert r.returncode == 1 and "inside the input folder" in r.stderr and not (src / "baked").exists()


def test_python_lodgen_build_writes_what_the_cli_writes(tmp_path):
    scene = tmp_path / "scene.gltf"
    textured_gltf(scene)  # two nodes, translated: each placed at its own matrix
    acuity.lodgen.build(str(scene), str(tmp_path / "py.glb"), levels=3)
    r = run("lodgen", scene, "-o", tmp_path / "cli.glb", "--levels", "3", "-q")
    assert r.returncode == 0, r.stderr
    assert (tmp_path / "py.glb").read_bytes() == (tmp_path / "cli.glb").read_bytes()


def test_local_and_a_two_worker_local_cluster_give_the_same_bytes(tmp_path):
    src = library(tmp_path, count=3)
    local = acuity.bake.bake(str(src), str(tmp_path / "local"), jobs=2, **SMALL_OPTIONS)
    assert local["failed"] == 1 and local["ok"] == 3
    with LocalCluster(n_workers=2, threads_per_worker=1, processes=True, dashboard_address=None) as cluster, \
            Client(cluster) as client:
        assert len(client.scheduler_info()["workers"]) == 2
        # A cache of its own: every asset baked on the workers.
        dask = acuity.bake.bake(str(src), str(tmp_path / "dask"), client=client, **SMALL_OPTIONS)
        assert dask["failed"] == 1
        a, b = files(tmp_path / "local"), files(tmp_path / "dask")
        assert sorted(a) == sorted(b)
        for name in a:
            if name != "index.json":
                assert a[name] == b[name], name
        assert without_seconds(a["index.json"]) == without_seconds(b["index.json"])  # seconds: each bake's own
        # Sharing the local run's cache (the farm's case): the index too is the same bytes.
        shared = tmp_path / "shared"
        acuity.bake.bake(str(src), str(shared), client=client, cache=str(tmp_path / "local" / ".cache"), **SMALL_OPTIONS)
        assert files(shared) == a
        # The CLI hands --dask to python3 -m acuity.bake: the same bytes again.
        r = run("bake", src, "-o", tmp_path / "cli", "--dask", cluster.scheduler_address, "--cache",
                tmp_path / "local" / ".cache", *SMALL)
        assert r.returncode == 1 and "1 of 4 assets failed" in r.stderr, r.stdout + r.stderr
        assert files(tmp_path / "cli") == a


def test_a_killed_bake_resumes_without_corruption(tmp_path):
    src = library(tmp_path, count=4)
    out = tmp_path / "out"
    p = subprocess.Popen([ACUITY, "bake", str(src), "-o", str(out), "-j", "1", "-q", *SMALL],
                         stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    deadline = time.monotonic() + 120
    records = []
    while time.monotonic() < deadline and p.poll() is None:
        records = [f for d, _, names in os.walk(out / ".cache") for f in names if f.endswith(".json")]
        if records:
            break
        time.sleep(0.01)
    assert p.poll() is None, "the bake ended before it could be killed; make the library larger"
    p.send_signal(signal.SIGKILL)
    p.wait()
    assert records and not (out / "index.json").exists()
    r = run("bake", src, "-o", out, "-j", "2", *SMALL)
    assert r.returncode == 1, r.stderr
    assert "cached" in r.stdout  # what the killed run finished was kept
    clean = tmp_path / "clean"
    run("bake", src, "-o", clean, "-j", "2", *SMALL)
    a, b = files(out), files(clean)
    assert sorted(a) == sorted(b)
    for name in a:
        if name != "index.json":
            assert a[name] == b[name], name
    assert without_seconds(a["index.json"]) == without_seconds(b["index.json"])
    assert not [n for n in a if ".tmp" in n]


def test_python_bake_refuses_bad_input(tmp_path):
    src = library(tmp_path, count=1)
    with pytest.raises(acuity.bake.InputError, match="no such file"):
        acuity.bake.bake(str(tmp_path / "nope"), str(tmp_path / "out"))
    with pytest.raises(acuity.bake.InputError, match="inside the input folder"):
        acuity.bake.bake(str(src), str(src / "out"))
    with pytest.raises(acuity.bake.InputError, match="unknown option 'colour'"):
        acuity.bake.bake(str(src), str(tmp_path / "out"), colour=1)
    assert not (tmp_path / "out").exists() and not (src / "out").exists()
