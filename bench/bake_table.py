"""The table in docs/bake.md: `acuity bake` throughput on bundled meshes (libcgal-demo), 1 thread vs
2 threads vs a 2-worker dask LocalCluster, each with a cache of its own, then a re-run answered by
the cache. Usage (from the repository root, after a build):

    PYTHONPATH=build/python /usr/bin/python3 bench/bake_table.py build/tools/acuity build/cgal-data/data/meshes

Prints wall seconds, CPU seconds of the process tree and assets per minute; the load average at the
start and end (the machine may be shared: compare rows of one run)."""
import os
import resource
import shutil
import subprocess
import sys
import tempfile
import time

MESHES = ["elephant", "cow", "fandisk", "camel", "knot1", "horizons", "rotor_small", "triceratops"]
OPTIONS = ["--res", "128"]


def timed(args, env=None):
    before = resource.getrusage(resource.RUSAGE_CHILDREN)
    t = time.monotonic()
    r = subprocess.run(args, capture_output=True, text=True, env=env)
    wall = time.monotonic() - t
    after = resource.getrusage(resource.RUSAGE_CHILDREN)
    cpu = (after.ru_utime - before.ru_utime) + (after.ru_stime - before.ru_stime)
    if r.returncode != 0:
        sys.exit("failed: %s\n%s%s" % (" ".join(args), r.stdout, r.stderr))
    return wall, cpu


def main():
    acuity, meshes = sys.argv[1], sys.argv[2]
    work = tempfile.mkdtemp(prefix="acuity_bake_bench_")
    src = os.path.join(work, "in")
    os.makedirs(src)
    for m in MESHES:
        shutil.copy(os.path.join(meshes, m + ".off"), src)
    n = len(MESHES)
    rows = []
    print("load average at start: %.1f %.1f %.1f" % os.getloadavg())
    dask_cli = [sys.executable, "-m", "acuity.bake"]
    import json
    configs = [
        ("1 thread", [acuity, "bake", src, "-o", os.path.join(work, "j1"), "-j", "1", "-q", *OPTIONS]),
        ("2 threads", [acuity, "bake", src, "-o", os.path.join(work, "j2"), "-j", "2", "-q", *OPTIONS]),
        ("2-worker LocalCluster", [*dask_cli, src, "-o", os.path.join(work, "dask"), "--workers", "2", "-q",
                                   "--options", json.dumps({"pixels": 128})]),
        ("re-run, all cached (2 threads)", [acuity, "bake", src, "-o", os.path.join(work, "j2"), "-j", "2", "-q", *OPTIONS]),
    ]
    for name, args in configs:
        wall, cpu = timed(args)
        rows.append((name, wall, cpu, 60.0 * n / wall))
    print("load average at end: %.1f %.1f %.1f" % os.getloadavg())
    print("%d assets (%s), %s\n" % (n, ", ".join(MESHES), " ".join(OPTIONS)))
    print("| run | wall s | CPU s | assets/min |")
    print("|---|---|---|---|")
    for name, wall, cpu, rate in rows:
        print("| %s | %.1f | %.1f | %.1f |" % (name, wall, cpu, rate))
    same = all(open(os.path.join(work, d, f), "rb").read() == open(os.path.join(work, "j1", f), "rb").read()
               for d in ("j2", "dask") for f in os.listdir(os.path.join(work, "j1")) if f.endswith((".glb", ".acuity")))
    print("\nchains and profiles byte-identical across the three bakes: %s" % same)
    one, two, dask, cached = (wall for _, wall, _, _ in rows)
    print("2 threads: %.2fx the speed of 1 thread; 2-worker LocalCluster: %.2fx; re-run from the cache: %.0fx faster "
          "than the 2-thread bake" % (one / two, one / dask, two / max(cached, 1e-9)))
    # The cache's hash against OpenSSL's (hashlib) on the largest bundled mesh of the README.
    import acuity.bake
    import hashlib
    data = open(os.path.join(meshes, "armadillo.off"), "rb").read()
    for name, f in (("acuity::bake SHA-256", acuity.bake.sha256), ("hashlib (OpenSSL)", lambda d: hashlib.sha256(d).hexdigest())):
        t = time.perf_counter()
        for _ in range(10):
            f(data)
        print("%s of armadillo.off (%d bytes): %.1f ms" % (name, len(data), (time.perf_counter() - t) * 100))
    shutil.rmtree(work)


if __name__ == "__main__":
    main()
