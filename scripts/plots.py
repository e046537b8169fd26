#!/usr/bin/python3
"""Publication plots of a rasm run folder, for users who want to restyle them.

    scripts/plots.py RUN_DIR [--out DIR] [--format pdf|png|svg]

Reads what `rasm run` wrote (docs/outputs.md) and writes, into --out (default RUN_DIR/plots):

  tracking.<fmt>     per frame: ICP inlier fraction and pose-check agreement, ICP residual (mm)
                     and, with groundtruth.txt, the world-frame position error (cm, no alignment:
                     the map starts at the first true pose); frames tracking lost shaded red
  timing.<fmt>       ms per frame of the stages, stacked in report.json's stage_order, with the
                     rest of the frame on top, so the layers add up to the total (10-frame means)
  path.<fmt>         the camera path from above (world x, y, equal scales) against the ground truth
  exploration.<fmt>  an exploring run's coverage and objects correct over simulated time

The same quantities as rasm's own PNGs (plot_tracking.png, plot_timing.png, plot_trajectory.png,
exploration.png), drawn with Debian's python3-matplotlib (scripts/install-deps.sh installs it).
Edit the `style()` function or the figure code below to restyle them.
"""

import argparse
import csv
import json
import math
import os
import sys

RUNNING_MEAN = 10


def fail(msg):
    print("plots.py: " + msg, file=sys.stderr)
    sys.exit(2)


def read_frames(path):
    """frames.csv as {column: [float or nan]}."""
    with open(path, newline="") as f:
        rows = list(csv.DictReader(f))
    if not rows:
        fail(path + ": no frame rows (expected the header and one row per frame)")
    cols = {}
    for name in rows[0]:
        vals = []
        for r in rows:
            try:
                vals.append(float(r[name]))
            except (TypeError, ValueError):
                vals.append(math.nan)
        cols[name] = vals
    return cols


def read_tum(path):
    """A TUM trajectory: [(t, x, y, z)]."""
    out = []
    with open(path) as f:
        for n, line in enumerate(f, 1):
            s = line.strip()
            if not s or s.startswith("#"):
                continue
            v = s.split()
            if len(v) != 8:
                fail("%s line %d: expected 8 numbers 'timestamp tx ty tz qx qy qz qw'" % (path, n))
            out.append(tuple(float(x) for x in v[:4]))
    return out


def world_frame_error_cm(estimate, groundtruth, max_dt_s=0.02):
    """Per estimated pose, the distance to the ground-truth pose nearest in time (cm), NaN when
    none is within max_dt_s. No alignment: both are in the world frame."""
    if not groundtruth:
        return [math.nan] * len(estimate)
    gt = sorted(groundtruth)
    times = [g[0] for g in gt]
    import bisect
    out = []
    for t, x, y, z in estimate:
        k = bisect.bisect_left(times, t)
        best = None
        for j in (k - 1, k):
            if 0 <= j < len(gt) and abs(gt[j][0] - t) <= max_dt_s:
                if best is None or abs(gt[j][0] - t) < abs(gt[best][0] - t):
                    best = j
        if best is None:
            out.append(math.nan)
        else:
            g = gt[best]
            out.append(100.0 * math.sqrt((x - g[1]) ** 2 + (y - g[2]) ** 2 + (z - g[3]) ** 2))
    return out


def running_mean(v, n=RUNNING_MEAN):
    out, window = [], []
    for x in v:
        window.append(x)
        if len(window) > n:
            window.pop(0)
        finite = [w for w in window if not math.isnan(w)]
        out.append(sum(finite) / len(finite) if finite else math.nan)
    return out


def lost_runs(x, tracked):
    """(start, end) x ranges of the frames tracking lost, half a frame either side."""
    runs, start = [], None
    for i, t in enumerate(tracked):
        if t == 0 and start is None:
            start = x[i] - 0.5
        if t != 0 and start is not None:
            runs.append((start, x[i - 1] + 0.5))
            start = None
    if start is not None:
        runs.append((start, x[-1] + 0.5))
    return runs


def style(plt):
    plt.rcParams.update({"font.size": 9, "axes.grid": True, "grid.alpha": 0.3,
                         "figure.dpi": 150, "savefig.bbox": "tight"})


def plot_tracking(plt, run, frames, out):
    x = frames.get("index") or list(range(len(frames["tracked"])))
    tracked = frames.get("tracked", [1] * len(x))
    est_path, gt_path = os.path.join(run, "trajectory.txt"), os.path.join(run, "groundtruth.txt")
    err = []
    if os.path.exists(est_path) and os.path.exists(gt_path):
        est = read_tum(est_path)
        if len(est) == len(x):
            err = world_frame_error_cm(est, read_tum(gt_path))
    panels = 3 if err and any(not math.isnan(e) for e in err) else 2
    fig, axes = plt.subplots(panels, 1, sharex=True, figsize=(7, 2 * panels))
    axes[0].plot(x, frames.get("inlier_fraction", []), label="ICP inlier fraction")
    axes[0].plot(x, frames.get("check_agreement", []), label="pose check agreement")
    axes[0].set_ylabel("fraction")
    axes[0].set_ylim(0, 1.05)
    axes[1].plot(x, [1000 * v for v in frames.get("rms_m", [])], color="C3",
                 label="ICP residual (rms)")
    axes[1].set_ylabel("mm")
    if panels == 3:
        axes[2].plot(x, err, color="C4", label="world-frame position error")
        axes[2].set_ylabel("cm")
    for ax in axes:
        for k, (a, b) in enumerate(lost_runs(x, tracked)):
            ax.axvspan(a, b, color="red", alpha=0.2, lw=0, label="tracking lost" if k == 0 else None)
        ax.legend(loc="upper right", fontsize=7)
    axes[-1].set_xlabel("frame")
    fig.savefig(out)
    plt.close(fig)


