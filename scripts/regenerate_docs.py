#!/usr/bin/python3
"""Regenerates every figure in docs/ from the command that produces it, or checks them.

  python3 scripts/regenerate_docs.py [--build build]              the quick figures (the demo's summary, images)
  python3 scripts/regenerate_docs.py --all [--build build]        also the slow ones: the 600-decision and sampled demos, every
                                                                  benchmark table (an idle machine: ~50 min)
  python3 scripts/regenerate_docs.py --only NAME [NAME ...]       just these figures (--list names them)
  python3 scripts/regenerate_docs.py --check [NAME ...]           fail when a deterministic figure differs from its command

Each figure is a block of a docs/*.md file between <!-- figure:NAME begin --> and <!-- figure:NAME
end --> (the demo's summary between <!-- demo-summary:begin --> and <!-- demo-summary:end -->),
holding exactly what its command prints: FIGURES below names each command. A measured figure (a
benchmark: times differ between runs) starts with a line saying when, on what machine and under
what load it was measured; a deterministic one (same inputs, same bytes: the demo for its seed,
the foveation tables) is compared by --check, which the tests run. Images in docs/images/ are
rewritten from the same runs:
  demo_sweep.png, demo_triangles.png: `python3 scripts/plot_simulation.py build/demo/simulate`
      over the demo's run; demo_frame_0600.png: that run's frame_0600.png;
  foveation_plan.png: `acuity plan --display 2000x2000 --fov 100 --gaze 15,8 --panel 640`;
  osg_field_debug.png: frame 80 of the acuity-osg command in docs/integrations.md (a build with
      -DACUITY_OSG=ON and xvfb-run; --no-osg leaves it);
  web_page_levels.png: `ctest -R web_page_chromium`'s page_levels.png (-DACUITY_WEB=ON; --no-web
      leaves it).
Runs programs with argument vectors, never a shell; writes each file by temp file and rename.
"""
import argparse
import datetime
import os
import platform
import shutil
import subprocess
import sys

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
DOCS = os.path.join(ROOT, "docs")
IMAGES = os.path.join(DOCS, "images")
PY = "/usr/bin/python3"


class Figure:
    """A block of `doc` printed by `argv` (a function of the build tree); `fenced`: shown as code."""

    def __init__(self, name, doc, argv, measured, fenced=False, extract=None, slow=None):
        self.name, self.doc, self.argv, self.measured, self.fenced = name, doc, argv, measured, fenced
        self.slow = measured if slow is None else slow  # left out unless --all or --only
        self.extract = extract or (lambda stdout: stdout.strip("\n"))

    def markers(self):
        if self.name == "demo-summary":  # the name issue 15 gave it
            return "<!-- demo-summary:begin -->", "<!-- demo-summary:end -->"
        return f"<!-- figure:{self.name} begin -->", f"<!-- figure:{self.name} end -->"


def demo_summary(stdout):
    """The summary in a demo's output: from 'N frames at' up to 'written to' (blank ends trimmed)."""
    lines = stdout.splitlines()
    start = next((i for i, l in enumerate(lines) if l.split(" ", 1)[0].isdigit() and " frames at " in l), None)
    if start is None:
        sys.exit("the demo printed no summary ('N frames at ...'):\n" + stdout)
    end = next((i for i in range(start, len(lines)) if lines[i].startswith("written to ")), len(lines))
    return "\n".join(lines[start:end]).strip("\n")


def sampled_summary(stdout):
    """The sampled decisions' block in a demo's output: from 'N decisions sampled' up to 'acuity demo finished'."""
    lines = stdout.splitlines()
    start = next((i for i, l in enumerate(lines) if " decisions sampled (seed " in l), None)
    if start is None:
        sys.exit("the demo printed no sampled decisions ('N decisions sampled ...'):\n" + stdout)
    end = next((i for i in range(start, len(lines)) if lines[i].startswith("acuity demo finished")), len(lines))
    return "\n".join(lines[start:end]).strip("\n")


def meshes(b):
    return os.path.join(b, "cgal-data", "data", "meshes")


def acuity(b):
    return os.path.join(b, "tools", "acuity")


