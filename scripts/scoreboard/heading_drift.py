#!/usr/bin/env python3
"""How much of a run's horizontal world-frame error its heading error explains.

    heading_drift.py RUN_DIR [RUN_DIR ...] [--groundtruth FILE] [--timeline STEP_S]

A robot whose estimated heading is off by psi drives each step of its path rotated by psi: the
horizontal error grows by (R(psi) - I) dp per step, distance x heading error. This integrates
that prediction along the true path (re-anchored to the estimate where it jumps by more than
2 cm within one frame: a relocalisation) and prints, per run, the world-frame horizontal error
(RMS, cm), the heading error (RMS and max, deg) and the RMS of what the heading does not explain
(cm). A run whose residual is much smaller than its error drifts because of its heading.

RUN_DIR holds trajectory.txt and groundtruth.txt (TUM format, camera optical frame, the world's
z up); --groundtruth names the truth for runs that have none (a replay of a rawlog). A run that
did not start at the truth's pose is moved there (its first pose onto the truth's: the replay of a
rawlog starts at the identity). --timeline prints the error, heading error and tracking status
every STEP_S seconds (frames.csv beside the trajectory). Python 3 standard library only.
"""

import argparse
import csv
import math
import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import row  # noqa: E402  (load_tum)


def quat_to_rot(qx, qy, qz, qw):
    return [[1 - 2 * (qy * qy + qz * qz), 2 * (qx * qy - qz * qw), 2 * (qx * qz + qy * qw)],
            [2 * (qx * qy + qz * qw), 1 - 2 * (qx * qx + qz * qz), 2 * (qy * qz - qx * qw)],
            [2 * (qx * qz - qy * qw), 2 * (qy * qz + qx * qw), 1 - 2 * (qx * qx + qy * qy)]]


def matmul(a, b):
    return [[sum(a[i][k] * b[k][j] for k in range(3)) for j in range(3)] for i in range(3)]


def transpose(a):
    return [[a[j][i] for j in range(3)] for i in range(3)]


def apply(a, v):
    return [sum(a[i][k] * v[k] for k in range(3)) for i in range(3)]


def load_poses(path):
    """{timestamp: (R, t)} of a TUM trajectory (row.load_tum's keys: rounded to 0.1 ms)."""
    return {t: (quat_to_rot(*v[3:7]), v[0:3]) for t, v in row.load_tum(path).items()}


def heading_error(r_est, r_gt):
    """Rotation about world z from the truth's orientation to the estimate's (rad)."""
    d = matmul(r_est, transpose(r_gt))
    return math.atan2(d[1][0] - d[0][1], d[0][0] + d[1][1])


def analyse(run, gt_path, timeline_s):
    if not os.path.isfile(gt_path):
        raise SystemExit(f"{run}: no ground truth {gt_path} (give one with --groundtruth)")
    gt = load_poses(gt_path)
    est = load_poses(os.path.join(run, "trajectory.txt"))
    stamps = sorted(t for t in est if t in gt)
    if len(stamps) < 2:
        raise SystemExit(f"{run}: fewer than two poses share a timestamp with {gt_path}")
    # Move the estimate's first pose onto the truth's (identity for a run started there).
    r0_gt, t0_gt = gt[stamps[0]]
    r0_est, t0_est = est[stamps[0]]
    r_fix = matmul(r0_gt, transpose(r0_est))
    rt0 = apply(r_fix, t0_est)
    t_fix = [t0_gt[i] - rt0[i] for i in range(3)]

    def world(t):
        r, p = est[t]
        q = apply(r_fix, p)
        return matmul(r_fix, r), [q[i] + t_fix[i] for i in range(3)]

    frames = {}
    csv_path = os.path.join(run, "frames.csv")
    if timeline_s and os.path.exists(csv_path):
        with open(csv_path) as f:
            for r in csv.DictReader(f):
                frames[round(float(r["timestamp_s"]), 4)] = r
    pred = [0.0, 0.0]
    sq_err = sq_res = sq_head = 0.0
    max_head = 0.0
    prev_r, prev_p = world(stamps[0])
    next_print = 0.0
    for a, b in zip(stamps, stamps[1:]):
        psi = heading_error(prev_r, gt[a][0])
        dp = [gt[b][1][i] - gt[a][1][i] for i in range(2)]
        c, s = math.cos(psi), math.sin(psi)
        pred[0] += (c - 1) * dp[0] - s * dp[1]
        pred[1] += s * dp[0] + (c - 1) * dp[1]
        r_b, p_b = world(b)
        e = [p_b[i] - gt[b][1][i] for i in range(2)]
        step = math.hypot((p_b[0] - prev_p[0]) - dp[0], (p_b[1] - prev_p[1]) - dp[1])
        if step > 0.02:  # a jump (relocalisation): the prediction restarts from the error there
            pred = list(e)
        head = math.degrees(heading_error(r_b, gt[b][0]))
        sq_err += e[0] ** 2 + e[1] ** 2
        sq_res += (e[0] - pred[0]) ** 2 + (e[1] - pred[1]) ** 2
        sq_head += head * head
        max_head = max(max_head, abs(head))
        if timeline_s and b >= next_print:
            r = frames.get(b, {})
            print(f"  {b:7.1f} s  horizontal error {100 * math.hypot(*e):5.1f} cm  "
                  f"heading error {head:6.2f} deg  {r.get('status', '')}")
            next_print += timeline_s
        prev_r, prev_p = r_b, p_b
    n = len(stamps) - 1
    return (100 * math.sqrt(sq_err / n), math.sqrt(sq_head / n), max_head,
            100 * math.sqrt(sq_res / n))


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("runs", nargs="+")
    ap.add_argument("--groundtruth")
    ap.add_argument("--timeline", type=float, default=0.0)
    a = ap.parse_args()
    print("| run | horizontal RMS (cm) | heading RMS / max (deg) | not explained by the heading, "
          "RMS (cm) |")
    print("|---|---|---|---|")
    for run in a.runs:
        if not os.path.isfile(os.path.join(run, "trajectory.txt")):
            raise SystemExit(f"{run}: not a run folder (expected {run}/trajectory.txt)")
        gt_path = a.groundtruth or os.path.join(run, "groundtruth.txt")
        if a.timeline:
            print(run)
        err, head_rms, head_max, res = analyse(run, gt_path, a.timeline)
        print(f"| {os.path.basename(os.path.normpath(run))} | {err:.2f} | {head_rms:.2f} / "
              f"{head_max:.2f} | {res:.2f} |")
    return 0


if __name__ == "__main__":
    sys.exit(main())
