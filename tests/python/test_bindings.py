"""The C example and the Python example (the C++ API underneath) give the same levels."""
import os
import subprocess
import sys

import pytest

from test_scheduler import make_profile

HELLO = os.environ.get("ACUITY_HELLO_LOD", "")
EXAMPLES = os.path.join(os.path.dirname(__file__), "..", "..", "examples")


@pytest.mark.skipif(not os.path.exists(HELLO), reason="ACUITY_HELLO_LOD not set")
def test_c_and_python_examples_agree(tmp_path):
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
