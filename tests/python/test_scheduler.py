"""acuity.Scheduler and profiles from Python, numpy in and out."""
import numpy as np
import pytest

import acuity


def make_profile(levels=5, orientations=8, bands=8):
    dirs = np.array([[1, 0, 0], [-1, 0, 0], [0, 1, 0], [0, -1, 0], [0, 0, 1], [0, 0, -1]], dtype=np.float32)
    band = 2.0 * 2.0 ** np.arange(bands, dtype=np.float32)
    k = np.arange(1, levels, dtype=np.float32)[:, None, None, None]
    b = np.arange(bands, dtype=np.float32)[None, None, None, :]
    lost = 0.2 / (1 + np.exp(-2 * (b - bands + 1.3 * k))) * np.ones((1, len(dirs), orientations, 1), np.float32)
    features = np.ones((levels, len(dirs), orientations), np.float32) * (256.0 / 2.0 ** np.arange(levels))[:, None, None]
    return acuity.spectra.encode_profile(
        sphere=[0, 0, 0, 1], triangles=[10000 >> i for i in range(levels)],
        geometric_error=[0.002 * (2 ** i - 1) for i in range(levels)], view_directions=dirs,
        orientations=np.arange(orientations) * 180.0 / orientations, bands=band, lost=lost, features=features)


def frame_looking_forward():
    f = acuity.Frame()
    g = acuity.Gaze()
    g.valid = True
    f.eyes = [acuity.Eye()]
    f.gaze = [g]
    f.dt = 1 / 90
    return f


def test_profile_round_trip(tmp_path):
    data = make_profile()
    p = acuity.Profile.from_bytes(data)
    assert (p.level_count, p.view_count, p.orientation_count, p.band_count) == (5, 6, 8, 8)
    assert p.lost.shape == (4, 6, 8, 8)
    assert p.triangles == [10000, 5000, 2500, 1250, 625]
    path = tmp_path / "a.acuity"
    path.write_bytes(p.to_bytes())
    assert acuity.Profile.load(str(path)).to_bytes() == data
    with pytest.raises(ValueError, match="checksum|too small|magic"):
        acuity.Profile.from_bytes(data[:-9] + b"\x00" * 9)
    # acuity::io's one error, a ValueError naming the path and the reason.
    assert issubclass(acuity.FileError, ValueError)
    with pytest.raises(acuity.FileError, match="no-such.acuity: No such file"):
        acuity.Profile.load(str(tmp_path / "no-such.acuity"))
    with pytest.raises(acuity.FileError, match="is a directory, not a regular file"):
        acuity.Profile.load(str(tmp_path))


def test_profile_detail_round_trip():
    """The optional Detail section: absent unless given, decoded as written (areas rounded up)."""
    assert acuity.Profile.from_bytes(make_profile()).detail is None
    lost_shape = (4, 6, 8, 8)
    area = np.full(lost_shape, 0.25, np.float32)
    offset = np.full(lost_shape, -0.25, np.float32)
    dirs = np.array([[1, 0, 0], [-1, 0, 0], [0, 1, 0], [0, -1, 0], [0, 0, 1], [0, 0, -1]], dtype=np.float32)
    data = acuity.spectra.encode_profile(
        sphere=[0, 0, 0, 1], triangles=[10000 >> i for i in range(5)], geometric_error=[0.002 * i for i in range(5)],
        view_directions=dirs, orientations=np.arange(8) * 22.5, bands=2.0 * 2.0 ** np.arange(8, dtype=np.float32),
        lost=np.full(lost_shape, 0.01, np.float32), features=np.zeros((5, 6, 8), np.float32),
        detail_area=area, detail_offset=offset)
    a, o, t = acuity.Profile.from_bytes(data).detail
    assert a.shape == lost_shape and np.all(a == 0.25) and np.all(o == -0.25) and np.all(t == 0)
    with pytest.raises(ValueError, match="one value per lost value"):
        acuity.spectra.encode_profile(
            sphere=[0, 0, 0, 1], triangles=[2, 1], geometric_error=[0, 0.1], view_directions=dirs[:1],
            orientations=[0], bands=[2], lost=[0.1], features=[0, 0], detail_area=[0.1, 0.2], detail_offset=[0, 0])


