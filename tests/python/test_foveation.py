"""acuity.foveation from Python: shapes, the rule against numpy formulas, properties, errors."""
import math

import numpy as np
import pytest

import acuity
import acuity.foveation as fov


def eye(w=2000, h=2000, half_h=50.0, half_v=50.0):
    e = acuity.Eye()
    e.fov_deg = [-half_h, half_h, half_v, -half_v]
    e.viewport = [w, h]
    return e


def gaze(yaw=0.0, pitch=0.0):
    g = acuity.Gaze()
    y, p = math.radians(yaw), math.radians(pitch)
    g.direction = [math.sin(y) * math.cos(p), math.sin(p), -math.cos(y) * math.cos(p)]
    g.valid = True
    return g


def test_shapes_dtypes_and_values():
    p = fov.plan(eye(1920, 1080, 45, 30), gaze(5, 3), tile_px=16)
    assert p.shading_rate.shape == (68, 120, 2) and p.shading_rate.dtype == np.uint8
    assert p.mip_bias.shape == (68, 120) and p.mip_bias.dtype == np.float32
    assert set(np.unique(p.shading_rate)) <= {1, 2, 4}
    assert np.all(p.mip_bias >= 0) and np.all(np.isfinite(p.mip_bias))
    assert p.status == "ok" and p.tile_px == 16
    for tile, shape in ((8, (135, 240)), (32, (34, 60))):
        assert fov.plan(eye(1920, 1080, 45, 30), gaze(), tile_px=tile).mip_bias.shape == shape


