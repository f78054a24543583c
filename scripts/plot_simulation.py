#!/usr/bin/python3
"""Plots of an `acuity simulate` run: python3 plot_simulation.py OUTPUT_DIR.

Reads frames.csv and sweep.csv from OUTPUT_DIR and writes:
  triangles.png  triangles drawn per frame by each rule, saccades and blinks shaded;
  sweep.png      triangles per frame against the fraction of visible-loss decisions for the
                 baselines at each tuning, with the perceptual, ungated and Reddy rules as points.
Needs Debian's python3-matplotlib (no display: the Agg backend).
"""
import csv
import os
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

# The main rules of frames.csv; "ungated" is the perceptual rule switching at once (no hysteresis).
RULES = ["perceptual", "ungated", "reddy", "distance", "screen-size"]
COLOURS = {"perceptual": "tab:blue", "ungated": "tab:cyan", "reddy": "tab:purple", "distance": "tab:green",
           "screen-size": "tab:orange"}
POINT_LABELS = {"perceptual": "perceptual (q = 1)", "ungated": "ungated (q = 1, switching at once)", "reddy": "reddy"}


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


def plot_triangles(out, frames):
    t = [float(r["seconds"]) for r in frames]
    fig, ax = plt.subplots(figsize=(10, 4.5))
    for a, b in spans(t, [r["saccade"] == "1" for r in frames]):
        ax.axvspan(a, b, color="0.85", lw=0)
    for a, b in spans(t, [float(r["gaze_confidence"]) == 0 for r in frames]):
        ax.axvspan(a, b, color="mistyrose", lw=0)
    ax.plot(t, [float(r["all_finest"]) for r in frames], color="k", lw=1, label="all finest")
    for rule in RULES:
        ax.plot(t, [float(r[rule]) for r in frames], color=COLOURS[rule], lw=1.2, label=rule)
    ax.set_xlabel("time [s]")
    ax.set_ylabel("triangles drawn (objects in view)")
    ax.set_title("Triangles per frame (grey: saccades, pink: blinks)")
    ax.legend(loc="upper right", fontsize=8)
    fig.tight_layout()
    fig.savefig(os.path.join(out, "triangles.png"), dpi=110)
    plt.close(fig)


def plot_sweep(out, sweep):
    judged = int(sweep[0]["judged"]) if sweep else 0
    if judged == 0:
        return
    fig, ax = plt.subplots(figsize=(7, 5))
    for rule, marker in (("perceptual", "^-"), ("screen-size", "o-"), ("distance", "s-")):
        rows = [r for r in sweep if r["rule"] == rule and r["sweep"] == "1"]
        x = [100.0 * int(r["visible_losses"]) / judged for r in rows]
        y = [float(r["triangles_per_frame"]) for r in rows]
        label = "perceptual (quality q swept)" if rule == "perceptual" else f"{rule} (sweep of its tuning)"
        ax.plot(x, y, marker, color=COLOURS[rule], ms=4, label=label)
    for r in sweep:
        if r["sweep"] == "0" and r["rule"] in POINT_LABELS:
            ax.plot(100.0 * int(r["visible_losses"]) / judged, float(r["triangles_per_frame"]), "*", ms=14,
                    color=COLOURS[r["rule"]], label=POINT_LABELS[r["rule"]])
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
    plot_triangles(out, read(os.path.join(out, "frames.csv")))
    plot_sweep(out, read(os.path.join(out, "sweep.csv")))


if __name__ == "__main__":
    main()
