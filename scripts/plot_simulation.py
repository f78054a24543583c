#!/usr/bin/python3
"""Plots of an `acuity simulate` run: python3 plot_simulation.py OUTPUT_DIR.

Reads frames.csv and sweep.csv from OUTPUT_DIR and writes:
  triangles.png  triangles drawn per frame by each rule, saccades and blinks shaded;
  sweep.png      triangles per frame against the fraction of visible-loss decisions for the
                 swept rules at each tuning, with every main rule at its default tuning as a point.
Needs Debian's python3-matplotlib (no display: the Agg backend).
"""
import csv
import os
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

# The main rules are frames.csv's columns after these (the simulation writes one per rule of the
# scheduler's selection_rules(), then "ungated": the perceptual rule switching at once, no hysteresis),
# and sweep.csv's rows with sweep 0; a new rule needs nothing here. Colours cycle over the rules.
FRAME_COLUMNS = ["frame", "seconds", "saccade", "gaze_confidence", "phase", "target", "all_finest"]
PALETTE = ["tab:blue", "tab:purple", "tab:green", "tab:orange", "tab:cyan", "tab:red", "tab:brown", "tab:olive"]
POINT_NOTES = {"perceptual": " (q = 1)", "ungated": " (q = 1, switching at once)"}


def rule_colours(rules):
    return {rule: PALETTE[i % len(PALETTE)] for i, rule in enumerate(rules)}


def read(path):
    with open(path, newline="") as f:
        return list(csv.DictReader(f))


def spans(times, flags):
    """(start, end) of each run of true flags."""
    out, start = [], None
    for t, on in zip(times, flags):
        if on and start is None:
            start = t
        if not on and start is not None:
            out.append((start, t))
            start = None
    if start is not None:
        out.append((start, times[-1]))
    return out


def plot_triangles(out, frames, rules, colours):
    t = [float(r["seconds"]) for r in frames]
    fig, ax = plt.subplots(figsize=(10, 4.5))
    for a, b in spans(t, [r["saccade"] == "1" for r in frames]):
        ax.axvspan(a, b, color="0.85", lw=0)
    for a, b in spans(t, [float(r["gaze_confidence"]) == 0 for r in frames]):
        ax.axvspan(a, b, color="mistyrose", lw=0)
    ax.plot(t, [float(r["all_finest"]) for r in frames], color="k", lw=1, label="all finest")
    for rule in rules:
        ax.plot(t, [float(r[rule]) for r in frames], color=colours[rule], lw=1.2, label=rule)
    ax.set_xlabel("time [s]")
    ax.set_ylabel("triangles drawn (objects in view)")
    ax.set_title("Triangles per frame (grey: saccades, pink: blinks)")
    ax.legend(loc="upper right", fontsize=8)
    fig.tight_layout()
    fig.savefig(os.path.join(out, "triangles.png"), dpi=110)
    plt.close(fig)


def plot_sweep(out, sweep, colours):
    judged = int(sweep[0]["judged"]) if sweep else 0
    if judged == 0:
        return
    fig, ax = plt.subplots(figsize=(7, 5))
    swept = list(dict.fromkeys(r["rule"] for r in sweep if r["sweep"] == "1"))  # in the file's order
    for rule, marker in zip(swept, ["^-", "o-", "s-", "v-", "D-", "x-"]):
        rows = [r for r in sweep if r["rule"] == rule and r["sweep"] == "1"]
        x = [100.0 * int(r["visible_losses"]) / judged for r in rows]
        y = [float(r["triangles_per_frame"]) for r in rows]
        label = "perceptual (quality q swept)" if rule == "perceptual" else f"{rule} (sweep of its tuning)"
        ax.plot(x, y, marker, color=colours[rule], ms=4, label=label)
    for r in sweep:  # every main rule at its default tuning, as a point
        if r["sweep"] == "0":
            ax.plot(100.0 * int(r["visible_losses"]) / judged, float(r["triangles_per_frame"]), "*", ms=14,
                    color=colours[r["rule"]], label=r["rule"] + POINT_NOTES.get(r["rule"], ""))
    ax.set_xlabel(f"visible-loss decisions [% of {judged} judged by render-and-analyze]")
    ax.set_ylabel("triangles per frame (objects in view)")
    ax.set_yscale("log")
    ax.set_title("Triangles against visible losses")
    ax.grid(True, which="both", alpha=0.3)
    ax.legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(os.path.join(out, "sweep.png"), dpi=110)
    plt.close(fig)


def main():
    if len(sys.argv) != 2:
        sys.exit("usage: plot_simulation.py OUTPUT_DIR")
    out = sys.argv[1]
    frames = read(os.path.join(out, "frames.csv"))
    rules = [c for c in (frames[0].keys() if frames else []) if c not in FRAME_COLUMNS]
    colours = rule_colours(rules)
    plot_triangles(out, frames, rules, colours)
    plot_sweep(out, read(os.path.join(out, "sweep.csv")), colours)


if __name__ == "__main__":
    main()
