#!/usr/bin/env python3
"""What got better or worse between two scoreboard results (docs/results.json layout).

    compare.py PREV.json CUR.json

For every task (and pooled row) in both, every metric that scripts/scoreboard/metrics.py marks
with a direction: better, worse, or unchanged when the change stays within the metric's noise
threshold (|cur - prev| <= max(abs_noise, rel_noise * |prev|)). A task that was ok and now failed
counts as worse (and the reverse as better). Prints one line per change beyond noise and the
summary "N better, M worse, K unchanged". scripts/scoreboard/gather.py calls compare() for
`scripts/scoreboard.sh --compare`. Exit status 0 either way. Python 3 standard library only.
"""

import json
import os
import sys

sys.dont_write_bytecode = True  # no __pycache__ in the source tree
sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import metrics as M  # noqa: E402


def compared_metrics():
    """Every metric with a direction, once per key (a key may head columns in two sections)."""
    seen = {}
    for _, _, m in M.section_metrics():
        if m.better and m.key not in seen:
            seen[m.key] = m
    return list(seen.values())


def _rows(doc):
    """name -> {status, metrics} for the rows and the pooled rows of a results document."""
    out = {r["name"]: r for r in doc.get("rows", [])}
    for p in doc.get("pooled", []):
        out[p["name"]] = dict(p, status="ok")
    return out


def compare(prev, cur):
    """{"changes": [...], "better", "worse", "unchanged", "only_prev", "only_cur"}; a change is
    {name, metric, label, prev, cur, delta, noise, verdict}."""
    P, C = _rows(prev), _rows(cur)
    res = {"changes": [], "better": 0, "worse": 0, "unchanged": 0,
           "only_prev": sorted(set(P) - set(C)), "only_cur": sorted(set(C) - set(P))}
    for name in [n for n in C if n in P]:
        p, c = P[name], C[name]
        if p.get("status") == "skipped" or c.get("status") == "skipped":
            continue
        if (p.get("status") == "ok") != (c.get("status") == "ok"):
            verdict = "worse" if p.get("status") == "ok" else "better"
            res[verdict] += 1
            res["changes"].append({"name": name, "metric": "status", "label": "status",
                                   "prev": p.get("status"), "cur": c.get("status"),
                                   "delta": None, "noise": None, "verdict": verdict})
            continue
        pm, cm = p.get("metrics", {}), c.get("metrics", {})
        for m in compared_metrics():
            a, b = pm.get(m.key), cm.get(m.key)
            if not isinstance(a, (int, float)) or not isinstance(b, (int, float)):
                continue
            delta, noise = b - a, m.noise(a)
            if abs(delta) <= noise + 1e-12:
                res["unchanged"] += 1
                continue
            up_is_good = m.better == "high"
            verdict = "better" if (delta > 0) == up_is_good else "worse"
            res[verdict] += 1
            res["changes"].append({"name": name, "metric": m.key, "label": m.label, "prev": a,
                                   "cur": b, "delta": delta, "noise": noise, "verdict": verdict,
                                   "fmt": m.fmt})
    return res


def summary(res):
    return f"{res['better']} better, {res['worse']} worse, {res['unchanged']} unchanged"


def lines(res):
    """The changes beyond noise, worse first, one line each, then the summary line."""
    out = []
    for ch in sorted(res["changes"], key=lambda c: (c["verdict"] != "worse", c["name"])):
        if ch["metric"] == "status":
            out.append(f"{ch['verdict']:7s} {ch['name']}: status {ch['prev']} -> {ch['cur']}")
            continue
        f = ch.get("fmt", ".3f")
        f = ".0f" if f == "d" else f
        out.append(f"{ch['verdict']:7s} {ch['name']}: {ch['label']} {ch['prev']:{f}} -> "
                   f"{ch['cur']:{f}} ({ch['delta']:+{f}}; noise {ch['noise']:{f}})")
    if res["only_prev"]:
        out.append("only in the previous results: " + ", ".join(res["only_prev"]))
    if res["only_cur"]:
        out.append("new (not in the previous results): " + ", ".join(res["only_cur"]))
    out.append(summary(res))
    return out


def main(argv):
    if len(argv) != 3:
        sys.exit(__doc__)
    prev, cur = (json.load(open(p)) for p in argv[1:3])
    if prev.get("panel") != cur.get("panel"):
        print(f"note: comparing a {cur.get('panel')} panel against a {prev.get('panel')} one "
              "(tasks of the same name only)")
    print("\n".join(lines(compare(prev, cur))))


if __name__ == "__main__":
    main(sys.argv)
