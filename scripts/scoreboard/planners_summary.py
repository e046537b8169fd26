#!/usr/bin/env python3
"""The planners panel against issue 38's targets: one Markdown summary from the run folders of
`scripts/scoreboard.sh --planners --out DIR` (finished tasks only; what is missing is listed).

    planners_summary.py DIR [--out FILE] [--horizon 240]

Per world and seed, from each run's exploration.json (`metrics`: coverage against simulated
time; `goals`: outcomes):
  AUC        area under the coverage curve over 0..horizon s (coverage x s; the coverage stays at
             its last value after an early stop), the measure the global tour optimises;
  c180/c240  coverage at 180 / 240 s (the last sample at or before);
  failed s   simulated seconds spent on goals that ended in a navigation failure (stuck,
             collision, unreachable, timeout).
Then per world kind (generated rooms, flats, shipped): ig's AUC over the best baseline's
(ig_greedy, frontier, random, lawnmower), ig's c180 over the oracle's, and the medians the
targets are stated in. Python 3 standard library only.
"""

import argparse
import json
import os
import statistics
import sys

BASELINES = ("ig_greedy", "frontier", "random", "lawnmower", "ig_before")
PLANNERS = ("ig",) + BASELINES + ("oracle",)
FAILED = ("stuck", "collision", "unreachable", "timeout")


def curve_stats(path, horizon):
    """(AUC, c180, c240, failed seconds) of one run folder, or None when it has not finished."""
    try:
        with open(os.path.join(path, "exploration.json")) as f:
            e = json.load(f)
    except (OSError, ValueError):
        return None
    pts = sorted((m["t"], m.get("coverage", 0.0)) for m in e.get("metrics", []))
    auc, last_t, last_c = 0.0, 0.0, 0.0
    for t, c in pts:
        if t > horizon:
            break
        auc += last_c * (t - last_t)
        last_t, last_c = t, c

    def at(tt):
        v = [c for t, c in pts if t <= tt + 0.01]
        return v[-1] if v else 0.0

    auc += last_c * (horizon - last_t)
    failed = sum(g["t_end"] - g["t_start"] for g in e.get("goals", [])
                 if any(g.get("outcome", "").startswith(f) for f in FAILED))
    return auc, at(180), at(horizon), failed


def parse_task(name):
    """planners_<world>_<planner>[_s<k>] (or flats_...) -> (world, planner, seed index)."""
    if not name.startswith(("planners_", "flats_")):
        return None
    rest = name.split("_", 1)[1]
    seed = 1
    if rest.rsplit("_", 1)[-1].startswith("s") and rest.rsplit("_", 1)[-1][1:].isdigit():
        rest, s = rest.rsplit("_", 1)
        seed = int(s[1:])
    for p in sorted(PLANNERS, key=len, reverse=True):
        if rest.endswith("_" + p):
            return rest[: -len(p) - 1], p, seed
    return None


def kind(world):
    return "flat" if world.startswith("flat") else "room" if world.startswith("gen") else "shipped"


def main(argv):
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("dir")
    ap.add_argument("--out", default="")
    ap.add_argument("--horizon", type=float, default=240.0)
    a = ap.parse_args(argv[1:])
    with open(os.path.join(a.dir, "tasks.tsv")) as f:
        names = [line.split("\t")[1] for line in f.read().splitlines()[1:]]
    runs, missing = {}, []
    for n in names:
        key = parse_task(n)
        s = curve_stats(os.path.join(a.dir, "runs", n), a.horizon) if key else None
        if s is None:
            missing.append(n)
        else:
            runs[key] = s
    worlds = []
    for w, _, k in runs:
        if (w, k) not in worlds:
            worlds.append((w, k))
    md = [f"Planners panel `{a.dir}`: {len(runs)} of {len(names)} runs finished; AUC over 0-"
          f"{a.horizon:.0f} s (coverage x s), coverage at 180 / {a.horizon:.0f} s, simulated "
          "seconds on failed goals.", "",
          "| world | seed | " + " | ".join(PLANNERS) + " | ig / best baseline | ig c180 / oracle |",
          "|---|---|" + "---|" * (len(PLANNERS) + 2)]
    ratios, oracle_ratios, flats240 = {}, {}, []
    for w, k in worlds:
        cells, complete = [], all((w, p, k) in runs for p in PLANNERS)
        for p in PLANNERS:
            s = runs.get((w, p, k))
            cells.append("-" if s is None else f"{s[0]:.0f} ({s[1]:.2f}/{s[2]:.2f}, {s[3]:.0f} s)")
        r = o = ""
        if complete:
            best = max(runs[(w, b, k)][0] for b in BASELINES)
            ratio = runs[(w, "ig", k)][0] / best if best > 0 else float("nan")
            oc = runs[(w, "oracle", k)][1]
            orat = runs[(w, "ig", k)][1] / oc if oc > 0 else float("nan")
            ratios.setdefault(kind(w), []).append(ratio)
            oracle_ratios.setdefault(kind(w), []).append(orat)
            r, o = f"{ratio:.2f}", f"{orat:.2f}"
        if kind(w) == "flat" and (w, "ig", k) in runs:
            flats240.append(runs[(w, "ig", k)][2])
        md.append(f"| {w} | {k} | " + " | ".join(cells) + f" | {r} | {o} |")
    md.append("")
    for kd in ("room", "flat", "shipped"):
        if kd in ratios:
            gen = ratios[kd]
            md.append(f"- {kd}: ig / best baseline median {statistics.median(gen):.2f} over "
                      f"{len(gen)} world-seeds (min {min(gen):.2f}, max {max(gen):.2f}); ig's "
                      f"coverage at 180 s / the oracle's median "
                      f"{statistics.median(oracle_ratios[kd]):.2f}")
    gen_all = ratios.get("room", []) + ratios.get("flat", [])
    if gen_all:
        md.append(f"- generated worlds (targets: >= 1.3 and >= 0.85): ig / best baseline median "
                  f"{statistics.median(gen_all):.2f}, ig c180 / oracle median "
                  f"{statistics.median(oracle_ratios.get('room', []) + oracle_ratios.get('flat', [])):.2f}")
    if flats240:
        md.append(f"- flats, ig's coverage at {a.horizon:.0f} s (target >= 0.7 at the mission's "
                  f"camera): {', '.join(f'{c:.2f}' for c in flats240)}")
    per_planner = {p: [runs[key][3] for key in runs if key[1] == p] for p in PLANNERS}
    md.append("- simulated seconds on failed goals, mean per run: " + ", ".join(
        f"{p} {statistics.mean(v):.0f}" for p, v in per_planner.items() if v))
    if missing:
        md.append(f"- not finished ({len(missing)}): " + ", ".join(missing))
    text = "\n".join(md) + "\n"
    if a.out:
        with open(a.out, "w") as f:
            f.write(text)
    sys.stdout.write(text)


if __name__ == "__main__":
    main(sys.argv)