def plot_timing(plt, frames, report, out):
    x = frames.get("index") or list(range(len(frames["ms_total"])))
    stages = report.get("stage_order") or [
        c[3:] for c in frames if c.startswith("ms_") and c not in ("ms_total", "ms_map_lock_wait")]
    layers, labels = [], []
    rest = list(frames["ms_total"])
    for s in stages:
        col = frames.get("ms_" + s)
        if col is None:
            continue
        rest = [r - (c if not math.isnan(c) else 0.0) for r, c in zip(rest, col)]
        layers.append(running_mean(col))
        labels.append(s)
    layers.append(running_mean([max(0.0, r) for r in rest]))
    labels.append("rest of the frame")
    fig, ax = plt.subplots(figsize=(7, 3))
    ax.stackplot(x, [[0.0 if math.isnan(v) else v for v in layer] for layer in layers],
                 labels=labels, alpha=0.8)
    ax.plot(x, running_mean(frames["ms_total"]), color="black", lw=1.2, label="total")
    ax.set_xlabel("frame")
    ax.set_ylabel("ms per frame (%d-frame mean)" % RUNNING_MEAN)
    ax.legend(loc="upper right", fontsize=7, ncol=2)
    fig.savefig(out)
    plt.close(fig)


def plot_path(plt, run, frames, out):
    est = read_tum(os.path.join(run, "trajectory.txt"))
    fig, ax = plt.subplots(figsize=(5, 5))
    gt_path = os.path.join(run, "groundtruth.txt")
    if os.path.exists(gt_path):
        gt = read_tum(gt_path)
        ax.plot([g[1] for g in gt], [g[2] for g in gt], color="C2", lw=3, alpha=0.5,
                label="ground truth")
    ax.plot([e[1] for e in est], [e[2] for e in est], color="C0", lw=1, label="estimate")
    tracked = frames.get("tracked", [])
    lost = [e for e, t in zip(est, tracked) if t == 0]
    if lost:
        ax.plot([e[1] for e in lost], [e[2] for e in lost], "r.", label="tracking lost")
    ax.set_aspect("equal")
    ax.set_xlabel("x (m)")
    ax.set_ylabel("y (m)")
    ax.legend(fontsize=7)
    fig.savefig(out)
    plt.close(fig)


def plot_exploration(plt, exploration, out):
    m = exploration.get("metrics", [])
    t = [e["t"] for e in m]
    fig, ax = plt.subplots(figsize=(6, 3))
    if any("coverage" in e for e in m):
        ax.plot(t, [e.get("coverage", math.nan) for e in m], label="coverage")
    if any("objects_correct_fraction" in e for e in m):
        ax.plot(t, [e.get("objects_correct_fraction", math.nan) for e in m],
                label="objects correct")
    ax.set_xlabel("simulated time (s)")
    ax.set_ylabel("fraction")
    ax.set_ylim(0, 1)
    ax.legend(fontsize=7)
    fig.savefig(out)
    plt.close(fig)


def main(argv):
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("run", help="a rasm run folder (rasm run --out)")
    ap.add_argument("--out", help="where the plots go (default RUN/plots)")
    ap.add_argument("--format", default="pdf", choices=["pdf", "png", "svg"])
    a = ap.parse_args(argv)
    frames_path = os.path.join(a.run, "frames.csv")
    if not os.path.isfile(frames_path):
        fail("%s: no frames.csv (expected a folder written by `rasm run`)" % a.run)
    try:
        import matplotlib
        matplotlib.use("Agg")
        import matplotlib.pyplot as plt
    except ImportError:
        fail("needs Debian's python3-matplotlib (scripts/install-deps.sh installs it); "
             "run with /usr/bin/python3")
    style(plt)
    out = a.out or os.path.join(a.run, "plots")
    os.makedirs(out, exist_ok=True)
    frames = read_frames(frames_path)
    report = {}
    if os.path.isfile(os.path.join(a.run, "report.json")):
        with open(os.path.join(a.run, "report.json")) as f:
            report = json.load(f)
    written = []

    def target(name):
        written.append(os.path.join(out, name + "." + a.format))
        return written[-1]

    plot_tracking(plt, a.run, frames, target("tracking"))
    if "ms_total" in frames:
        plot_timing(plt, frames, report, target("timing"))
    if os.path.isfile(os.path.join(a.run, "trajectory.txt")):
        plot_path(plt, a.run, frames, target("path"))
    xp = os.path.join(a.run, "exploration.json")
    if os.path.isfile(xp):
        with open(xp) as f:
            plot_exploration(plt, json.load(f), target("exploration"))
    for w in written:
        print(w)


if __name__ == "__main__":
    main(sys.argv[1:])
