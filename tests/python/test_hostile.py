"""Hostile assets, tracks, options and callers through the acuity command and the Python module
(issue 12): each fails within seconds with a message that says why, reads nothing outside the
asset's folder, never crashes or hangs, and destroys no file. The hostile files are made here."""
import base64
import json
import os
import re
import stat
import struct
import subprocess
import sys
import zlib

import numpy as np
import pytest

from test_cli import textured_gltf

ACUITY = os.environ.get("ACUITY_BIN", "")
ROOT = os.path.join(os.path.dirname(__file__), "..", "..")


def run(*args, cwd=None, timeout=60):
    """The command with a time limit: a hang is a failure, not a stuck test run."""
    return subprocess.run([ACUITY, *map(str, args)], capture_output=True, text=True, timeout=timeout, cwd=cwd)


def crashed(r):
    return r.returncode < 0 or r.returncode >= 128  # killed by a signal


TRIANGLE = struct.pack("<9f", 0, 0, 0, 1, 0, 0, 0, 1, 0) + struct.pack("<4H", 0, 1, 2, 0)


def triangle_doc(uri=None):
    """A valid one-triangle glTF; its buffer embedded, or at `uri`."""
    return {
        "asset": {"version": "2.0"},
        "buffers": [{"byteLength": 44, "uri": uri or "data:application/octet-stream;base64," + base64.b64encode(TRIANGLE).decode()}],
        "bufferViews": [{"buffer": 0, "byteOffset": 0, "byteLength": 36}, {"buffer": 0, "byteOffset": 36, "byteLength": 6}],
        "accessors": [{"bufferView": 0, "componentType": 5126, "count": 3, "type": "VEC3"},
                      {"bufferView": 1, "componentType": 5123, "count": 3, "type": "SCALAR"}],
        "meshes": [{"name": "tri", "primitives": [{"attributes": {"POSITION": 0}, "indices": 1}]}],
        "nodes": [{"name": "tri", "mesh": 0}],
        "scenes": [{"nodes": [0]}],
    }


def save(path, doc):
    path.parent.mkdir(parents=True, exist_ok=True)
    path.write_text(json.dumps(doc))
    return path


def python(code, timeout=60):
    """Runs code in a fresh interpreter (a crash there must not take the test run with it)."""
    env = dict(os.environ)
    return subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, timeout=timeout, env=env)


# --- 1: reads outside the asset folder -------------------------------------------------------

def test_lodgen_never_reads_outside_the_asset_folder(tmp_path):
    """A buffer uri of ../secret, %2e%2e/secret, an absolute path or a file: URL is refused, and
    the secret's bytes appear in no output."""
    secret = tmp_path / "secret" / "key.bin"
    secret.parent.mkdir()
    secret.write_bytes(TRIANGLE)  # a valid buffer: only the confinement can refuse it
    assets = tmp_path / "assets"
    for name, uri, why in [("up", "../secret/key.bin", "leaves the asset folder"),
                           ("escaped", "%2e%2e/secret/key.bin", "%-escapes"),
                           ("absolute", str(secret), "absolute path"),
                           ("url", "file://" + str(secret), "scheme")]:
        gltf = save(assets / f"{name}.gltf", triangle_doc(uri))
        out = tmp_path / f"{name}.glb"
        r = run("lodgen", gltf, "-o", out, "-q")
        assert r.returncode != 0 and why in r.stderr, (name, r.stderr)
        assert not out.exists()
    # Given by bare name from inside the folder, an absolute uri is still refused.
    r = run("lodgen", "absolute.gltf", "-o", tmp_path / "bare.glb", "-q", cwd=assets)
    assert r.returncode != 0 and "absolute path" in r.stderr
    # A file only in the current folder is not found (no "." fallback).
    save(assets / "cwd.gltf", triangle_doc("only_here.bin"))
    (tmp_path / "only_here.bin").write_bytes(TRIANGLE)
    r = run("lodgen", assets / "cwd.gltf", "-o", tmp_path / "cwd.glb", "-q", cwd=tmp_path)
    assert r.returncode != 0 and "only_here.bin" in r.stderr
    # --asset-root widens the folder explicitly.
    r = run("lodgen", assets / "up.gltf", "-o", tmp_path / "root.glb", "-q", "--asset-root", tmp_path, "--levels", "1")
    assert r.returncode == 0, r.stderr


def test_simulate_and_profile_are_confined_too(tmp_path):
    (tmp_path / "secret.bin").write_bytes(TRIANGLE)
    gltf = save(tmp_path / "assets" / "s.gltf", triangle_doc("../secret.bin"))
    for args in (["simulate", gltf, "--res", "32", "--seconds", "0.1", "--no-plots", "-o", tmp_path / "out"],
                 ["profile", gltf, "-o", tmp_path / "s.acuity"]):
        r = run(*args)
        assert r.returncode != 0 and "leaves the asset folder" in r.stderr, r.stderr
    assert not (tmp_path / "s.acuity").exists()


