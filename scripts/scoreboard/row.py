#!/usr/bin/env python3
"""One scoreboard row from a finished task (scripts/scoreboard/run_task.sh calls it).

    row.py OUT NAME --status ok|failed|skipped [--error TEXT] [--wall-s S] [--eval-failed E,..]

Reads the task's line of OUT/tasks.tsv and its run folder OUT/runs/NAME (report.json,
frames.csv, config.ini, trajectory.txt, groundtruth.txt and the JSON the evals wrote there:
ate_sim3.json, rpe.json, segmentation.json, classification.json, exploration_eval.json,
memory.json, bench.json) and writes OUT/rows/NAME.json atomically (NAME.json.tmp, then renamed):

    {"name", "task", "group", "evals", "pool", "status", "error", "errors" (per eval), "wall_s",
     "commit" (report.json rasm.commit), "metrics": {key: value}, "detail": {...}}

The metric keys are those of scripts/scoreboard/metrics.py; "detail" holds what the table does
not show (lost stretches, per-stage ms, stop reasons). Python 3 standard library only.
"""

import csv
import json
import math
import os
import sys


def load_json(path):
    try:
        with open(path) as f:
            return json.load(f)
    except (OSError, ValueError):
        return None


def ini_value(path, section, key, default=None):
    """A key of an INI file as rasm writes config.ini ('key = value', ';' comments)."""
    cur = None
    try:
        for line in open(path):
            line = line.split(";")[0].strip()
            if line.startswith("["):
                cur = line.strip("[]")
            elif cur == section and "=" in line:
                k, v = (x.strip() for x in line.split("=", 1))
                if k == key:
                    return v
    except OSError:
        pass
    return default


def load_tum(path):
    """TUM trajectory: {timestamp rounded to 0.1 ms: [tx, ty, tz, qx, qy, qz, qw]}."""
    poses = {}
    for line in open(path):
        if line.startswith("#") or not line.strip():
            continue
        v = [float(x) for x in line.split()]
        poses[round(v[0], 4)] = v[1:8]
    return poses


def cm(x):
    return None if x is None else 100.0 * x


# ---- tracking --------------------------------------------------------------------------------