def test_saves_more_than_half_centred_on_2000_over_100_degrees():
    p = fov.plan(eye(), gaze())
    assert p.saved > 0.5
    rates = p.shading_rate.astype(float)
    assert p.shaded == pytest.approx(np.sum(256.0 / (rates[..., 0] * rates[..., 1])))
    # The gaze's tile is full rate with no bias.
    r, c = int(p.origin_px[1] // 16), int(p.origin_px[0] // 16)
    assert tuple(p.shading_rate[r, c]) == (1, 1) and p.mip_bias[r, c] == 0


def test_the_row_through_the_gaze_against_numpy():
    """Geisler-Perry's cutoff at contrast 1/q, the pinhole's pixels per degree, Nyquist."""
    cfg = fov.FoveationConfig()
    cfg.model = "geisler-perry"
    p = fov.plan(eye(), gaze(), config=cfg, layers=0)
    f = 1000 / math.tan(math.radians(50))
    cols = np.arange(63, 125)
    u0 = (cols * 16.0 - 1000) / f                      # nearest tangent of each tile, right half
    uc, vc = u0 + 8 / f, (1000 - 63 * 16.0 + 8) / f    # row 62's centre
    theta = np.degrees(np.arctan(np.hypot(uc, vc)))
    e = theta - np.degrees(16 * math.sqrt(2) / 2 / f) - cfg.gaze_uncertainty_deg
    cutoff = 2.3 * math.log(64.0) / (0.106 * (np.maximum(e, 0) + 2.3))
    ppd_x = f * (1 + u0 ** 2) * math.pi / 180
    ratio = ppd_x / (2 * cutoff)
    expected = np.where(ratio >= 4, 4, np.where(ratio >= 2, 2, 1))
    expected[e <= cfg.foveal_radius_deg] = 1
    got = p.shading_rate[62, cols, 0]
    clear = (np.abs(ratio / 2 - 1) > 0.1) & (np.abs(ratio / 4 - 1) > 0.1)
    assert clear.sum() > 40
    np.testing.assert_array_equal(got[clear], expected[clear])
    bias = np.where(e <= cfg.foveal_radius_deg, 0, np.maximum(0, np.log2(np.minimum(ppd_x, ppd_x / np.sqrt(1 + u0 ** 2) * 1) / (2 * cutoff))))
    assert np.all(p.mip_bias[62, cols] <= bias + 1e-4)
    assert np.all(p.mip_bias[62, cols] >= bias - 0.1)


def test_never_finer_farther_out_along_rays():
    for g in (gaze(), gaze(30, -20), gaze(-60, 0)):
        p = fov.plan(eye(), g, tile_px=16, layers=0)
        ox, oy = p.origin_px
        s = np.arange(0, 4000, 0.5)
        for a in np.linspace(0, 2 * np.pi, 720, endpoint=False):
            x, y = ox + s * np.cos(a), oy + s * np.sin(a)
            inside = (x >= 0) & (y >= 0) & (x < 2000) & (y < 2000)
            if not inside.any():
                continue
            c, r = (x[inside] // 16).astype(int), (y[inside] // 16).astype(int)
            for values in (p.shading_rate[r, c, 0], p.shading_rate[r, c, 1], p.mip_bias[r, c]):
                assert np.all(np.diff(values.astype(float)) >= 0)


def test_no_gaze_invalid_eye_and_two_eyes():
    g = gaze(20, 0)
    g.valid = False
    p = fov.plan(eye(), g)
    assert p.status == "no-gaze" and p.origin_px == (1000.0, 1000.0)
    bad = eye()
    bad.fov_deg = [-50, float("nan"), 50, -50]
    q = fov.plan(bad, gaze())
    assert q.status == "invalid-eye"
    assert np.all(q.shading_rate == 1) and np.all(q.mip_bias == 0)
    assert q.layers["n_layers"] == 0
    left, right = eye(1920, 1920, 45, 45), eye(1920, 1920, 45, 45)
    left.fov_deg = [-55, 40, 45, -45]
    right.fov_deg = [-40, 55, 45, -45]
    a, b = fov.plan(left, gaze(8, 4)), fov.plan(right, gaze(-8, 4))
    np.testing.assert_array_equal(a.shading_rate, b.shading_rate[:, ::-1, :])
    assert not np.array_equal(a.shading_rate, fov.plan(left, gaze(-8, 4)).shading_rate)


def test_config_from_the_scheduler_and_layers():
    sc = acuity.SchedulerConfig()
    sc.model = "geisler-perry"
    sc.quality = 0.5
    cfg = fov.config_from(sc)
    assert cfg.model == "geisler-perry" and cfg.quality == 0.5
    a = fov.plan(eye(), gaze(), config=sc)
    b = fov.Planner(cfg).plan(eye(), gaze())
    np.testing.assert_array_equal(a.shading_rate, b.shading_rate)
    np.testing.assert_array_equal(a.mip_bias, b.mip_bias)
    # A stricter q saves less.
    sc.quality = 1.0
    assert a.saved < fov.plan(eye(), gaze(), config=sc).saved
    layers = fov.plan(eye(3840, 2160, 45, 30), gaze(), config=sc).layers  # q = 1
    assert layers["n_layers"] == 3
    assert layers["radius_deg"][0] < layers["radius_deg"][1] < layers["radius_deg"][2]
    assert layers["sampling"][0] == 1.0 and layers["speedup"] > 1.5
    # The MAR line stays below Geisler-Perry's 1 / f_c(e - 1 deg) (finest within 3.5 deg).
    e = np.linspace(0, 90, 901)
    mar = 0.106 * (np.where(e <= 3.5, 0, e - 1) + 2.3) / (2.3 * math.log(64))
    assert np.all(layers["omega0"] + layers["slope"] * e <= mar * (1 + 1e-6))


def test_errors():
    with pytest.raises(ValueError):
        fov.plan(eye(), gaze(), tile_px=12)
    cfg = fov.FoveationConfig()
    cfg.max_rate = 3
    with pytest.raises(ValueError):
        fov.plan(eye(), gaze(), config=cfg)
    with pytest.raises(ValueError):
        cfg.model = "nope"
    with pytest.raises(TypeError):
        fov.plan(eye(), gaze(), config=42)


# ---- acuity plan (the CLI) ------------------------------------------------------------------------
import os  # noqa: E402
import struct  # noqa: E402
import subprocess  # noqa: E402

ACUITY = os.environ.get("ACUITY_BIN", "")


def run_plan(*args):
    assert os.path.exists(ACUITY), "ACUITY_BIN must name the built acuity command"
    return subprocess.run([ACUITY, "plan", *map(str, args)], capture_output=True, text=True, timeout=300)


def test_cli_track_csv_and_picture(tmp_path):
    track = tmp_path / "gaze.csv"
    yaw = math.radians(10)
    track.write_text("t,x,y,z,confidence\n"
                     "0,0,0,-1,1\n"
                     f"0.02,{math.sin(yaw)},0,{-math.cos(yaw)},1\n"
                     "0.04,0,0,-1,0\n")
    csv, png = tmp_path / "saved.csv", tmp_path / "maps.png"
    res = run_plan("--display", "1000x800", "--fov", "90", "--gaze-track", track, "--fps", "50",
                   "--csv", csv, "--png", png, "--frame", "1", "--panel", "300")
    assert res.returncode == 0, res.stderr
    rows = [line.split(",") for line in csv.read_text().splitlines()]
    assert rows[0][:3] == ["frame", "time_s", "status"] and len(rows) == 4
    assert [r[2] for r in rows[1:]] == ["ok", "ok", "no-gaze"]
    # The same frames through the Python API.
    e = eye(1000, 800, 45, math.degrees(math.atan(math.tan(math.radians(45)) * 0.8)))
    g = gaze(10, 0)
    assert float(rows[2][7]) == pytest.approx(fov.plan(e, g, layers=0).saved, abs=1e-6)
    g.valid = False
    assert float(rows[3][7]) == pytest.approx(fov.plan(e, g, layers=0).saved, abs=1e-6)
    data = png.read_bytes()
    assert data[:8] == b"\x89PNG\r\n\x1a\n"
    width, height = struct.unpack(">II", data[16:24])
    assert width == 2 * 300 + 48 and height > 240


def test_cli_table_and_bad_input(tmp_path):
    res = run_plan("--table")
    assert res.returncode == 0, res.stderr
    line = next(l for l in res.stdout.splitlines() if l.startswith("| 2000x2000, 100 deg | centred"))
    assert float(line.split("|")[3].strip().rstrip("%")) > 50
    out = tmp_path / "x.csv"
    for args in (["--display", "12x"], ["--display", "0x100"], ["--gaze", "1"], ["--tile", "12"],
                 ["--gaze-track", tmp_path / "missing.csv"], ["--model", "nope"]):
        res = run_plan(*args, "--csv", out)
        assert res.returncode != 0, args
        assert not out.exists()
    track = tmp_path / "t.csv"
    track.write_text("t,x,y,z\n0,0,0,-1\n")
    res = run_plan("--gaze-track", track, "--csv", track)
    assert res.returncode != 0 and "overwrite" in res.stderr
    assert track.read_text() == "t,x,y,z\n0,0,0,-1\n"