# --- 2: accessor offsets near 2^64, through Python ---------------------------------------------

def test_python_lodgen_survives_a_wrapping_byte_offset(tmp_path):
    for count in (3, 1 << 40):
        doc = triangle_doc()
        doc["accessors"][0]["byteOffset"] = 2 ** 64 - 36
        doc["accessors"][0]["count"] = count
        gltf = save(tmp_path / f"wrap{count}.gltf", doc)
        r = python(f"import acuity.lodgen as L\ntry:\n L.build({str(gltf)!r}, {str(tmp_path / 'o.glb')!r})\n"
                   f"except ValueError as e:\n print('refused:', e)")
        assert r.returncode == 0, r.stderr  # the interpreter did not die
        assert "refused:" in r.stdout and "overflows" in r.stdout, r.stdout
        assert not (tmp_path / "o.glb").exists()


# --- 3, 4, 6, 7: graphs, levels, JSON depth ----------------------------------------------------

@pytest.mark.parametrize("name,nodes,why", [
    ("cycle", [{"children": [1]}, {"children": [0], "mesh": 0}], "cycle"),
    ("self", [{"children": [0], "mesh": 0}], "its own child"),
    ("chain", [{"children": [i + 1]} for i in range(99999)] + [{"mesh": 0}], "max_node_depth"),
    ("fanout", [{"children": [1] * 64}, {"mesh": 0}], "twice"),
    ("dag", sum(([{"children": [2 * k + 1, 2 * k + 2]}, {"children": [2 * k + 2]}] for k in range(24)), []) + [{"mesh": 0}],
     "two parents"),
])
def test_hostile_node_graphs_fail_cleanly(tmp_path, name, nodes, why):
    doc = triangle_doc()
    doc["nodes"] = nodes
    gltf = save(tmp_path / f"{name}.gltf", doc)
    for args in (["lodgen", gltf, "-o", tmp_path / "o.glb", "-q"],
                 ["simulate", gltf, "--res", "32", "--seconds", "0.1", "--no-plots", "-o", tmp_path / "out"]):
        r = run(*args)
        assert not crashed(r) and r.returncode != 0, (args[0], r.returncode, r.stderr)
        assert why in r.stderr, (args[0], r.stderr)


def test_msft_lod_with_100000_ids_is_refused_before_rendering(tmp_path):
    doc = triangle_doc()
    doc["nodes"].append({"mesh": 0})
    doc["nodes"][0]["extensions"] = {"MSFT_lod": {"ids": [1] * 100000}}
    gltf = save(tmp_path / "lods.gltf", doc)
    for args in (["simulate", gltf, "--res", "32", "--seconds", "0.1", "--no-plots", "-o", tmp_path / "out"],
                 ["profile", gltf, "-o", tmp_path / "p.acuity"]):
        r = run(*args, timeout=30)
        assert r.returncode != 0 and "max_levels" in r.stderr, r.stderr


def test_json_nested_100000_deep_is_refused(tmp_path):
    text = json.dumps(triangle_doc())[:-1] + ',"extras":' + "[" * 100000 + "]" * 100000 + "}"
    gltf = tmp_path / "deep.gltf"
    gltf.write_text(text)
    r = run("lodgen", gltf, "-o", tmp_path / "o.glb", "-q")
    assert not crashed(r) and r.returncode != 0 and "max_json_depth" in r.stderr, (r.returncode, r.stderr)


# --- 5: image bombs ----------------------------------------------------------------------------

def png(width, height):
    """A real greyscale PNG of zeros: tiny compressed, width x height pixels decoded."""
    def chunk(kind, data):
        return struct.pack(">I", len(data)) + kind + data + struct.pack(">I", zlib.crc32(kind + data))
    z = zlib.compressobj(9)
    row = bytes(width + 1)
    body = b"".join(z.compress(row) for _ in range(height)) + z.flush()
    return (b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", struct.pack(">IIBBBBB", width, height, 8, 0, 0, 0, 0)) +
            chunk(b"IDAT", body) + chunk(b"IEND", b""))