def tracking(d, rep, m, detail):
    """Fraction tracked, ATE (report.json: over every frame and over the tracked ones), Sim(3) ATE
    and RPE over 1 s (rasm eval ate --scale / rpe), SILENT frames (reported tracked, more than 5 cm
    from the ground truth after the ATE alignment of the tracked frames; a robot frame its drift
    report flags off the floor is counted apart), the lost stretches and how they ended, and for
    simulated runs (which start at the true pose) the UNALIGNED world-frame error: max / RMS of
    the position error and of its z (up) component over every frame, and the max tilt (report.json
    world_frame_error)."""
    m["frames"] = rep.get("frames")
    m["frames_tracked"] = rep.get("frames_tracked")
    m["tracked_fraction"] = rep.get("tracked_fraction")
    m["lost_intervals"] = rep.get("lost_intervals")
    m["relocalisations"] = rep.get("relocalisations")
    ate = rep.get("ate", {}).get("translation_m", {}).get("rmse")
    ate_t = rep.get("ate_tracked", rep.get("ate", {})).get("translation_m", {}).get("rmse")
    m["ate_all_cm"], m["ate_tracked_cm"] = cm(ate), cm(ate_t)
    sim3 = load_json(os.path.join(d, "ate_sim3.json"))
    if sim3:
        m["ate_sim3_cm"] = cm(sim3.get("ate", sim3).get("translation_m", {}).get("rmse"))
    rpe = load_json(os.path.join(d, "rpe.json"))
    if rpe:
        m["rpe_1s_cm"] = cm(rpe.get("translation_m", {}).get("rmse"))
        m["rpe_1s_deg"] = rpe.get("rotation_deg", {}).get("rmse")
    elif os.path.exists(os.path.join(d, "rpe.txt")):  # e.g. a run shorter than 1 s
        detail["rpe_error"] = open(os.path.join(d, "rpe.txt")).read().strip()[-300:]
    gt_path, est_path = os.path.join(d, "groundtruth.txt"), os.path.join(d, "trajectory.txt")
    if not (os.path.exists(gt_path) and os.path.exists(est_path)):
        return
    gt, est = load_tum(gt_path), load_tum(est_path)
    rows = list(csv.DictReader(open(os.path.join(d, "frames.csv"))))

    # Per-frame error after the run's own ATE alignment of the tracked frames (report.json
    # ate_tracked, or ate when nothing was lost: alignment.T_gt_est).
    A = rep.get("ate_tracked", rep.get("ate", {})).get("alignment", {}).get("T_gt_est")

    def aligned(p):
        if not A:
            return p
        return [sum(A[i][k] * p[k] for k in range(3)) + A[i][3] for i in range(3)]

    # A robot's drift report (frames.csv floor_height_m / floor_tilt_deg beyond [robot]
    # floor_max_height_m / floor_max_tilt_deg of the run's config.ini, docs/tracking.md) flags a
    # tracked frame as off the floor: such a frame is reported, not silent.
    ini = os.path.join(d, "config.ini")
    limits = {k: float(ini_value(ini, "robot", k, v)) for k, v in
              (("floor_max_height_m", 0.03), ("floor_max_tilt_deg", 1.5))}

    def off_floor(r):
        h, tilt = r.get("floor_height_m", ""), r.get("floor_tilt_deg", "")
        return (h not in ("", "nan") and abs(float(h)) > limits["floor_max_height_m"]) or \
               (tilt not in ("", "nan") and abs(float(tilt)) > limits["floor_max_tilt_deg"])

    silent = flagged = drift_big = off = 0
    sq_pos = sq_z = 0.0
    max_pos = max_z = 0.0
    n = 0
    for r in rows:
        t = round(float(r["timestamp_s"]), 4)
        if t not in gt or t not in est:
            continue
        g, e = gt[t][:3], est[t][:3]
        err = math.dist(g, aligned(e))
        raw, dz = math.dist(g, e), e[2] - g[2]
        n += 1
        sq_pos += raw * raw
        sq_z += dz * dz
        max_pos, max_z = max(max_pos, raw), max(max_z, abs(dz))
        drift_big += raw > 0.05
        if err > 0.05:
            if r["tracked"] != "1":
                flagged += 1
            elif off_floor(r):
                off += 1
            else:
                silent += 1
    m["silent_frames"], m["off_floor_frames"] = silent, off
    detail["lost_over_5cm"] = flagged
    if ini_value(ini, "source", "type") == "sim" and n:
        m["pos_max_cm"], m["pos_rms_cm"] = cm(max_pos), cm(math.sqrt(sq_pos / n))
        m["z_max_cm"], m["z_rms_cm"] = cm(max_z), cm(math.sqrt(sq_z / n))
        m["unaligned_over_5cm"] = drift_big
        # The run's own world-frame error (report.json, associated as the ATE) adds the tilt; its
        # position and z errors are the ones computed here from the files.
        world = rep.get("world_frame_error", {}).get("all", {})
        if world:
            m["tilt_max_deg"] = world.get("tilt_deg", {}).get("max")
            m["heading_rms_deg"] = world.get("heading_deg", {}).get("rmse")
            for key, ours in (("position_m", max_pos), ("vertical_m", max_z)):
                theirs = world.get(key, {}).get("max")
                if theirs is not None and abs(theirs - ours) > 1e-3:
                    detail["world_frame_error_mismatch"] = \
                        f"{key} max: report.json {theirs:.4f} m, trajectory files {ours:.4f} m"

    # Lost stretches: [first frame index, frames lost, how the stretch ended (pose_source of the
    # frame that ended it, or "end of run"), frames until the view showed mapped space again].
    stretches = []
    for r in rows:
        if r["tracked"] != "1":
            if stretches and stretches[-1][2] is None:
                stretches[-1][1] += 1
            else:
                stretches.append([int(r["index"]), 1, None])
        elif stretches and stretches[-1][2] is None:
            stretches[-1][2] = r["pose_source"]
    for st in stretches:
        if st[2] is None:
            st[2] = "end of run"
    # Where the view shows mapped space again: the first frame of a stretch whose true pose is
    # within 0.3 m and 20 deg (optical axes) of a frame tracked before the stretch (the keyframe
    # spacing); a frame with no ICP inliers and too few ORB features (a covered lens) shows
    # nothing. Frames lost minus that offset is the relocalisation delay of a stretch ended by
    # relocalisation.
    def axis(q):
        qx, qy, qz, qw = q
        return (2 * (qx * qz + qw * qy), 2 * (qy * qz - qw * qx), 1 - 2 * (qx * qx + qy * qy))

    index_of = {int(r["index"]): k for k, r in enumerate(rows)}
    cos20 = math.cos(math.radians(20))

    def near_fused(k, before):
        t = round(float(rows[k]["timestamp_s"]), 4)
        blind = rows[k].get("inliers") == "0" and \
            rows[k].get("relocalisation_failure") == "too few features"
        if t not in gt or blind:
            return False
        p, z = gt[t][:3], axis(gt[t][3:7])
        for j in range(before):
            tj = round(float(rows[j]["timestamp_s"]), 4)
            if rows[j]["tracked"] != "1" or tj not in gt:
                continue
            if math.dist(p, gt[tj][:3]) < 0.3 and \
                    sum(a * b for a, b in zip(z, axis(gt[tj][3:7]))) > cos20:
                return True
        return False

    delays = []
    for st in stretches:
        k0 = index_of[st[0]]
        ends = st[1] + (k0 + st[1] < len(rows))  # the frame that ended the stretch counts too
        st.append(next((o for o in range(ends) if near_fused(k0 + o, k0)), None))
        if st[2] == "relocalised" and st[3] is not None:
            delays.append(st[1] - st[3])
    detail["lost_stretches"] = stretches
    m["reloc_delay_max_frames"] = max(delays) if delays else None


