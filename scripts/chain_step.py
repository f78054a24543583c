#!/usr/bin/python3
"""How lodgen's step between levels pays: the demo's 400 sampled decisions (docs/demo.md) with chains
of each step, spanning the same 1/16 of the finest mesh's triangles (0.5: 5 levels, 0.6: 6, 0.707: 9).
Prints a Markdown table: per step, the levels, the perceptual rule's triangles (of all-finest and
against the oracle, the coarsest level the exact-view check finds invisible), how many triangles
screen-size needs at the perceptual rule's 1% rate, the visible losses, the seven profiles' bytes,
the runtime tables they take (Scheduler.table_bytes, default configuration and with a hysteresis
margin of 0.2) and the time lodgen and the profiles took (each step's chains and profiles built
afresh, except where its cache already holds them; times are wall seconds on a shared machine).

Run: python3 scripts/chain_step.py build [STEP ...]   (docs/lodgen.md holds its output:
scripts/regenerate_docs.py --only chain-step). Runs programs with argument vectors, never a shell.
"""
import os
import re
import subprocess
import sys

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
STEPS = [0.5, 0.6, 0.707]


def demo(build, step):
    cache = os.path.join(build, "demo") if step == 0.5 else os.path.join(build, "demo-ratio-%g" % step)
    argv = [os.path.join(build, "tools", "acuity"), "demo", "--sampled", "400", "--ratio", str(step), "--cache", cache]
    r = subprocess.run(argv, capture_output=True, text=True)
    if r.returncode != 0:
        sys.exit("%s failed:\n%s%s" % (" ".join(argv), r.stdout, r.stderr))
    return cache, r.stdout


def number(pattern, text, what):
    m = re.search(pattern, text, re.M)
    if not m:
        sys.exit("the demo printed no %s (/%s/)" % (what, pattern))
    return m.group(1)


def tables(profiles):
    sys.path.insert(0, os.path.join(BUILD, "python"))
    import acuity  # noqa: E402 (the build's module)
    out = []
    for margin in (0.0, 0.2):
        c = acuity.SchedulerConfig()
        c.hysteresis_margin = margin
        total = 0
        for f in profiles:
            s = acuity.Scheduler(c)
            total += s.table_bytes(s.add_profile(acuity.Profile.load(f)))
        out.append(total)
    return out


def row(build, step):
    cache, text = demo(build, step)
    # One line per chain as the scene loads it: its name (its profile's, in <cache>/profiles) and levels.
    chains = dict(re.findall(r"^\s+(\S+)\s+(\d+) levels, \d+ -> \d+ triangles", text, re.M))
    levels = sorted({int(n) for n in chains.values()})
    lodgen = sum(float(s) for s in re.findall(r"lodgen: .* levels, ([\d.]+) s$", text, re.M))
    built = re.findall(r"^\s+\S+\s+\d+ levels, .*: profile \(\d+ views\), ([\d.]+) s$", text, re.M)
    profile_s = sum(float(s) for s in built)
    perceptual = number(r"^perceptual\s+\d+\s+([\d.]+%)", text, "perceptual line")
    visible = number(r"^perceptual\s+\d+\s+[\d.]+%\s+[\d.]+x\s+([\d.]+% \(\d+/\d+\))", text, "visible losses")
    oracle = number(r"the perceptual rule draws ([\d.]+x) the oracle's", text, "oracle line")
    screen = number(r"^\s+screen-size\s+\d+ triangles = ([\d.]+x) the perceptual rule's at 1%", text,
                    "screen-size at 1%")
    profiles = sorted(os.path.join(cache, "profiles", name + ".acuity") for name in chains)
    size = sum(os.path.getsize(f) for f in profiles)
    plain, margin = tables(profiles)
    timing = ("%.0f" % lodgen if lodgen else "cached") + " / " + ("%.0f" % profile_s if built else "cached")
    return "| %g | %s | %s | %s | %s | %s | %.0f | %.0f / %.0f | %s |" % (
        step, "-".join(str(x) for x in (levels[0], levels[-1])) if len(levels) > 1 else levels[0], perceptual,
        oracle, screen, visible, size / 1024, plain / 1024, margin / 1024, timing)


def main():
    global BUILD
    BUILD = os.path.abspath(sys.argv[1] if len(sys.argv) > 1 else os.path.join(ROOT, "build"))
    steps = [float(s) for s in sys.argv[2:]] or STEPS
    print("| step (ratio) | levels | perceptual: of all-finest | of the oracle | screen-size at 1% | visible losses |"
          " profiles [KiB] | tables [KiB]: default / margin 0.2 | lodgen / profile [s] |")
    print("|---|---|---|---|---|---|---|---|---|")
    for step in steps:
        print(row(BUILD, step), flush=True)


if __name__ == "__main__":
    main()