def test_a_12000_square_png_is_refused_from_its_header(tmp_path):
    bomb = png(12000, 12000)
    assert len(bomb) < 1 << 20
    (tmp_path / "bomb.png").write_bytes(bomb)
    doc = triangle_doc()
    doc["images"] = [{"uri": "bomb.png"}]
    doc["textures"] = [{"source": 0}]
    doc["materials"] = [{"pbrMetallicRoughness": {"baseColorTexture": {"index": 0}}}]
    doc["meshes"][0]["primitives"][0]["material"] = 0
    gltf = save(tmp_path / "bomb.gltf", doc)
    r = run("lodgen", gltf, "-o", tmp_path / "o.glb", "-q", timeout=20)
    assert r.returncode != 0 and "max_image_pixels" in r.stderr and "12000 x 12000" in r.stderr, r.stderr
    # The same six times, used by no material: never decoded, so the mesh goes through.
    doc = triangle_doc()
    doc["images"] = [{"uri": "bomb.png"}] * 6
    r = run("lodgen", save(tmp_path / "unused.gltf", doc), "-o", tmp_path / "u.glb", "-q", "--levels", "1", timeout=20)
    assert r.returncode == 0, r.stderr


# --- 8, 16: outputs ----------------------------------------------------------------------------

def test_outputs_are_regular_files_and_never_an_input(tmp_path):
    mesh = tmp_path / "e.off"
    mesh.write_text("OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n")
    before = mesh.read_bytes()
    r = run("lodgen", mesh, "-o", mesh, "-q")
    assert r.returncode != 0 and mesh.read_bytes() == before
    gltf = save(tmp_path / "c.gltf", triangle_doc())
    before = gltf.read_bytes()
    for args in (["lodgen", gltf, "-o", gltf, "-q"], ["profile", gltf, "-o", gltf]):
        r = run(*args)
        assert r.returncode != 0 and "is the input" in r.stderr, r.stderr
        assert gltf.read_bytes() == before
    r = run("lodgen", mesh, "-o", tmp_path / "e.obj", "-q")
    assert r.returncode != 0 and ".glb" in r.stderr
    # A device or FIFO is never replaced by a regular file.
    fifo = tmp_path / "out.glb"
    os.mkfifo(fifo)
    r = run("lodgen", mesh, "-o", fifo, "-q")
    assert r.returncode != 0 and "not a regular file" in r.stderr
    assert stat.S_ISFIFO(os.lstat(fifo).st_mode)
    # (-o /dev/null is refused by the same check, tests/test_hostile.cpp; a test must not risk the
    # machine's /dev/null on a regression, so the command is tried on a FIFO of its own.)
    r = run("profile", gltf, "-o", fifo)
    assert r.returncode != 0 and "not a regular file" in r.stderr
    assert stat.S_ISFIFO(os.lstat(fifo).st_mode)
    # An unwritable or missing folder is found before the work starts.
    r = run("lodgen", mesh, "-o", tmp_path / "no" / "such" / "x.glb", "-q")
    assert r.returncode != 0 and "does not exist" in r.stderr
    scene = tmp_path / "grid.gltf"
    textured_gltf(scene)
    r = run("simulate", scene, "--res", "32", "--seconds", "0.1", "--no-plots", "-o", mesh / "out")
    assert r.returncode != 0 and "not a directory" in r.stderr and "assets:" not in r.stdout, (r.stdout, r.stderr)


# --- 9, 18: FIFOs and directories as inputs ------------------------------------------------------

def test_fifos_and_directories_fail_at_once(tmp_path):
    fifo = tmp_path / "pipe"
    os.mkfifo(fifo)
    r = run("inspect", fifo, timeout=20)
    assert r.returncode != 0 and "FIFO" in r.stderr
    r = run("inspect", tmp_path, timeout=20)
    assert r.returncode != 0 and "directory" in r.stderr and "max_size" not in r.stderr
    scene = tmp_path / "grid.gltf"
    textured_gltf(scene)
    for option in ("--gaze", "--head"):
        r = run("simulate", scene, "--res", "32", "--seconds", "0.1", option, fifo, "--no-plots", "-o", tmp_path / "out",
                timeout=60)
        assert r.returncode != 0 and "FIFO" in r.stderr, r.stderr
    save(tmp_path / "f.gltf", triangle_doc("pipe"))
    r = run("lodgen", tmp_path / "f.gltf", "-o", tmp_path / "f.glb", "-q", timeout=20)
    assert r.returncode != 0 and "FIFO" in r.stderr, r.stderr


# --- 17: a byte order mark in a track ----------------------------------------------------------

def test_gaze_csv_with_a_byte_order_mark(tmp_path):
    scene = tmp_path / "grid.gltf"
    textured_gltf(scene)
    gaze = tmp_path / "gaze.csv"
    gaze.write_bytes(b"\xef\xbb\xbft,x,y,z\n0,0,0,-1\n10,0,0,-1\n")
    r = run("simulate", scene, "--res", "32", "--seconds", "0.2", "--gaze", gaze, "--no-plots", "--validate", "0",
            "--images", "0", "-o", tmp_path / "out", timeout=300)
    assert r.returncode == 0, r.stderr


