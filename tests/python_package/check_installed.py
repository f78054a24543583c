"""The pip-installed `acuity` (tests/python_package.cmake), run from outside the source and build
trees with no PYTHONPATH: it is the venv's copy; a scheduler frame runs; acuity.bake on a 2-worker
Dask LocalCluster bakes with workers that import the same installed copy, and gives the bytes a
local bake gives. Usage: check_installed.py TESTS_PYTHON_DIR WORK_DIR"""
import os
import pathlib
import sys

import acuity
import acuity.bake


def worker_acuity():
    """Where a Dask worker imports acuity from."""
    import acuity as imported
    return imported.__file__


def main():
    tests_python, work = sys.argv[1], pathlib.Path(sys.argv[2])
    venv = os.path.realpath(sys.prefix)
    assert sys.prefix != sys.base_prefix, "not run by a venv's python"
    assert os.path.realpath(acuity.__file__).startswith(venv + os.sep), acuity.__file__
    assert "PYTHONPATH" not in os.environ

    sys.path.append(tests_python)  # after site-packages: the tests' helpers, never another acuity
    import numpy as np
    from dask.distributed import Client, LocalCluster
    from test_bake import SMALL_OPTIONS, files, library
    from test_scheduler import frame_looking_forward, objects_in_a_row

    z = -np.geomspace(2, 2000, 40)
    s, ids = objects_in_a_row(z)
    s.run_frame(frame_looking_forward())
    levels = s.levels(ids)
    assert np.all(np.diff(levels.astype(int)) >= 0) and levels[0] < levels[-1], levels
    print("acuity %s from %s: levels %s" % (acuity.__version__, acuity.__file__, " ".join(map(str, levels))))

    src = library(work, count=2)
    local = acuity.bake.bake(str(src), str(work / "local"), jobs=1, **SMALL_OPTIONS)
    with LocalCluster(n_workers=2, threads_per_worker=1, processes=True, dashboard_address=None) as cluster, \
            Client(cluster) as client:
        where = client.run(worker_acuity)
        assert len(where) == 2 and all(os.path.realpath(w).startswith(venv + os.sep) for w in where.values()), where
        dask = acuity.bake.bake(str(src), str(work / "dask"), client=client, **SMALL_OPTIONS)
    assert local["ok"] == dask["ok"] == 2 and local["failed"] == dask["failed"] == 1, (local, dask)
    a, b = files(work / "local"), files(work / "dask")
    assert sorted(a) == sorted(b) and all(a[n] == b[n] for n in a if n != "index.json")
    print("bake on 2 Dask workers importing %s: %d assets, the same bytes as a local bake" % (set(where.values()), dask["ok"]))


if __name__ == "__main__":  # Dask's worker processes are spawned: they import this file, never run it
    main()