# ---- segmentation, classification, exploration, memory, bench ----------------------------------


def segmentation(d, rep, m, detail):
    ev = load_json(os.path.join(d, "segmentation.json"))
    if not ev:
        return False
    st = rep.get("stages", {})
    m["seg_objects_evaluated"] = ev.get("objects_evaluated")
    m["seg_objects_recovered"] = ev.get("objects_recovered", ev.get("tp"))
    for k in ("objects_recovered_fraction", "pq", "sq", "rq", "segments_per_object",
              "undersegmented_objects", "label_changes_per_stable_surfel"):
        m[k] = ev.get(k)
    m["seg_ms"] = st.get("segmentation", {}).get("mean_ms")
    detail["segmentation"] = {k: ev.get(k) for k in ("world", "tp", "fp", "fn", "segments",
                                                     "objects_without_segment", "targets")}
    detail["segmentation"]["failure_kinds"] = segmentation_failures(ev.get("objects", []))
    return True


def segmentation_failures(objs):
    """Why the evaluated objects that were not recovered failed, counted by kind. Instance ids
    follow the worlds' convention: structure 1-9 (not in "objects"), furniture 10-99, objects
    >= 100."""
    label = {o["instance"]: o.get("name") or o.get("class") for o in objs}
    kinds = {}
    for o in objs:
        if not o.get("evaluated") or o.get("recovered"):
            continue
        big = "furniture" if o["instance"] < 100 else "object"
        h = o.get("merged_with")
        if o.get("undersegmented"):
            if h not in label:
                k = f"{big} merged with structure (floor, wall)"
            elif h < 100:
                k = f"{big} merged with the furniture it stands on or beside"
            else:
                k = f"{big} merged with a neighbouring object"
        elif not o.get("segments"):
            k = (f"{big} without a segment: surfels mostly unlabelled (segment 0)"
                 if 2 * o.get("unsegmented_surfels", 0) >= o.get("surfels", 0)
                 else f"{big} without a segment of its own: surfels in segments of other instances")
        elif o["segments"] > 1:
            k = f"{big} split into several segments"
        else:
            k = f"{big} with one segment, IoU <= 0.5"
        kinds[k] = kinds.get(k, 0) + 1
    return kinds


def classification(d, rep, m, detail):
    ev = load_json(os.path.join(d, "classification.json"))
    if not ev:
        return False
    cl = rep.get("classification", {})
    precs = [c["precision"] for c in ev.get("per_class", {}).values()
             if c.get("precision") is not None]
    m["cls_objects_evaluated"] = ev.get("objects_evaluated")
    m["cls_objects_correct"] = sum(1 for o in ev.get("objects", [])
                                   if o.get("evaluated") and o.get("correct"))
    m["object_accuracy"] = ev.get("object_accuracy")
    m["segmented_coco_objects"] = ev.get("segmented_coco_objects")
    m["segmented_coco_accuracy"] = ev.get("segmented_coco_accuracy")
    m["macro_precision"] = sum(precs) / len(precs) if precs else None
    ol = ev.get("object_level", {})
    m["objects_reported"] = ol.get("reported")
    m["objects_reported_correct"] = ol.get("reported_correct")
    m["object_precision"] = ol.get("precision")
    m["objects_coco"] = ol.get("objects")
    m["objects_found"] = ol.get("objects_found")
    m["object_recall"] = ol.get("recall")
    m["detections"], m["detections_fused"] = cl.get("detections"), cl.get("detections_fused")
    return True


def exploration(d, rep, m, detail):
    """rasm eval exploration over this one run (one group): coverage and objects correct at
    60 / 120 / 180 simulated s; a time beyond the task's time budget is left empty (the eval
    would repeat the final value)."""
    ev = load_json(os.path.join(d, "exploration_eval.json"))
    if not ev or not ev.get("groups"):
        return False
    g = ev["groups"][0]
    ini = os.path.join(d, "config.ini")  # (runs before the merge of [explore] into [exploration])
    budget = float(ini_value(ini, "exploration", "time_budget_s", "")
                   or ini_value(ini, "explore", "time_budget_s", "0") or 0)
    for t in (60, 120, 180):
        ok = budget <= 0 or t <= budget + 1e-6
        m[f"coverage_{t}"] = g.get("coverage_at", {}).get(str(t)) if ok else None
        m[f"objects_correct_{t}"] = g.get("objects_correct_at", {}).get(str(t)) if ok else None
    m["coverage_final"] = g.get("coverage_final")
    m["objects_correct_final"] = rep.get("objects_correct_fraction")
    m["path_m"], m["sim_s"] = g.get("path_length_m"), g.get("sim_time_s")
    m["lost_fraction"] = g.get("frames_lost_fraction")
    m["ate_all_cm"] = cm(rep.get("ate", {}).get("translation_m", {}).get("rmse"))
    m["stop_reason"] = rep.get("stop_reason")
    ex = rep.get("exploration", {})
    detail["exploration"] = {"world": g.get("world"), "planner": g.get("planner"),
                             "time_to_90_coverage_s": g.get("time_to_90_coverage_s"),
                             "goals": ex.get("goals"), "goals_reached": ex.get("goals_reached"),
                             "objects_detectable": ex.get("objects_detectable")}
    return True