# --- 19: no shell ------------------------------------------------------------------------------

def test_simulate_output_names_reach_no_shell(tmp_path):
    scene = tmp_path / "grid.gltf"
    textured_gltf(scene)
    for name in ("x'; touch PWNED; echo '", "bob's run"):
        out = tmp_path / name
        r = run("simulate", scene, "--res", "32", "--seconds", "0.2", "--validate", "0", "--images", "0", "-o", out,
                cwd=tmp_path, timeout=300)
        assert r.returncode == 0, r.stderr
        assert not (tmp_path / "PWNED").exists()
        assert (out / "summary.json").exists(), r.stdout
        # acuity runs no other program: the plots are left to the command it prints, the name quoted.
        assert not (out / "triangles.png").exists(), r.stdout
        quoted = "'" + str(out).replace("'", "'\\''") + "'"
        assert "plot_simulation.py " + quoted + "\n" in r.stdout, r.stdout


def test_no_system_or_popen_in_the_sources():
    """CI's grep: no shell anywhere in the project's C and C++ sources."""
    pattern = re.compile(r"\b(std::system|system|popen|execl?p?)\s*\(")
    found = []
    for top in ("scheduler", "io", "lodgen", "spectra", "bake", "sim", "tools", "bindings", "bench", "examples", "tests"):
        for dirpath, _, files in os.walk(os.path.join(ROOT, top)):
            for f in files:
                if f.endswith((".c", ".cpp", ".hpp", ".h")):
                    text = open(os.path.join(dirpath, f), encoding="utf-8", errors="replace").read()
                    text = re.sub(r"//.*|/\*.*?\*/", "", text, flags=re.S)
                    found += [f"{dirpath}/{f}: {m.group(0)}" for m in pattern.finditer(text)]
    assert found == []


# --- 20: NaN options ---------------------------------------------------------------------------

@pytest.mark.parametrize("command,option", [
    ("lodgen", "--reference-height"), ("lodgen", "--max-error"), ("lodgen", "--ratio"),
    ("simulate", "--saccade-speed"), ("simulate", "--seconds"), ("simulate", "--fov"), ("simulate", "--fps"),
    ("profile", "--tolerance"),
])
def test_nan_options_are_refused(tmp_path, command, option):
    gltf = save(tmp_path / "t.gltf", triangle_doc())
    out = tmp_path / ("o.glb" if command == "lodgen" else "o.acuity" if command == "profile" else "out")
    for value in ("nan", "inf"):
        r = run(command, gltf, "-o", out, option, value)
        assert r.returncode != 0 and "not a finite number" in r.stderr, (option, value, r.stderr)
    assert not out.exists()


# --- 10, 11, 12: the Python scheduler ----------------------------------------------------------

def test_python_profile_from_empty_bytes_raises():
    r = python("import acuity\ntry:\n acuity.Profile.from_bytes(b'')\nexcept ValueError as e:\n print('refused:', e)")
    assert r.returncode == 0 and "32-byte header" in r.stdout, (r.returncode, r.stdout, r.stderr)


def test_python_scheduler_is_all_or_nothing():
    import acuity
    from test_scheduler import make_profile
    c = acuity.SchedulerConfig()
    c.max_objects = 3
    s = acuity.Scheduler(c)
    s.add_profile(acuity.Profile.from_bytes(make_profile()))

    def rows(n):
        return (np.zeros(n, np.uint32), np.tile([0.0, 0.0, -5.0], (n, 1)), np.tile([0, 0, 0, 1.0], (n, 1)), np.ones(n))
    first = s.add_objects(*rows(2))
    with pytest.raises(ValueError, match="do not fit"):
        s.add_objects(*rows(2))  # one would fit: none may be added
    bad = rows(1)
    with pytest.raises(IndexError, match="profile 4"):
        s.add_objects(np.array([4], np.uint32), *bad[1:])
    third = s.add_objects(*rows(1))  # the one free slot is still free
    assert len(set(first) | set(third)) == 3
    s.remove_objects(third)
    gone = third
    for call in (lambda: s.set_transforms(gone, *rows(1)[1:]),
                 lambda: s.set_velocities(gone, np.zeros((1, 3))),
                 lambda: s.set_clamps(int(gone[0]), 0, 1),
                 lambda: s.set_bias(int(gone[0]), 0.5),
                 lambda: s.remove_objects(gone),
                 lambda: s.set_transforms(np.array([first[0], 999], np.uint32), *rows(2)[1:])):
        with pytest.raises(IndexError, match="does not exist"):
            call()