FIGURES = [
    Figure("demo-summary", "demo.md",
           lambda b: [acuity(b), "demo", "--cache", os.path.join(b, "demo"), "-o", os.path.join(b, "demo", "simulate")],
           measured=False, fenced=True, extract=demo_summary),
    Figure("demo-600", "demo.md",
           lambda b: [acuity(b), "demo", "--cache", os.path.join(b, "demo"), "--validate", "600", "-o",
                      os.path.join(b, "demo", "validate600")],
           measured=False, fenced=True, extract=demo_summary, slow=True),
    Figure("demo-sampled", "demo.md",
           lambda b: [acuity(b), "demo", "--cache", os.path.join(b, "demo"), "--sampled", "400"],
           measured=False, fenced=True, extract=sampled_summary, slow=True),
    Figure("demo-sampled-flat", "demo.md",
           lambda b: [acuity(b), "demo", "--flat", "--cache", os.path.join(b, "demo-flat"), "--sampled", "400"],
           measured=False, fenced=True, extract=sampled_summary, slow=True),
    Figure("foveation-table", "foveation.md", lambda b: [acuity(b), "plan", "--table"], measured=False),
    Figure("foveation-speed", "foveation.md",
           lambda b: [PY, os.path.join(ROOT, "bench", "foveation_table.py"), os.path.join(b, "bench", "bench_foveation")],
           measured=True),
    Figure("models-table", "benchmarks.md",
           lambda b: [PY, os.path.join(ROOT, "bench", "models_table.py"), os.path.join(b, "bench", "bench_models")],
           measured=True),
    Figure("scheduler-table", "benchmarks.md",
           lambda b: [PY, os.path.join(ROOT, "bench", "scheduler_table.py"), os.path.join(b, "bench", "bench_scheduler"),
                      "--min-time", "0.2"],
           measured=True),
    Figure("scheduler-setup", "benchmarks.md",
           lambda b: [PY, os.path.join(ROOT, "bench", "scheduler_table.py"), os.path.join(b, "bench", "bench_scheduler"),
                      "--min-time", "0.2", "--setup"],
           measured=True),
    Figure("bake-table", "bake.md",
           lambda b: [PY, os.path.join(ROOT, "bench", "bake_table.py"), acuity(b), meshes(b)], measured=True),
    Figure("lodgen-bench", "lodgen.md",
           lambda b: [os.path.join(b, "bench", "bench_lodgen"), meshes(b), "2"], measured=True),
    Figure("lodgen-sweep", "lodgen.md",
           lambda b: [PY, os.path.join(ROOT, "scripts", "lodgen_sweep.py"), acuity(b), os.path.join(b, "lodgen-sweep")],
           measured=True),
    Figure("chain-step", "lodgen.md",
           lambda b: [PY, os.path.join(ROOT, "scripts", "chain_step.py"), b], measured=True),
    Figure("cluster-targets", "lodgen.md",
           lambda b: [PY, os.path.join(ROOT, "scripts", "cluster_targets.py"), b, "--views", "100", "--lenient"],
           measured=True),
    Figure("calibration", "spectra.md",
           lambda b: [PY, os.path.join(ROOT, "scripts", "calibration.py")], measured=False, slow=True),
    Figure("calibration-default", "spectra.md",
           lambda b: [PY, os.path.join(ROOT, "scripts", "calibration.py"), "--model", "default"], measured=False,
           slow=True),
    Figure("profile-bench", "spectra.md",
           lambda b: [os.path.join(b, "bench", "bench_profile"), meshes(b), "48"], measured=True),
]


def run(args, env=None):
    """Runs a program (no shell); its standard output, or an exit naming the command that failed."""
    r = subprocess.run([str(a) for a in args], capture_output=True, text=True, env=env)
    if r.returncode != 0:
        sys.exit(f"{' '.join(map(str, args))} failed ({r.returncode}):\n{r.stdout}{r.stderr}")
    return r.stdout


def shown(argv, build):
    """The command as docs show it: the build tree as build/, other paths relative to the repository."""
    def relative(a):
        if a == PY:
            return "python3"
        if a == build or a.startswith(build + os.sep):
            return os.path.join("build", os.path.relpath(a, build))
        return os.path.relpath(a, ROOT) if os.path.isabs(a) and a.startswith(ROOT + os.sep) else a
    return " ".join(relative(str(a)) for a in argv)


def machine_line(fig, build):
    cpu = platform.processor() or platform.machine()
    try:
        with open("/proc/cpuinfo", encoding="utf-8") as f:
            cpu = next((l.split(":", 1)[1].strip() for l in f if l.startswith("model name")), cpu)
    except OSError:
        pass
    load = " ".join(f"{x:.1f}" for x in os.getloadavg())
    return (f"_Measured {datetime.date.today().isoformat()} on {os.cpu_count()} cores ({cpu}), load average {load} "
            f"at the start, by `{shown(fig.argv(build), build)}` (scripts/regenerate_docs.py)._")


def block(fig, content):
    begin, end = fig.markers()
    body = f"```\n{content}\n```" if fig.fenced else content
    return f"{begin}\n{body}\n{end}"


