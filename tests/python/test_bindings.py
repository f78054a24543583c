"""The C example and the Python example (the C++ API underneath) give the same levels."""
import os
import subprocess
import sys

import pytest

from test_scheduler import make_profile

HELLO = os.environ.get("ACUITY_HELLO_LOD", "")
EXAMPLES = os.path.join(os.path.dirname(__file__), "..", "..", "examples")


def test_c_and_python_examples_agree(tmp_path):
    assert os.path.exists(HELLO), "ACUITY_HELLO_LOD must name the built hello_lod example (ctest sets it)"
    path = tmp_path / "p.acuity"
    path.write_bytes(make_profile())
    c = subprocess.run([HELLO, str(path)], capture_output=True, text=True, timeout=60)
    assert c.returncode == 0, c.stderr
    py = subprocess.run([sys.executable, os.path.join(EXAMPLES, "hello_lod.py"), str(path)], capture_output=True, text=True,
                        timeout=60, env=dict(os.environ))
    assert py.returncode == 0, py.stderr
    assert c.stdout == py.stdout
    levels = [int(x) for x in c.stdout.split("\n")[0].split(":")[1].split()]
    assert len(levels) == 20 and len(set(levels)) > 1  # a scene where the levels differ
    bad = tmp_path / "bad.acuity"
    bad.write_bytes(b"not a profile" * 8)
    r = subprocess.run([HELLO, str(bad)], capture_output=True, text=True, timeout=60)
    assert r.returncode == 1 and "magic" in r.stderr


def test_transitions_and_update_ranges():
    """begin_frame / update(first, count) / end_frame equal run_frame; the fade rises by dt / T."""
    import numpy as np

    import acuity
    from test_scheduler import frame_looking_forward

    def scheduler():
        c = acuity.SchedulerConfig()
        c.max_objects = 6
        c.transition_seconds = 0.1
        s = acuity.Scheduler(c)
        p = s.add_profile(acuity.Profile.from_bytes(make_profile()))
        pos = np.array([[0.0, 0.0, -2.0 - 3 * i] for i in range(6)])
        ids = s.add_objects(np.full(6, p), pos, np.tile([0, 0, 0, 1], (6, 1)), np.ones(6))
        return s, ids, pos

    a, ids, pos = scheduler()
    b, _, _ = scheduler()
    f = frame_looking_forward()
    f.dt = 0.025
    a.run_frame(f)
    b.begin_frame(f)
    b.update(0, 4)
    b.update(4, 2**31)  # clipped to the capacity
    b.end_frame()
    assert list(a.levels(ids)) == list(b.levels(ids))
    far = pos * 40  # everything moves away: coarser levels, fades start at 0
    for s in (a, b):
        s.set_transforms(ids, far, np.tile([0, 0, 0, 1], (6, 1)), np.ones(6))
        s.run_frame(f)
    previous, fades = b.transitions(ids)
    changed = (b.flags(ids) & acuity.FLAG_CHANGED) != 0
    assert changed.any()
    assert np.all(fades[changed] == 0) and np.all(previous[changed] < b.levels(ids)[changed])
    i = int(ids[np.argmax(changed)])
    for n in range(1, 6):
        b.run_frame(f)
        assert b.transition(i) == pytest.approx(min(1.0, 0.25 * n))
        assert b.previous_level(i) == previous[np.argmax(changed)]
    with pytest.raises(ValueError):
        b.update(0, 6)  # no frame begun
    with pytest.raises(ValueError):
        b.end_frame()
    with pytest.raises(IndexError):
        b.transition(99)
    with pytest.raises(ValueError):
        b.set_clamps(i, 3, 1)
    with pytest.raises(ValueError):
        b.set_bias(i, float("nan"))
