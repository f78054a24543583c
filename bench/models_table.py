#!/usr/bin/python3
"""Runs bench_models and prints the docs/benchmarks.md table: threshold evaluations per second of
each model (double and float, scalar and a batch of 4096), ns per evaluation, and the ratio to
Geisler-Perry's closed form measured in the same run; then the inverse, max_visible_frequency.

    /usr/bin/python3 bench/models_table.py build/bench/bench_models [--min-time 0.3]
"""
import google_benchmark

ORDER = [("geisler-perry", "geisler-perry (baseline)"), ("reddy", "reddy (step)"),
         ("default", "default (low-pass Daly × GP eccentricity)"), ("kelly-daly", "kelly-daly (band-pass)"),
         ("stela-csf", "stela-csf (two mechanisms, data-fitted)")]
COLUMNS = [("BM_threshold_scalar<double>", "double, scalar"), ("BM_threshold_scalar<float>", "float, scalar"),
           ("BM_threshold_batch<double>", "double, batch of 4096"), ("BM_threshold_batch<float>", "float, batch")]


def main():
    args = google_benchmark.arguments(__doc__, "bench_models")
    rate = {}  # (benchmark, model) -> evaluations per second
    for b in google_benchmark.run(args.bench, args.min_time):
        rate[(b["run_name"].rsplit("/", 1)[0], b["label"])] = b["items_per_second"]
    print("| model | " + " | ".join(label for _, label in COLUMNS) + " | ns/eval (double) | vs. baseline |")
    print("|---|" + "---|" * (len(COLUMNS) + 2))
    base = 1e9 / rate[(COLUMNS[0][0], "geisler-perry")]
    for model, label in ORDER:
        ns = 1e9 / rate[(COLUMNS[0][0], model)]
        ratio = ns / base
        vs = "1.00×" if model == "geisler-perry" else (f"{ratio:.2f}× slower" if ratio >= 1 else f"{1 / ratio:.2f}× faster")
        cells = [f"{rate[(bench, model)] / 1e6:.1f} M/s" for bench, _ in COLUMNS]
        print(f"| {label} | " + " | ".join(cells) + f" | {ns:.1f} | {vs} |")
    inverse = ", ".join(f"{model} {rate[('BM_max_visible_frequency', model)] / 1e6:.2f} M/s "
                        f"({1e9 / rate[('BM_max_visible_frequency', model)]:.0f} ns)" for model, _ in ORDER)
    print(f"\n`max_visible_frequency` (the inverse, double): {inverse}.")


if __name__ == "__main__":
    main()