def documented(fig):
    path = os.path.join(DOCS, fig.doc)
    text = open(path, encoding="utf-8").read()
    begin, end = fig.markers()
    b, e = text.find(begin), text.find(end)
    if b < 0 or e < b:
        sys.exit(f"{path}: no {begin} ... {end} block")
    return path, text, text[b:e + len(end)]


def write_atomically(path, data):
    tmp = path + ".tmp"
    with open(tmp, "wb") as f:
        f.write(data)
    os.replace(tmp, path)


def produce(fig, build):
    env = dict(os.environ, PYTHONPATH=os.path.join(build, "python"))
    line = machine_line(fig, build) if fig.measured else None
    content = fig.extract(run(fig.argv(build), env=env))
    return block(fig, f"{line}\n\n{content}" if line else content)


def images(build, no_osg, no_web):
    cache = os.path.join(build, "demo")
    out = os.path.join(cache, "simulate")
    run([sys.executable, os.path.join(ROOT, "scripts", "plot_simulation.py"), out])
    for name, target in (("sweep.png", "demo_sweep.png"), ("triangles.png", "demo_triangles.png"),
                         ("frame_0600.png", "demo_frame_0600.png")):
        shutil.copyfile(os.path.join(out, name), os.path.join(IMAGES, target))
    run([acuity(build), "plan", "--display", "2000x2000", "--fov", "100", "--gaze", "15,8", "--panel", "640",
         "--png", os.path.join(IMAGES, "foveation_plan.png")])
    if not no_osg:
        osg_out = os.path.join(build, "osg")
        run(["xvfb-run", "-a", os.path.join(build, "integrations", "osg", "acuity-osg"), os.path.join(cache, "field.glb"),
             "--profiles", os.path.join(cache, "profiles"), "--headless", "--frames", "120", "--out", osg_out, "--debug",
             "--png-every", "40"])
        shutil.copyfile(os.path.join(osg_out, "frame_00080.png"), os.path.join(IMAGES, "osg_field_debug.png"))
    if not no_web:
        run(["ctest", "--test-dir", build, "-R", "web_page_chromium"])
        shutil.copyfile(os.path.join(build, "web", "test-work", "page", "page_levels.png"),
                        os.path.join(IMAGES, "web_page_levels.png"))


def main():
    p = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    p.add_argument("--build", default=os.path.join(ROOT, "build"), help="the build tree (default: build)")
    p.add_argument("--check", nargs="*", metavar="NAME",
                   help="compare deterministic figures (the quick ones when none named) with their commands")
    p.add_argument("--only", nargs="+", metavar="NAME", help="regenerate just these figures (no images)")
    p.add_argument("--all", action="store_true", help="also the slow figures: benchmark tables, the 600-decision demo")
    p.add_argument("--list", action="store_true", help="list the figures and their commands")
    p.add_argument("--no-osg", action="store_true", help="leave docs/images/osg_field_debug.png as it is")
    p.add_argument("--no-web", action="store_true", help="leave docs/images/web_page_levels.png as it is")
    a = p.parse_args()
    build = os.path.abspath(a.build)
    by_name = {f.name: f for f in FIGURES}
    if a.list:
        for f in FIGURES:
            kind = ("measured" if f.measured else "deterministic") + (", slow" if f.slow else "")
            print(f"{f.name:20} docs/{f.doc:16} {kind:21} "
                  f"{shown(f.argv(build), build)}")
        return
    for name in (a.check or []) + (a.only or []):
        if name not in by_name:
            sys.exit(f"no figure '{name}' (--list names them)")
    if a.check is not None:
        names = a.check or [f.name for f in FIGURES if not f.measured and not f.slow]
        for name in names:
            fig = by_name[name]
            if fig.measured:
                sys.exit(f"{name} is measured: it differs run to run, regenerate it instead")
            path, _, old = documented(fig)
            new = produce(fig, build)
            if old != new:
                sys.exit(f"{path}: figure {name} differs from what `{shown(fig.argv(build), build)}` prints; run "
                         f"python3 scripts/regenerate_docs.py --only {name}\n--- documented\n{old}\n--- printed\n{new}")
            print(f"{path}: figure {name} matches its command")
        return
    if a.only:
        chosen = [by_name[n] for n in a.only]
    else:
        chosen = [f for f in FIGURES if a.all or not f.slow]
    for fig in chosen:
        print(f"{fig.name}: {shown(fig.argv(build), build)}", flush=True)
        documented(fig)  # the block exists, before a long run
        new = produce(fig, build)
        path, text, old = documented(fig)  # read after the run: edits made meanwhile are kept
        write_atomically(path, text.replace(old, new).encode("utf-8"))
    if not a.only:
        images(build, a.no_osg, a.no_web)
    print("regenerated", ", ".join(f.name for f in chosen), "from", build)


if __name__ == "__main__":
    main()
