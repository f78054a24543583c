"""What the bench/*_table.py scripts share: their command line, and one run of a Google Benchmark
program read from its JSON output (an argument vector, never a shell)."""
import argparse
import json
import subprocess


def arguments(doc, program, min_time="0.3", flags=()):
    """The table script's arguments: the path to `program`, --min-time [s per case] and `flags`
    (pairs of a flag's name and help: booleans)."""
    parser = argparse.ArgumentParser(description=doc, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("bench", help=f"path to {program}")
    parser.add_argument("--min-time", default=min_time)
    for name, help_text in flags:
        parser.add_argument(name, action="store_true", help=help_text)
    return parser.parse_args()


def run(bench, min_time, pattern=None):
    """The benchmarks of one run of `bench` (those matching `pattern`, a regex), as the JSON lists them."""
    argv = [bench, "--benchmark_min_time=" + min_time, "--benchmark_format=json"]
    if pattern:
        argv.append("--benchmark_filter=" + pattern)
    out = subprocess.run(argv, check=True, capture_output=True, text=True).stdout
    return json.loads(out)["benchmarks"]
