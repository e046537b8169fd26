#!/usr/bin/env python3
"""The world-frame panel against its targets: one Markdown summary from the run folders of
`scripts/scoreboard.sh --worldframe --out DIR` (finished tasks only; what is missing is listed).

    worldframe_summary.py DIR [--out FILE]

Per world and seed, the run on tracked poses (wf_<world>_tracked[_s<k>]) from its report.json:
  pos RMS / max   world-frame position error over every frame, no alignment (cm; lost frames at
                  their propagated pose), report.json world_frame_error.all.position_m;
  tilt max        the largest angle between the estimated and the true up direction (deg);
  heading RMS     the yaw error about the world's up (deg; report.json
                  world_frame_error.all.heading_deg, absent in runs before it): what becomes
                  horizontal drift as the robot drives (docs/results-worldframe.md "Heading");
  lost            frames not tracked (%);
  cov / truth     coverage at the end (180 simulated s) of the tracked run and of the same world
                  and seed fused at the true poses (wf_<world>_truth[_s<k>]), and their ratio.
Then the medians and how many world-seeds meet each target: position RMS <= 1.5 cm and max <= 3 cm,
tilt <= 0.15 deg, lost < 1%, coverage ratio >= 0.9 (median). Python 3 standard library only.
"""

import argparse
import json
import os
import re
import statistics
import sys

MAX_TARGETS = {"rms_cm": 1.5, "max_cm": 3.0, "tilt_deg": 0.15}  # per world-seed, at most
LOST_BELOW_PCT = 1.0      # per world-seed, frames lost below
RATIO_MEDIAN_MIN = 0.9    # median coverage over the true poses', at least


def load(path):
    try:
        with open(os.path.join(path, "report.json")) as f:
            return json.load(f)
    except (OSError, ValueError):
        return None


def tracked_row(r):
    w = r["world_frame_error"]["all"]
    return {"rms_cm": 100 * w["position_m"]["rmse"], "max_cm": 100 * w["position_m"]["max"],
            "tilt_deg": w["tilt_deg"]["max"],
            "heading_deg": w.get("heading_deg", {}).get("rmse"),
            "lost_pct": 100.0 * r["frames_lost"] / max(1, r["frames"]),
            "cov": r.get("coverage_fraction")}


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("dir")
    ap.add_argument("--out")
    a = ap.parse_args()
    runs = os.path.join(a.dir, "runs")
    names = sorted(n for n in os.listdir(runs) if n.startswith("wf_") and "_tracked" in n
                   and os.path.isdir(os.path.join(runs, n)))
    rows, missing = [], []
    for n in names:
        m = re.match(r"wf_(.+)_tracked(_s\d+)?$", n)
        world, suffix = m.group(1), m.group(2) or ""
        rt, rg = load(os.path.join(runs, n)), load(os.path.join(runs, f"wf_{world}_truth{suffix}"))
        if rt is None:
            missing.append(n)
            continue
        row = tracked_row(rt)
        row["name"] = world + suffix
        row["truth"] = rg.get("coverage_fraction") if rg else None
        if rg is None:
            missing.append(f"wf_{world}_truth{suffix}")
        row["ratio"] = (row["cov"] / row["truth"]) if row["truth"] and row["cov"] is not None \
            else None
        rows.append(row)
    out = ["| world, seed | pos RMS / max (cm) | tilt max (deg) | heading RMS (deg) | lost (%) "
           "| cov tracked / truth | ratio |",
           "|---|---|---|---|---|---|---|"]
    for r in rows:
        truth = f"{r['truth']:.3f}" if r["truth"] is not None else "-"
        ratio = f"{r['ratio']:.2f}" if r["ratio"] is not None else "-"
        heading = f"{r['heading_deg']:.2f}" if r["heading_deg"] is not None else "-"
        out.append(f"| {r['name']} | {r['rms_cm']:.2f} / {r['max_cm']:.2f} | {r['tilt_deg']:.3f} "
                   f"| {heading} | {r['lost_pct']:.1f} | {r['cov']:.3f} / {truth} | {ratio} |")
    out.append("")
    if rows:
        def med(k):
            v = [r[k] for r in rows if r[k] is not None]
            return statistics.median(v) if v else float("nan")
        def meets(k):
            if k == "lost_pct":
                return sum(1 for r in rows if r[k] < LOST_BELOW_PCT)
            return sum(1 for r in rows if r[k] <= MAX_TARGETS[k])
        n, t = len(rows), MAX_TARGETS
        out.append(f"Over {n} world-seeds (medians; targets in brackets): position RMS "
                   f"{med('rms_cm'):.2f} cm [<= {t['rms_cm']:g}: {meets('rms_cm')} of {n}], "
                   f"max {med('max_cm'):.2f} cm [<= {t['max_cm']:g}: {meets('max_cm')}], "
                   f"tilt max {med('tilt_deg'):.3f} deg [<= {t['tilt_deg']:g}: "
                   f"{meets('tilt_deg')}], heading RMS {med('heading_deg'):.2f} deg, lost {med('lost_pct'):.1f}% "
                   f"[< {LOST_BELOW_PCT:g}: {meets('lost_pct')}], coverage over the true poses' "
                   f"{med('ratio'):.2f} [median >= {RATIO_MEDIAN_MIN:g}].")
    if missing:
        out.append("")
        out.append("Not finished: " + ", ".join(missing) + ".")
    text = "\n".join(out) + "\n"
    if a.out:
        with open(a.out, "w") as f:
            f.write(text)
    sys.stdout.write(text)


if __name__ == "__main__":
    main()