def memory(d, rep, m, detail):
    ev = load_json(os.path.join(d, "memory.json"))
    if not ev:
        return False
    m["rss_growth_second_half"] = ev.get("rss_mb", {}).get("growth_second_half")
    m["surfels_growth_second_half"] = ev.get("surfels", {}).get("growth_second_half")
    m["map_bytes_per_surfel"] = ev.get("map_bytes_per_surfel")
    detail["memory"] = {"plateau": ev.get("plateau"), "seconds": ev.get("seconds"),
                        "rss_mb_at_end": ev.get("rss_mb", {}).get("at_end")}
    return True


def bench(d, rep, m, detail):
    ev = load_json(os.path.join(d, "bench.json"))
    if not ev:
        return False
    m["fps_preloaded"] = ev.get("fps")
    detail["bench_cpu_ms_per_frame"] = ev.get("cpu_ms_per_frame")
    return True


EVAL_READERS = {"seg": segmentation, "cls": classification, "expl": exploration, "mem": memory,
                "bench": bench}


def main(argv):
    import argparse
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("out")
    ap.add_argument("name")
    ap.add_argument("--status", required=True, choices=("ok", "failed", "skipped"))
    ap.add_argument("--error", default="")
    ap.add_argument("--wall-s", type=float)
    ap.add_argument("--eval-failed", default="", help="evals that exited non-zero, comma-separated")
    a = ap.parse_args(argv[1:])
    task = None
    with open(os.path.join(a.out, "tasks.tsv")) as f:
        for line in f.read().splitlines()[1:]:
            c = line.split("\t")
            if c[1] == a.name:
                task = c
    if task is None:
        sys.exit(f"row.py: no task {a.name} in {a.out}/tasks.tsv")
    evals = [e for e in task[3].split(",") if e]
    row = {"name": a.name, "task": int(task[0]), "group": task[2], "evals": evals,
           "pool": task[4] if task[4] != "-" else None, "status": a.status,
           "error": a.error or None, "errors": {},
           "wall_s": a.wall_s, "commit": None, "metrics": {}, "detail": {}}
    d = os.path.join(a.out, "runs", a.name)
    rep = load_json(os.path.join(d, "report.json")) if a.status != "skipped" else None
    if rep:
        m, detail = row["metrics"], row["detail"]
        row["commit"] = rep.get("rasm", {}).get("commit")
        row["detail"]["report_status"] = rep.get("status")
        if rep.get("error") and not row["error"]:
            row["error"] = rep["error"]
        # speed and memory: every task
        m["fps"], m["cpu_ms_per_frame"] = rep.get("fps"), rep.get("cpu_ms_per_frame")
        m["peak_rss_mb"], m["surfels"] = rep.get("peak_rss_mb"), rep.get("surfels")
        m["wall_s"] = a.wall_s
        detail["stage_mean_ms"] = {k: round(v.get("mean_ms", 0), 2)
                                   for k, v in rep.get("stages", {}).items()}
        if a.status == "ok":
            if "track" in evals:
                try:
                    tracking(d, rep, m, detail)
                except (OSError, ValueError, KeyError) as e:
                    row["errors"]["track"] = f"{type(e).__name__}: {e}"
            for ev in filter(None, a.eval_failed.split(",")):
                row["errors"][ev] = f"exited non-zero (see runs/{a.name}/{ev}.txt)"
            for ev in evals:
                if ev in EVAL_READERS and not EVAL_READERS[ev](d, rep, m, detail):
                    row["errors"].setdefault(
                        ev, f"no output of the {ev} eval (see runs/{a.name}/{ev}.txt)")
    os.makedirs(os.path.join(a.out, "rows"), exist_ok=True)
    path = os.path.join(a.out, "rows", a.name + ".json")
    with open(path + ".tmp", "w") as f:
        json.dump(row, f, indent=1)
        f.write("\n")
    os.replace(path + ".tmp", path)


if __name__ == "__main__":
    main(sys.argv)
