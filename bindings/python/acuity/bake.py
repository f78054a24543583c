"""acuity.bake: bake an asset library -- LOD chains (.glb), profiles (.acuity) and OUT/index.json --
through the content-addressed cache, locally on all cores or as one Dask task per asset.

    acuity.bake.bake("assets/", "baked/")                            # all local cores (oneTBB)
    acuity.bake.bake("assets/", "baked/", workers=2)                 # a 2-worker dask LocalCluster
    acuity.bake.bake("assets/", "baked/", client="tcp://host:8786")  # a farm's Dask scheduler
    python3 -m acuity.bake assets/ -o baked/ --dask tcp://host:8786  # the same from a shell

Every path runs the same C++ (acuity::bake: plan_bake, bake_asset, finish_bake), so the outputs
and the index are the same bytes whichever runs the tasks. Workers need this package importable --
installed (`pip install --no-index --no-build-isolation <build>/python` into the workers' Python
environment) or on PYTHONPATH -- and the input and cache folders at the same paths (a shared file
system); the client copies the results from the cache into OUT.
"""
import argparse
import json
import sys
import time

from . import _acuity

_native = _acuity._bake
InputError = _acuity.lodgen.InputError
FileError = _acuity.FileError
TOOL_VERSION = _native.TOOL_VERSION

__all__ = ["bake", "plan", "bake_asset", "sha256", "InputError", "FileError", "TOOL_VERSION", "main"]


def plan(input, out, cache=None, **options):
    """The jobs of a folder, manifest (.json) or single asset, as a dict {out, cache, defaults, jobs}."""
    return json.loads(_native.plan(str(input), str(out), str(cache or ""), json.dumps(options)))


def bake_asset(job, cache, profile_jobs=1):
    """Bakes one job (JSON text from plan()["jobs"]) into the cache; returns the result JSON text.
    What each Dask task runs."""
    return _native.bake_asset(job, cache, profile_jobs)


def sha256(data):
    """SHA-256 of bytes as 64 hex digits (the cache's hash function)."""
    return _native.sha256(bytes(data))


def _progress(done, total, current, start, stream):
    stream.write("\r" + _native.progress_text(done, total, current, time.monotonic() - start))
    if done == total:
        stream.write("\n")
    stream.flush()


def _client_for(client, workers):
    """(client, cluster to close or None): an address is connected to; workers=N starts a LocalCluster."""
    from dask.distributed import Client, LocalCluster  # python3-distributed; required for Dask runs
    if client is None:
        cluster = LocalCluster(n_workers=int(workers), threads_per_worker=1, processes=True, dashboard_address=None)
        return Client(cluster), cluster
    if isinstance(client, str):
        return Client(client), None
    return client, None


def _run_dask(p, client, workers, profile_jobs, progress):
    from dask.distributed import as_completed
    owned_client, cluster = None, None
    c, cluster = _client_for(client, workers)
    if c is not client:
        owned_client = c
    try:
        futures = c.map(bake_asset, [j for j in p["jobs"]], cache=p["cache"], profile_jobs=profile_jobs, pure=False)
        index = {f.key: i for i, f in enumerate(futures)}
        results = [None] * len(futures)
        start = time.monotonic()
        for done, f in enumerate(as_completed(futures), 1):
            i = index[f.key]
            results[i] = f.result()
            if progress:
                _progress(done, len(futures), json.loads(p["jobs"][i])["name"], start, sys.stderr)
        return results
    finally:
        if owned_client is not None:
            owned_client.close()
        if cluster is not None:
            cluster.close()


def bake(input, out, client=None, cache=None, workers=None, jobs=0, profile_jobs=1, progress=False, **options):
    """Bakes every asset of `input` (folder, manifest .json or one file) into folder `out`.

    client: None runs locally on `jobs` threads (0: all cores) unless `workers` asks for a Dask
    LocalCluster of that many single-threaded worker processes; a dask.distributed.Client, or a
    scheduler address such as "tcp://host:8786", runs one task per asset there (each task bakes with
    `profile_jobs` threads). cache: the cache folder (default out/.cache), shared by the workers.
    options: levels, ratio, max_error, backend, lock_border, crease, measure_seconds, reference_height, pixels, orientations,
    bands, views, tolerance, bound_cells, clusters, window_pixels, group_views, view_cells, asset_root (as `acuity bake`; a manifest
    may override them per asset).

    Returns the index (the dict written to out/index.json). A failed asset is listed with
    "status": "error"; the others are baked. Raises InputError when the input or out is refused,
    FileError when a manifest or the cache cannot be read or out cannot be written.
    """
    return _bake(input, out, client, cache, workers, jobs, profile_jobs, progress, options)[2]


def _bake(input, out, client, cache, workers, jobs, profile_jobs, progress, options):
    """bake(), returning (plan as JSON text, results as JSON texts, index)."""
    p = plan(input, out, cache, **options)
    text = json.dumps(p)
    if client is None and not workers:
        results = _native.bake_all(text, int(jobs))
    else:
        results = _run_dask(p, client, workers, int(profile_jobs), progress)
    _native.finish(text, results)
    with open(p["out"] + "/index.json", encoding="utf-8") as f:
        return text, results, json.load(f)


def main(argv=None):
    """python3 -m acuity.bake INPUT -o OUT [--dask ADDRESS | --workers N] [--cache DIR] [--options JSON]"""
    ap = argparse.ArgumentParser(prog="python3 -m acuity.bake", description=main.__doc__)
    ap.add_argument("input")
    ap.add_argument("-o", "--output", required=True)
    ap.add_argument("--cache", default=None)
    ap.add_argument("--dask", default=None, help="dask.distributed scheduler address, e.g. tcp://host:8786")
    ap.add_argument("--workers", type=int, default=None, help="a LocalCluster of N worker processes")
    ap.add_argument("--jobs", type=int, default=0, help="local threads (0: all cores) without Dask")
    ap.add_argument("--options", default="{}", help="bake options as JSON (as `acuity bake` passes them)")
    ap.add_argument("-q", "--quiet", action="store_true")
    a = ap.parse_args(argv)
    start = time.monotonic()
    try:
        text, results, index = _bake(a.input, a.output, a.dask, a.cache, a.workers, a.jobs, 1, not a.quiet,
                                     json.loads(a.options))
    except (InputError, FileError) as e:
        print("acuity bake: %s" % e, file=sys.stderr)
        return 1
    print(_native.summary_table(text, results, time.monotonic() - start), end="")
    if index["failed"]:
        print("acuity bake: %d of %d assets failed (see %s/index.json)" % (index["failed"], len(index["assets"]), a.output),
              file=sys.stderr)
        return 1
    return 0


if __name__ == "__main__":
    sys.exit(main())