def test_area_law_reads_the_extent():
    """SchedulerConfig.area_law (on by default): with a Detail section the Default model's levels are
    at least as coarse as with the law off (the extents here are small: every band's threshold rises),
    and coarser somewhere; off, the section changes nothing."""
    dirs = np.array([[1, 0, 0], [-1, 0, 0], [0, 1, 0], [0, -1, 0], [0, 0, 1], [0, 0, -1]], dtype=np.float32)
    shape = (4, 6, 8, 8)
    band = 2.0 * 2.0 ** np.arange(8, dtype=np.float32)
    lost = 0.2 / (1 + np.exp(-2 * (np.arange(8)[None, None, None, :] - 8 + 1.3 * np.arange(1, 5)[:, None, None, None])))
    data = acuity.spectra.encode_profile(
        sphere=[0, 0, 0, 1], triangles=[10000 >> i for i in range(5)], geometric_error=[0.002 * i for i in range(5)],
        view_directions=dirs, orientations=np.arange(8) * 22.5, bands=band,
        lost=np.broadcast_to(lost, shape).astype(np.float32), features=np.zeros((5, 6, 8), np.float32),
        detail_area=np.full(shape, 0.001, np.float32), detail_offset=np.zeros(shape, np.float32))
    assert acuity.SchedulerConfig().area_law is True
    z = -np.geomspace(2, 200, 32).astype(np.float32)
    levels = {}
    for law in (True, False):
        config = acuity.SchedulerConfig()
        config.max_objects = 64
        config.area_law = law
        s = acuity.Scheduler(config)
        pid = s.add_profile(acuity.Profile.from_bytes(data))
        pos = np.stack([np.zeros_like(z), np.zeros_like(z), z], axis=1)
        ids = s.add_objects(np.full(len(z), pid), pos, np.tile([0, 0, 0, 1], (len(z), 1)).astype(np.float32),
                            np.ones(len(z)))
        s.run_frame(frame_looking_forward())
        levels[law] = s.levels(ids)
    assert np.all(levels[True] >= levels[False]) and np.any(levels[True] > levels[False])


def objects_in_a_row(z):
    """A scheduler of 64 slots with one object of make_profile() at each depth z [m] straight ahead."""
    config = acuity.SchedulerConfig()
    config.max_objects = 64
    s = acuity.Scheduler(config)
    pid = s.add_profile(acuity.Profile.from_bytes(make_profile()))
    pos = np.stack([np.zeros_like(z), np.zeros_like(z), z], axis=1)
    rot = np.tile([0, 0, 0, 1], (len(z), 1)).astype(np.float32)
    return s, s.add_objects(np.full(len(z), pid), pos, rot, np.ones(len(z)))


def test_levels_coarsen_with_distance():
    z = -np.geomspace(2, 2000, 40)
    s, ids = objects_in_a_row(z)
    s.run_frame(frame_looking_forward())
    levels = s.levels(ids)
    assert levels.dtype == np.uint8 and levels.shape == (40,)
    assert np.all(np.diff(levels.astype(int)) >= 0)
    assert levels[0] < levels[-1] == 4
    assert s.stats["triangles"] == sum(10000 >> int(l) for l in levels)
    e = s.explain(int(ids[10]))
    assert e["level"] == levels[10]
    assert e["distance_m"] == pytest.approx(-z[10], rel=1e-5)
    assert len(e["levels"]) == 5


def test_stats_count_objects_at_rest():
    # A still eye over still objects: their memos decide them at rest within a few frames (rests
    # are set a block in eight frames); an eye that reports a velocity cannot rest.
    s, ids = objects_in_a_row(-np.geomspace(2, 200, 64))
    f = frame_looking_forward()
    s.run_frame(f)
    assert s.stats["at_rest"] == 0  # no rest set yet
    levels = s.levels(ids)
    for _ in range(16):
        s.run_frame(f)
    assert s.stats["at_rest"] == 64
    assert np.array_equal(s.levels(ids), levels)
    assert s.stats["triangles"] == sum(10000 >> int(l) for l in levels)
    eye = f.eyes[0]
    eye.velocity = [0.0, 0.0, -0.01]
    f.eyes = [eye]
    s.run_frame(f)
    assert s.stats["at_rest"] == 0


def test_bad_input_is_flagged_not_fatal():
    s = acuity.Scheduler()
    pid = s.add_profile(acuity.Profile.from_bytes(make_profile()))
    ids = s.add_objects([pid, pid], [[0, 0, -10], [np.nan, 0, -10]], [[0, 0, 0, 1]] * 2, [1, 1])
    s.run_frame(frame_looking_forward())
    flags = s.flags(ids)
    assert not flags[0] & acuity.FLAG_INVALID_INPUT
    assert flags[1] & acuity.FLAG_INVALID_INPUT
    assert s.levels(ids)[1] == 0
    with pytest.raises(ValueError, match="position"):
        s.add_objects([pid], [[0, 0]], [[0, 0, 0, 1]], [1])
    with pytest.raises(IndexError):
        s.levels([9999])


