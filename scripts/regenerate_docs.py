#!/usr/bin/python3
"""Regenerates the figures in docs/ from the commands that produce them, or checks them.

  python3 scripts/regenerate_docs.py [--build build]            rewrite docs/ from fresh runs
  python3 scripts/regenerate_docs.py --check [--build build]    fail when docs/demo.md's summary differs

What it regenerates (each from the command docs/ names next to the figure):
  docs/demo.md, between <!-- demo-summary:begin --> and <!-- demo-summary:end -->: the summary
      `build/tools/acuity demo` prints (the table of rules and the quality sweep; the timings, cache
      lines and file list around it are not part of it);
  docs/images/demo_sweep.png, demo_triangles.png: `python3 scripts/plot_simulation.py
      build/demo/simulate` over that run; demo_frame_0600.png: that run's frame_0600.png;
  docs/images/foveation_plan.png: `acuity plan --display 2000x2000 --fov 100 --gaze 15,8 --panel 640`;
  docs/images/osg_field_debug.png: frame 80 of the acuity-osg command in docs/integrations.md
      (needs a build with -DACUITY_OSG=ON and xvfb-run; --no-osg leaves it);
  docs/images/web_page_levels.png: `ctest -R web_page_chromium`'s page_levels.png (needs a build
      with -DACUITY_WEB=ON; --no-web leaves it).
The demo is deterministic for its seed (1), so the summary is the same on every machine; it takes a
minute or two with the chains and profiles cached in build/demo. Runs programs with argument vectors,
never a shell.
"""
import argparse
import os
import shutil
import subprocess
import sys

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
DEMO_MD = os.path.join(ROOT, "docs", "demo.md")
IMAGES = os.path.join(ROOT, "docs", "images")
BEGIN, END = "<!-- demo-summary:begin -->", "<!-- demo-summary:end -->"


def run(args, **kwargs):
    """Runs a program (no shell); its standard output, or an exit naming the command that failed."""
    r = subprocess.run([str(a) for a in args], capture_output=True, text=True, **kwargs)
    if r.returncode != 0:
        sys.exit(f"{' '.join(map(str, args))} failed ({r.returncode}):\n{r.stdout}{r.stderr}")
    return r.stdout


def demo_summary(stdout):
    """The summary in the demo's output: from 'N frames at' up to 'written to' (blank ends trimmed)."""
    lines = stdout.splitlines()
    start = next((i for i, l in enumerate(lines) if l.split(" ", 1)[0].isdigit() and " frames at " in l), None)
    if start is None:
        sys.exit("the demo printed no summary ('N frames at ...'):\n" + stdout)
    end = next((i for i in range(start, len(lines)) if lines[i].startswith("written to ")), len(lines))
    return "\n".join(lines[start:end]).strip("\n")


def block(summary):
    return f"{BEGIN}\n```\n{summary}\n```\n{END}"


def documented_block(text):
    """The block between the markers in docs/demo.md, markers included."""
    b, e = text.find(BEGIN), text.find(END)
    if b < 0 or e < b:
        sys.exit(f"{DEMO_MD}: no {BEGIN} ... {END} block")
    return text[b:e + len(END)]


def write_atomically(path, data):
    tmp = path + ".tmp"
    with open(tmp, "wb") as f:
        f.write(data)
    os.replace(tmp, path)


def main():
    p = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    p.add_argument("--build", default=os.path.join(ROOT, "build"), help="the build tree (default: build)")
    p.add_argument("--check", action="store_true", help="only compare docs/demo.md's summary with a fresh demo")
    p.add_argument("--out", help="where the demo writes (default: BUILD/demo/simulate)")
    p.add_argument("--no-osg", action="store_true", help="leave docs/images/osg_field_debug.png as it is")
    p.add_argument("--no-web", action="store_true", help="leave docs/images/web_page_levels.png as it is")
    a = p.parse_args()
    acuity = os.path.join(a.build, "tools", "acuity")
    cache = os.path.join(a.build, "demo")
    out = a.out or os.path.join(cache, "simulate")
    stdout = run([acuity, "demo", "--cache", cache, "-o", out])
    summary = block(demo_summary(stdout))
    text = open(DEMO_MD, encoding="utf-8").read()
    documented = documented_block(text)
    if a.check:
        if documented != summary:
            sys.exit(f"{DEMO_MD}: the demo summary differs from what `acuity demo` prints; "
                     f"run python3 scripts/regenerate_docs.py\n--- documented\n{documented}\n--- printed\n{summary}")
        print(f"{DEMO_MD}: the demo summary matches `acuity demo`")
        return
    write_atomically(DEMO_MD, text.replace(documented, summary).encode("utf-8"))
    run([sys.executable, os.path.join(ROOT, "scripts", "plot_simulation.py"), out])
    for name, target in (("sweep.png", "demo_sweep.png"), ("triangles.png", "demo_triangles.png"),
                         ("frame_0600.png", "demo_frame_0600.png")):
        shutil.copyfile(os.path.join(out, name), os.path.join(IMAGES, target))
    run([acuity, "plan", "--display", "2000x2000", "--fov", "100", "--gaze", "15,8", "--panel", "640",
         "--png", os.path.join(IMAGES, "foveation_plan.png")])
    if not a.no_osg:
        osg_out = os.path.join(a.build, "osg")
        run(["xvfb-run", "-a", os.path.join(a.build, "integrations", "osg", "acuity-osg"), os.path.join(cache, "field.glb"),
             "--profiles", os.path.join(cache, "profiles"), "--headless", "--frames", "120", "--out", osg_out, "--debug",
             "--png-every", "40"])
        shutil.copyfile(os.path.join(osg_out, "frame_00080.png"), os.path.join(IMAGES, "osg_field_debug.png"))
    if not a.no_web:
        run(["ctest", "--test-dir", a.build, "-R", "web_page_chromium"])
        shutil.copyfile(os.path.join(a.build, "web", "test-work", "page", "page_levels.png"),
                        os.path.join(IMAGES, "web_page_levels.png"))
    print("regenerated docs/demo.md's summary and docs/images/ from", a.build)


if __name__ == "__main__":
    main()
