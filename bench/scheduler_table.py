#!/usr/bin/python3
"""Runs bench_scheduler and prints the docs/benchmarks.md table: milliseconds per frame at 1k..1M
objects for each case, beside the plain distance loop of the same run, and the ratio to it; with
--setup instead what the tables cost to build: add_profile of one profile, and a scene of distinct
assets to its first frame.

    /usr/bin/python3 bench/scheduler_table.py build/bench/bench_scheduler [--min-time 0.2] [--setup]
"""
import google_benchmark
import sys

CASES = [  # (benchmark name prefix, label)
    ("BM_distance_loop", "plain distance loop (baseline)"),
    ("BM_scheduler/distance_rule", "scheduler, distance rule"),
    ("BM_scheduler/perceptual_static", "perceptual, still, tabulated"),
    ("BM_scheduler/perceptual_all_moving", "perceptual, all moving, tabulated"),
    ("BM_scheduler/perceptual_static_trembling", "perceptual, still, eye trembling ±0.2 mm, tabulated"),
    ("BM_scheduler/perceptual_static_restless", "perceptual, still, eye jumping ±0.5 m (no rests), tabulated"),
    ("BM_scheduler/perceptual_head_turning", "perceptual, still, head turning 30 deg/s, tabulated"),
    ("BM_scheduler/perceptual_head_sweeping", "perceptual, still, head sweeping ±15° at 30 deg/s, tabulated"),
    ("BM_scheduler/perceptual_head_track", "perceptual, still, head track (sway, turns, saccades), tabulated"),
    ("BM_scheduler/perceptual_static_exact", "perceptual, still, exact"),
    ("BM_scheduler/perceptual_all_moving_exact", "perceptual, all moving, exact"),
    ("BM_scheduler_2threads/perceptual_static", "perceptual, still, tabulated, 2 threads"),
    ("BM_scheduler_2threads/perceptual_all_moving", "perceptual, all moving, tabulated, 2 threads"),
]
SIZES = [1000, 10000, 100000, 1000000]


def main():
    args = google_benchmark.arguments(__doc__, "bench_scheduler", min_time="0.2",
                                      flags=[("--setup", "add_profile and the scene's first frame, not the frames")])
    if args.setup:
        pattern = "^(BM_add_profile/.*|BM_scene_ready/.*|BM_scene_walk/.*)$"
    else:
        pattern = "^((" + "|".join(name for name, _ in CASES) + ")/[0-9]+(/real_time)?)$"
    ms = {}  # (case, n) -> ms per frame (real time for the threaded cases, CPU time otherwise)
    setup = {}  # "tabulated" / "exact" -> (CPU ms per add_profile, table bytes)
    scene = {}  # "tabulated" / "exact" -> (assets, CPU ms to the first frame, tables MiB, profiles MiB)
    for b in google_benchmark.run(args.bench, args.min_time, pattern):
        name = b["run_name"].removesuffix("/real_time")
        if name.startswith("BM_add_profile/"):
            scale = {"ms": 1.0, "us": 1e-3, "ns": 1e-6}[b["time_unit"]]
            setup[name.split("/")[1]] = (b["cpu_time"] * scale, b.get("table_bytes", 0))
            continue
        if name.startswith("BM_scene_walk/"):
            scene["walk"] = (int(name.split("/")[1]), b["cpu_time"] * {"ms": 1.0, "us": 1e-3, "ns": 1e-6}[b["time_unit"]],
                             b["views_made"], b["held_KiB"], b["seen_KiB"], b["most_KiB"])
            continue
        if name.startswith("BM_scene_ready/"):
            scale = {"ms": 1.0, "us": 1e-3, "ns": 1e-6}[b["time_unit"]]
            _, evaluation, assets = name.split("/")[:3]
            scene[evaluation] = (int(assets), b["cpu_time"] * scale, b["tables_MiB"], b["profiles_MiB"],
                                 b.get("make_ms", 0), b.get("views", 0))
            continue
        case, n = name.rsplit("/", 1)
        scale = {"ms": 1.0, "us": 1e-3, "ns": 1e-6}[b["time_unit"]]
        t = b["real_time"] if "2threads" in case else b["cpu_time"]
        ms[(case, int(n))] = t * scale
    if args.setup:
        print_setup(setup, scene)
        return 0
    print("| case | " + " | ".join(f"{n:,} objects" for n in SIZES) + " |")
    print("|---|" + "---|" * len(SIZES))
    for case, label in CASES:
        cells = []
        for n in SIZES:
            t, base = ms.get((case, n)), ms.get((CASES[0][0], n))
            if t is None:
                cells.append("—")
            elif case == CASES[0][0]:
                cells.append(f"{t:.3f} ms")
            else:
                cells.append(f"{t:.3f} ms ({t / base:.0f}×)")
        print(f"| {label} | " + " | ".join(cells) + " |")
    scaling = []
    for label, one in (("still", "BM_scheduler/perceptual_static"), ("all moving", "BM_scheduler/perceptual_all_moving")):
        two = one.replace("BM_scheduler/", "BM_scheduler_2threads/")
        at = [f"{ms[(one, n)] / ms[(two, n)]:.1f}× at {n:,}" for n in SIZES if (one, n) in ms and (two, n) in ms]
        if at:
            scaling.append(f"{label} " + ", ".join(at))
    if scaling:
        print("\ntwo threads' speed over one thread's (this run): " + "; ".join(scaling))
    return 0