def test_tabulated_is_the_default_and_never_coarser_than_exact():
    assert acuity.SchedulerConfig().evaluation == acuity.Evaluation.tabulated
    assert "Evaluation" in acuity.__all__
    rng = np.random.default_rng(4)
    n = 300
    z = -np.geomspace(1.5, 400, n)
    pos = np.stack([rng.uniform(-0.6, 0.6, n) * -z, rng.uniform(-0.4, 0.4, n) * -z, z], axis=1)
    rot = np.tile([0, 0, 0, 1], (n, 1)).astype(np.float32)
    vel = rng.normal(0, 3, (n, 3)).astype(np.float32)
    levels = {}
    for evaluation in (acuity.Evaluation.tabulated, acuity.Evaluation.exact):
        config = acuity.SchedulerConfig()
        config.max_objects = n
        config.evaluation = evaluation
        s = acuity.Scheduler(config)
        pid = s.add_profile(acuity.Profile.from_bytes(make_profile()))
        ids = s.add_objects(np.full(n, pid), pos, rot, np.ones(n))
        s.set_velocities(ids, vel)
        s.run_frame(frame_looking_forward())
        levels[evaluation] = s.levels(ids).astype(int)
    tab, exact = levels[acuity.Evaluation.tabulated], levels[acuity.Evaluation.exact]
    assert np.all(tab <= exact)                      # conservative
    assert np.mean(tab != exact) <= 0.02             # and close (the C++ test pins 0.5% on 100 000 decisions)
    assert len(set(exact)) >= 3                      # the scene spans several levels


def test_a_tabulated_bias_decides_as_that_quality():
    """Objects of bias 2 listed in tabulated_biases read the tables a quality-2 scheduler reads."""
    rng = np.random.default_rng(5)
    n = 300
    z = -np.geomspace(1.5, 400, n)
    pos = np.stack([rng.uniform(-0.6, 0.6, n) * -z, rng.uniform(-0.4, 0.4, n) * -z, z], axis=1)
    rot = np.tile([0, 0, 0, 1], (n, 1)).astype(np.float32)
    assert list(acuity.SchedulerConfig().tabulated_biases) == [0, 0, 0]

    def levels(quality=1.0, bias=1.0, tabulated=(0, 0, 0), evaluation=acuity.Evaluation.tabulated):
        config = acuity.SchedulerConfig()
        config.max_objects = n
        config.quality = quality
        config.tabulated_biases = list(tabulated)
        config.evaluation = evaluation
        s = acuity.Scheduler(config)
        pid = s.add_profile(acuity.Profile.from_bytes(make_profile()))
        ids = s.add_objects(np.full(n, pid), pos, rot, np.ones(n))
        for i in ids:
            s.set_bias(int(i), bias)
        s.run_frame(frame_looking_forward())
        return s.levels(ids).astype(int)

    biased = levels(bias=2.0, tabulated=(2.0, 0, 0))
    assert np.array_equal(biased, levels(quality=2.0))
    assert np.all(biased <= levels(bias=2.0, evaluation=acuity.Evaluation.exact))
    assert np.any(biased > levels())  # the bias did coarsen


def test_table_bytes_per_profile():
    """What a profile's tables cost: none evaluated exactly; a hysteresis margin and each listed bias
    add a set as large as the first."""
    def table_bytes(**fields):
        config = acuity.SchedulerConfig()
        config.max_objects = 1
        for name, value in fields.items():
            setattr(config, name, value)
        s = acuity.Scheduler(config)
        pid = s.add_profile(acuity.Profile.from_bytes(make_profile()))
        with pytest.raises(IndexError, match="profile 1 was not added"):
            s.table_bytes(pid + 1)
        with pytest.raises(IndexError):
            s.table_bytes(-1)
        return s.table_bytes(pid)

    one_set = table_bytes()
    assert one_set > 0
    assert table_bytes(evaluation=acuity.Evaluation.exact) == 0
    assert table_bytes(hysteresis_margin=0.3) == 2 * one_set
    assert table_bytes(tabulated_biases=[2.0, 0, 0]) == 2 * one_set
    assert table_bytes(tabulated_biases=[2.0, 0.5, 0], hysteresis_margin=0.3) == 6 * one_set


