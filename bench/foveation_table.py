#!/usr/bin/python3
"""Runs bench_foveation and prints the docs/foveation.md speed table: CPU time per eye of
plan_foveation for each case, and its ratio to filling the same two maps with a constant in the
same run; then the once-per-configuration table build.

    /usr/bin/python3 bench/foveation_table.py build/bench/bench_foveation [--min-time 0.3]
"""
import google_benchmark

CASES = [("BM_plan_foveation/0/16", "2000×2000, 100°, gaze centred", 16),
         ("BM_plan_foveation/1/16", "gaze 20° right, 10° up", 16),
         ("BM_plan_foveation/2/16", "no gaze (64% of the tiles at full rate)", 16),
         ("BM_plan_foveation/3/16", "head turning at 100°/s", 16),
         ("BM_plan_foveation/0/8", "gaze centred", 8),
         ("BM_plan_foveation/0/32", "gaze centred", 32)]
BASELINE = "BM_fill_constant/16"


def main():
    args = google_benchmark.arguments(__doc__, "bench_foveation")
    scale = {"ns": 1e-3, "us": 1.0, "ms": 1e3, "s": 1e6}
    micros = {b["name"]: b["cpu_time"] * scale[b["time_unit"]]
              for b in google_benchmark.run(args.bench, args.min_time)}
    base = micros[BASELINE]
    print(f"| case | tile | µs per eye | vs. constant fill ({base:.2f} µs) |")
    print("|---|---|---|---|")
    for name, label, tile in CASES:
        ratio = f"{micros[name] / base:.0f}×" if tile == 16 else ""
        print(f"| {label} | {tile} | {micros[name]:.0f} | {ratio} |")
    print(f"\n`init_foveation_planner` (once per configuration): {micros['BM_init_planner'] / 1e3:.1f} ms.")


if __name__ == "__main__":
    main()