def print_setup(setup, scene):
    """The --setup lines: add_profile's time and tables, and each scene's time to its first frame."""
    if "tabulated" in setup and "exact" in setup:
        (tab, nbytes), (exact, _) = setup["tabulated"], setup["exact"]
        print(f"add_profile, one 14-view profile with a Pooled section (as `acuity profile` writes it): tabulated "
              f"{tab:.1f} ms ({nbytes / 1024:.0f} KiB of tables), exact {exact:.3f} ms ({tab / exact:.0f}× the exact path's)")
        if "tabulated_plain" in setup:  # the same profile without it: no area law, a moving row per orientation
            plain, plain_bytes = setup["tabulated_plain"]
            print(f"  without it (an older profile): tabulated {plain:.1f} ms ({plain / tab:.1f}× with it), "
                  f"{plain_bytes / 1024:.0f} KiB of tables")
    for evaluation in ("exact", "tabulated", "deferred", "views"):
        if evaluation not in scene:
            continue
        assets, t, tables, profiles, make_ms, views = scene[evaluation]
        head = (f"\nscene ready, {assets:,} distinct 32-view assets with a Pooled section, hysteresis margin 0.2, ")
        if evaluation == "views":
            print(f"{head}tables deferred, then those of the views the first frame saw objects from "
                  f"(wanted_tables: {views:.2f} per asset) made and installed on one thread and a second frame run: "
                  f"{t / 1000:.2f} s until every object decides through tables, {tables:.1f} MiB of tables "
                  f"({tables * 1024 / assets:.1f} KiB per asset), {make_ms:.1f} ms CPU per view made")
            continue
        what = "tabulated, tables deferred (add_profile_deferred)" if evaluation == "deferred" else evaluation
        print(f"{head}{what}: {t / 1000:.2f} s to the first frame, {tables:.1f} MiB of tables "
              f"({tables * 1024 / assets:.0f} KiB per asset), {profiles:.1f} MiB of profiles")
        if make_ms:
            print(f"  then make_tables + install_tables: {make_ms:.0f} ms CPU per asset, on whichever threads "
                  f"the host gives it ({assets * make_ms / 1000 / 60:.1f} min of CPU for all {assets:,})")
    if "walk" in scene:
        assets, t, made, held, seen, most = scene["walk"]
        print(f"\na walk, {assets} distinct 32-view assets over a 30 m disc, the eye once round a 15 m circle in 720 "
              f"frames, the views wanted made after each frame on one thread, drop_idle_tables(90) every 90: "
              f"at most {held:.1f} KiB of tables per asset held at once (one asset at most {most:.1f} KiB), "
              f"against {seen:.1f} KiB for every view seen; {made:.1f} views made per asset (some again after a drop), {t / 1000:.1f} s CPU in all")


if __name__ == "__main__":
    sys.exit(main())