class FreshObjects:
    """n objects ahead (1.5-400 m, unturned, moving a little), of the profiles in turn: schedulers
    of those profiles, and the levels the objects get in a frame where they are fresh (their level
    at once)."""

    def __init__(self, seed, n, profiles):
        rng = np.random.default_rng(seed)
        z = -np.geomspace(1.5, 400, n)
        self.n, self.profiles = n, profiles
        self.pos = np.stack([rng.uniform(-0.6, 0.6, n) * -z, rng.uniform(-0.4, 0.4, n) * -z, z], axis=1)
        self.rot = np.tile([0, 0, 0, 1], (n, 1)).astype(np.float32)
        self.vel = rng.normal(0, 3, (n, 3)).astype(np.float32)

    def scheduler(self, evaluation=acuity.Evaluation.tabulated, deferred=False):
        config = acuity.SchedulerConfig()
        config.max_objects = self.n
        config.evaluation = evaluation
        s = acuity.Scheduler(config)
        for p in self.profiles:
            s.add_profile(p, deferred=deferred)
        return s

    def levels(self, s):
        ids = s.add_objects(np.arange(self.n) % len(self.profiles), self.pos, self.rot, np.ones(self.n))
        s.set_velocities(ids, self.vel)
        s.run_frame(frame_looking_forward())
        out = s.levels(ids).astype(int)
        s.remove_objects(ids)
        return out


def test_deferred_tables_made_on_worker_threads():
    """A profile added deferred decides as exact evaluation does until its tables, made on worker
    threads while frames run, are installed; then as a profile added with its tables."""
    from concurrent.futures import ThreadPoolExecutor
    n = 2000  # moving: a few decisions where the tables are finer than exact (4 at this seed)
    scene = FreshObjects(7, n, [acuity.Profile.from_bytes(make_profile(levels=k)) for k in (5, 4)])
    scheduler, levels = scene.scheduler, scene.levels
    built, exact, deferred = scheduler(), scheduler(acuity.Evaluation.exact), scheduler(deferred=True)
    want_built, want_exact = levels(built), levels(exact)
    assert np.any(want_built != want_exact)  # the two paths tell apart here
    assert deferred.table_bytes(0) == deferred.table_bytes(1) == 0
    with ThreadPoolExecutor(2) as pool:
        made = [pool.submit(deferred.make_tables, pid) for pid in (0, 1)]
        assert np.array_equal(levels(deferred), want_exact)  # frames while the tables are made
        made = [m.result() for m in made]
    assert isinstance(made[0], acuity.ProfileTables) and made[0].nbytes == built.table_bytes(0)
    with pytest.raises(ValueError, match="another profile"):
        deferred.install_tables(1, made[0])
    deferred.install_tables(0, made[0])
    assert not made[0] and made[0].nbytes == 0
    mixed = levels(deferred)
    odd = np.arange(n) % 2 == 1
    assert np.array_equal(mixed[~odd], want_built[~odd]) and np.array_equal(mixed[odd], want_exact[odd])
    deferred.install_tables(1, made[1])
    assert np.array_equal(levels(deferred), want_built)
    assert deferred.table_bytes(1) == built.table_bytes(1)
    with pytest.raises(ValueError, match="keeps no tables"):
        exact.make_tables(0)


def test_view_tables_made_as_wanted():
    """A deferred profile's tables made one view at a time, those wanted_tables() lists: the objects
    decide exactly until then, and as with every table after; each view is listed once, and the
    tables held are those views' (fewer bytes than every view's). drop_idle_tables frees them."""
    # Unturned objects ahead: a few of the profile's views are seen.
    scene = FreshObjects(8, 1500, [acuity.Profile.from_bytes(make_profile(levels=5))])
    scheduler, levels = scene.scheduler, scene.levels
    built, exact, lazy = scheduler(), scheduler(acuity.Evaluation.exact), scheduler(deferred=True)
    assert np.array_equal(levels(lazy), levels(exact))
    wanted = lazy.wanted_tables()
    assert wanted and len(set(wanted)) == len(wanted) and all(p == 0 for p, _ in wanted)
    assert lazy.wanted_tables() == []  # each listed once
    for p, view in wanted:
        lazy.install_tables(p, lazy.make_tables(p, view))
    assert np.array_equal(levels(lazy), levels(built))
    assert lazy.wanted_tables() == []
    one_view = lazy.make_tables(0, wanted[0][1])
    assert 0 < lazy.table_bytes(0) == len(wanted) * one_view.nbytes < built.table_bytes(0)
    with pytest.raises(ValueError, match="has tables of their views"):
        lazy.install_tables(0, one_view)
    with pytest.raises(ValueError, match="view 99"):
        lazy.make_tables(0, 99)
    # Dropped when idle: kept while read within the frames given; with 0 all go, the objects decide
    # exactly again and their views are listed again.
    held = lazy.table_bytes(0)
    assert lazy.drop_idle_tables(1000) == 0 and lazy.table_bytes(0) == held
    assert lazy.drop_idle_tables(0) == held and lazy.table_bytes(0) == 0
    assert np.array_equal(levels(lazy), levels(exact))
    assert sorted(lazy.wanted_tables()) == sorted(wanted)


