"""hello_lod.py — the same scene, loop and output as hello_lod.c, through the Python API (which wraps the
C++ API). Usage: PYTHONPATH=build/python /usr/bin/python3 examples/hello_lod.py PROFILE.acuity"""
import sys

import numpy as np

import acuity


def levels(profile_path):
    config = acuity.SchedulerConfig()
    config.max_objects = 20
    config.transition_seconds = 0.25
    s = acuity.Scheduler(config)
    p = s.add_profile(acuity.Profile.load(profile_path))
    i = np.arange(20)
    positions = np.stack([(i % 5 - 2) * 3.0, np.zeros(20), -(2.0 + i * 4.0)], axis=1)
    ids = s.add_objects(np.full(20, p), positions, np.tile([0, 0, 0, 1], (20, 1)), np.ones(20))
    s.set_velocities(ids, np.stack([np.where(i % 3 == 0, 2.0, 0.0), np.zeros(20), np.zeros(20)], axis=1))
    eye, gaze = acuity.Eye(), acuity.Gaze()
    gaze.valid = True
    frame = acuity.Frame()
    frame.eyes = [eye]
    frame.dt = 1 / 64
    for f in range(10):
        gaze.direction = [0.125 * f, 0.0, -1.0]
        frame.gaze = [gaze]
        s.begin_frame(frame)
        s.update(0, 10)
        s.update(10, 10)
        s.end_frame()
    previous, fades = s.transitions(ids)
    return s.levels(ids), previous, fades, s.stats["triangles"]


if __name__ == "__main__":
    lv, previous, fades, tri = levels(sys.argv[1])
    print("levels: " + " ".join(str(int(x)) for x in lv))
    print("fading:" + "".join(f" {i}:{int(p)}>{int(l)}@{float(f):.4f}" for i, (p, l, f) in enumerate(zip(previous, lv, fades)) if f < 1))
    print(f"triangles: {tri}")