@pytest.mark.parametrize("hz", [72, 90, 120])
def test_hysteresis_and_wait_in_seconds_take_the_same_time_at_any_rate(hz):
    """hysteresis_seconds and max_coarsen_wait_seconds sum dt: 0.1 s + 0.3 s is 0.4 s at every rate;
    the frame counts (aliases) apply only while the seconds are 0."""
    def frames_to_coarsen(config):
        config.max_objects = 4
        config.saccade_speed = 200  # gating on; the gaze stays still
        s = acuity.Scheduler(config)
        pid = s.add_profile(acuity.Profile.from_bytes(make_profile()))
        ids = s.add_objects([pid], [[0, 0, -2]], [[0, 0, 0, 1]], [1])
        s.set_velocities(ids, [[0, 0, 0]])
        f = frame_looking_forward()
        f.dt = 1 / hz
        s.run_frame(f)
        near = s.levels(ids)[0]
        s.set_transforms(ids, [[0, 0, -500]], [[0, 0, 0, 1]], [1])
        for n in range(1, 400):
            s.run_frame(f)
            if s.levels(ids)[0] != near:
                return n
        return None

    config = acuity.SchedulerConfig()
    assert (config.hysteresis_seconds, config.max_coarsen_wait_seconds) == (0, 0)
    config.hysteresis_seconds = 0.1
    config.max_coarsen_wait_seconds = 0.3
    config.hysteresis_frames, config.max_coarsen_wait = 50, 50  # ignored
    n = frames_to_coarsen(config)
    assert 0.4 * (1 - 1e-4) <= n / hz < 0.4 + 1 / hz
    frames = acuity.SchedulerConfig()
    frames.hysteresis_frames, frames.max_coarsen_wait = 4, 6
    assert frames_to_coarsen(frames) == 10


def test_views_beyond_the_eyes_get_their_own_levels():
    """A shadow map's light view (orthographic, looking down) gives an object behind the eye a level
    from its texel footprint; a finer map a finer level; a class no view named the coarsest."""
    config = acuity.SchedulerConfig()
    config.max_objects = 4
    config.max_views = 2
    config.max_view_classes = 2
    s = acuity.Scheduler(config)
    pid = s.add_profile(acuity.Profile.from_bytes(make_profile()))
    ids = s.add_objects([pid, pid], [[0, 0, 30], [0, 0, -5]], [[0, 0, 0, 1]] * 2, [1, 1])
    sun = acuity.View()
    sun.projection = acuity.ViewProjection.orthographic
    sun.orientation = [-0.70710678, 0, 0, 0.70710678]  # looking down
    sun.position = [0, 50, 0]
    sun.extent_m = [-40, 40, 40, -40]
    levels = {}
    for texels in (256, 4096):
        sun.viewport = [texels, texels]
        s.run_frame(frame_looking_forward(), views=[sun])
        levels[texels] = s.view_levels(0, ids)
        # orthographic: the same footprint wherever the object is (here, both the same object)
        assert levels[texels][0] == levels[texels][1]
        # level k's error (0.002 (2^k - 1) diameters of 2 m) covers at most 1 texel of 80 m / texels
        k = int(levels[texels][0])
        assert 0.004 * (2 ** k - 1) * texels / 80 <= 1
        assert k == 4 or 0.004 * (2 ** (k + 1) - 1) * texels / 80 > 1
    assert levels[4096][0] < levels[256][0]
    assert s.levels(ids)[0] > levels[4096][0]  # the eye, facing away, does not need it
    assert list(s.view_levels(1, ids)) == [4, 4]  # a class no view named: coarsest
    with pytest.raises(ValueError, match="max_views"):
        s.run_frame(frame_looking_forward(), views=[sun, sun, sun])
    bad = acuity.View()
    bad.view_class = 2
    with pytest.raises(ValueError, match="max_view_classes"):
        s.run_frame(frame_looking_forward(), views=[bad])
    with pytest.raises(ValueError, match="max_view_classes"):
        s.view_levels(2, ids)
