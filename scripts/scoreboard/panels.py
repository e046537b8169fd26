#!/usr/bin/env python3
"""The scoreboard's panels: the tasks of `scripts/scoreboard.sh --smoke | --quick | --full`.

    panels.py PANEL OUT RASM DATA [-- extra rasm run arguments]

Writes OUT/tasks.tsv, one line per task (the list scripts/scoreboard/run_task.sh reads):

    task  name  group  evals  pool  needs  est_s  args

  task   1..N, the order the tasks run in (and the Slurm array index)
  name   the run folder OUT/runs/<name> and the row file OUT/rows/<name>.json
  group  the task's main group (tracking, segmentation, classification, exploration, memory)
  evals  what runs after `rasm run`, comma-separated (scripts/scoreboard/metrics.py EVALS):
         track (trajectory vs ground truth: rasm eval ate --scale / rpe, silent and unaligned
         errors), seg (rasm eval segmentation), cls (rasm eval classification), expl (rasm eval
         exploration), mem (rasm eval memory), bench (rasm bench --preload on the same input)
  pool   rows with the same pool key get a pooled / median row (generated worlds; '-': none)
  needs  ':'-separated paths that must exist, else the task is skipped with a message ('-': none)
  est_s  estimated wall seconds on 2 free cores (docs/scoreboard.md "Cost")
  args   the `rasm run` arguments, shell-quoted (run_task.sh adds --out and
         --set output.overwrite=true)

Rooms of `rasm sim generate --seed S --fast` (seeds from 1001: no evaluation tuned on them;
earlier ones used 1-20 and 101-120) are generated into OUT/worlds/ here, once (existing files are
kept), with their _handheld, _robot, _handheld_fast and _robot_fast trajectories. The memory task's
lap spec is written there too. Python 3 standard library only.
"""

import os
import shlex
import subprocess
import sys

# ---- camera resolutions (the sim renders at [camera]'s intrinsics; real sequences keep theirs)


def camera(width, height):
    f = 262.5 * width / 320.0
    return ["--set", "camera.preset=", "--set", f"camera.width={width}",
            "--set", f"camera.height={height}", "--set", f"camera.fx={f:g}",
            "--set", f"camera.fy={f:g}", "--set", f"camera.cx={(width - 1) / 2:g}",
            "--set", f"camera.cy={(height - 1) / 2:g}"]


RES = {"640x480": [], "320x240": camera(320, 240), "160x120": camera(160, 120)}

# Outputs no evaluation reads (map.ply only where seg / cls read it).
OUTPUTS_OFF = ["--set", "output.write_3dscene=false", "--set", "output.preview_png=false",
               "--set", "output.write_rawlog=false", "--set", "output.save_map=false",
               "--set", "output.write_mesh=false"]

# ---- cost model (docs/scoreboard.md "Cost"): wall seconds on 2 free cores -----------------------
# From smoke runs of the binary of fe50f96 (<= 30 frames, 20 simulated s, OMP_NUM_THREADS=1: CPU
# ms per frame of the first frames), scaled by the growth of the per-frame cost with the map
# (x1.4-1.5 over a whole sequence) and the 2-thread speed-up (x1.6-1.85), and checked against the
# frame rates and wall times of whole runs in docs/history/ (slam-eval.md, exploration.md).
START_S = 3.0            # process start, configuration, outputs, evals and row of one task
MS_PER_FRAME = {         # wall ms per frame of `rasm run` (render + mapping), 2 threads
    ("sim", "640x480"): 125.0, ("sim", "320x240"): 35.0, ("sim", "160x120"): 12.0,
    ("tum", "640x480"): 60.0, ("7scenes", "640x480"): 95.0,
}
EXPLORE_S_PER_SIM_S = {  # wall s per simulated s of an exploring run (10 Hz camera), by planner
    ("ig", "640x480"): 2.0, ("ig", "320x240"): 1.25, ("ig", "160x120"): 0.5,
    ("ig_greedy", "640x480"): 2.0, ("ig_greedy", "320x240"): 1.25, ("ig_greedy", "160x120"): 0.5,
    ("oracle", "640x480"): 1.5, ("oracle", "320x240"): 0.6, ("oracle", "160x120"): 0.4,
    ("frontier", "640x480"): 1.3, ("frontier", "320x240"): 0.45, ("frontier", "160x120"): 0.3,
    ("random", "640x480"): 1.3, ("random", "320x240"): 0.5, ("random", "160x120"): 0.3,
    ("lawnmower", "640x480"): 1.3, ("lawnmower", "320x240"): 0.5, ("lawnmower", "160x120"): 0.3,
}
SEG_EVAL_S = {"640x480": 10.0, "320x240": 4.0, "160x120": 1.0}  # eval segmentation + classification

# Frames of the shipped trajectories at 30 Hz (hand-held: the last keyframe's time; robot loops:
# their recorded lengths, docs/history/). Generated ones are read from the spec's header.
FRAMES = {"office_handheld": 901, "office_handheld_fast": 301, "office_handheld_long": 1801,
          "cluttered_lab_handheld": 451, "cluttered_lab_handheld_fast": 151,
          "office_robot_loop": 743, "office_robot_fast": 650, "two_rooms_robot": 1400,
          "cluttered_lab_robot": 400}


def spec_frames(path, rate_hz=30):
    """Frames of a `rasm sim generate` trajectory: its header says "Checked when generated: 25.1 s,
    ..." (hand-held) or "... driven in 26.2 s ..." (robot)."""
    import re
    with open(path) as f:
        for line in f:
            if line.startswith("# Checked when generated"):
                m = re.search(r"([0-9.]+) s\b", line)
                if m:
                    return int(float(m.group(1)) * rate_hz) + 1
    return 900


def robot_spec(world):
    """The robot spec whose start pose an exploring run of a world starts from."""
    return {"office": "office_robot_loop", "cluttered_lab": "cluttered_lab_robot",
            "two_rooms": "two_rooms_robot"}.get(world, world[:-5] + "_robot.yaml"
                                                if world.endswith(".yaml") else world)


class Panel:
    def __init__(self, out, rasm, data, extra):
        self.out, self.rasm, self.data, self.extra = out, rasm, data, extra
        self.tasks = []

    def add(self, name, group, evals, args, est_s, pool="", needs=()):
        for t in self.tasks:
            assert t["name"] != name, f"duplicate task name {name}"
        self.tasks.append({"name": name, "group": group, "evals": ",".join(evals),
                           "pool": pool or "-", "needs": ":".join(needs) or "-",
                           "est_s": round(est_s), "args": list(args) + self.extra})

    # -- a generated room: OUT/worlds/gen<seed>.yaml and its four trajectories --------------------
    def gen(self, seed, rooms=0):
        """A generated room of `seed` (rooms = 0), or a flat of `rooms` rooms off a hallway."""
        name = f"gen{seed}" if rooms == 0 else f"flat{seed}r{rooms}"
        world = os.path.join(self.out, "worlds", f"{name}.yaml")
        if not os.path.exists(world[:-5] + "_robot_fast.yaml"):
            os.makedirs(os.path.dirname(world), exist_ok=True)
            log = world[:-5] + ".log"
            layout = [] if rooms == 0 else ["--layout", "flat", "--rooms", str(rooms)]
            with open(log, "w") as f:
                r = subprocess.run([self.rasm, "sim", "generate", world, "--seed", str(seed),
                                    "--fast"] + layout, stdout=f, stderr=subprocess.STDOUT)
            if r.returncode != 0:
                sys.exit(f"scoreboard: rasm sim generate --seed {seed} failed (see {log})")
        return world

    # -- task kinds -------------------------------------------------------------------------------
    def real(self, name, ini, folder, kind, evals=("track",), sets=(), max_frames=0):
        """A real sequence of DATA (skipped when absent): its INI (None: the embedded default with
        [source] type = kind) plus the folder's path and the DATA folder's detector."""
        path = os.path.join(self.data, folder)
        needs = [path]
        args = [ini] if ini else ["--set", f"source.type={kind}"]
        args += ["--set", f"source.path={path}", "--set", "output.write_ply=false"]
        # Every real source runs the default detector for real data (detectors = auto:
        # NanoDet-m on a worker thread), its files from DATA/detectors.
        nanodet = os.path.join(self.data, "detectors", "nanodet-m-320-onnx")
        needs.append(nanodet)
        args += ["--set", f"dnn_detector.model={nanodet}/nanodet.onnx",
                 "--set", f"dnn_detector.names={nanodet}/coco.names"]
        args += OUTPUTS_OFF + list(sets)
        frames = {"tum/fr1_xyz_first37": 37, "tum/fr3_cabinet_keyframes": 58,
                  "7scenes/redkitchen_first300": 300}[folder]
        if max_frames:
            args += ["--set", f"source.max_frames={max_frames}"]
            frames = min(frames, max_frames)
        est = START_S + frames * MS_PER_FRAME[(kind, "640x480")] / 1000.0
        if "bench" in evals:
            est *= 2
        self.add(name, "tracking", evals, args, est, needs=needs)

    def sim(self, name, world, traj, seed, res, evals, group="tracking", max_frames=0, pool="",
            sets=()):
        """A scripted simulated run (sim source: world rendered along a trajectory spec)."""
        ply = "true" if ("seg" in evals or "cls" in evals) else "false"
        args = ["--set", "source.type=sim", "--set", f"sim.world={world}",
                "--set", f"sim.trajectory={traj}", "--set", f"sim.seed={seed}",
                "--set", "exploration.enabled=false", "--set", f"output.write_ply={ply}"]
        args += OUTPUTS_OFF + RES[res] + list(sets)
        frames = FRAMES[traj] if traj in FRAMES else spec_frames(traj)
        if max_frames:
            args += ["--set", f"source.max_frames={max_frames}"]
            frames = min(frames, max_frames)
        est = START_S + frames * MS_PER_FRAME[("sim", res)] / 1000.0
        if ply == "true":
            est += SEG_EVAL_S[res]
        self.add(name, group, evals, args, est, pool=pool)

    def explore(self, name, world, planner, seed, budget_s, res, pool="", evals=("expl", "track"),
                poses="tracked", sets=()):
        """An exploring run: the robot explores `world` from its robot spec's start pose for
        `budget_s` simulated seconds (no wall-clock budget: the result must not depend on the
        machine's speed), deterministic planning (the embedded default's planner_thread = false).
        poses = "groundtruth" fuses at the true poses (compares the planners alone)."""
        args = ["--set", "source.type=sim", "--set", f"sim.world={world}",
                "--set", f"sim.trajectory={robot_spec(world)}", "--set", f"sim.seed={seed}",
                "--set", f"exploration.seed={seed}", "--set", f"exploration.planner={planner}",
                "--set", "exploration.enabled=true", "--set", f"exploration.time_budget_s={budget_s}",
                "--set", "exploration.wall_budget_s=0", "--set", "output.write_ply=false",
                "--set", f"mapper.poses={poses}"]
        args += OUTPUTS_OFF + RES[res] + list(sets)
        est = START_S + budget_s * EXPLORE_S_PER_SIM_S[(planner, res)]
        self.add(name, "exploration", evals, args, est, pool=pool)

    def memory(self, name, laps, res, rate_hz=10, max_frames=0):
        """The office robot loop driven `laps` times with the whole pipeline on (no exploration:
        the same path every lap): does memory plateau? (rasm eval memory)."""
        spec = os.path.join(self.out, "worlds", f"office_robot_laps{laps}.yaml")
        os.makedirs(os.path.dirname(spec), exist_ok=True)
        wp = ", ".join(["[4.3, 2.2], [4.3, 3.9], [1.5, 3.9], [1.2, 2.5]"] * laps)
        with open(spec, "w") as f:
            f.write(f"# office_robot_loop's waypoints {laps} times (scripts/scoreboard/panels.py)\n"
                    f"type: robot\nrate_hz: {rate_hz}\nstart: {{x: 1.2, y: 2.5, yaw_deg: 0}}\n"
                    f"waypoints: [{wp}]\n"
                    "controller: {lookahead_m: 0.5, max_v_mps: 0.35, max_w_degps: 45}\n"
                    "robot: {footprint_radius_m: 0.25, camera_height_m: 0.55, "
                    "camera_pitch_deg: -10}\n")
        args = ["--set", "source.type=sim", "--set", "sim.world=office",
                "--set", f"sim.trajectory={spec}", "--set", "sim.seed=1",
                "--set", "exploration.enabled=false", "--set", "output.write_ply=false"]
        args += OUTPUTS_OFF + RES[res]
        frames = laps * 25 * rate_hz  # ~25 s per lap
        if max_frames:
            args += ["--set", f"source.max_frames={max_frames}"]
            frames = min(frames, max_frames)
        self.add(name, "memory", ("mem",), args,
                 START_S + frames * MS_PER_FRAME[("sim", res)] / 1000.0)


# ---- the panels --------------------------------------------------------------------------------


def smoke(p):
    """Every code path in a minute or two: each group and eval once, 10-30 frames at 160x120,
    10 s explorations; the numbers mean nothing."""
    p.real("real_tum_fr1_xyz_first37", "ini/tum_fr1_xyz.ini", "tum/fr1_xyz_first37", "tum",
           evals=("track", "bench"), max_frames=10)
    p.real("real_7scenes_redkitchen_first300", "ini/7scenes_redkitchen.ini",
           "7scenes/redkitchen_first300", "7scenes", max_frames=10)
    p.real("real_tum_fr3_cabinet_keyframes", None, "tum/fr3_cabinet_keyframes", "tum",
           max_frames=10)
    p.sim("sim_office_robot_loop", "office", "office_robot_loop", 1, "160x120", ("track",),
          max_frames=40)
    p.sim("sim_office_handheld", "office", "office_handheld", 1, "160x120",
          ("track", "seg", "cls"), group="segmentation", max_frames=20)
    for s in (1001, 1002):  # two rooms: the pooled rows
        g = p.gen(s)
        p.sim(f"gen{s}_handheld", g, g[:-5] + "_handheld.yaml", s, "160x120",
              ("track", "seg", "cls"), group="segmentation", max_frames=15, pool="gen_handheld")
    p.explore("explore_office_ig", "office", "ig", 1, 10, "160x120")
    p.explore("explore_gen1001_random", p.gen(1001), "random", 1001, 10, "160x120")
    p.memory("memory_office_laps", 1, "160x120", max_frames=30)


def quick(p):
    """Within 15 minutes on 2 free cores (docs/scoreboard.md "Cost"): the real sequences at their
    resolution; at 320x240 the shipped robot, fast and hand-held paths, every kind of path of one
    generated room and the hand-held and robot paths of a second; the office robot loop at
    640x480; every planner (ig, frontier, random, lawnmower) exploring the first room, and ig and
    random the office, for 180 simulated s."""
    p.real("real_tum_fr1_xyz_first37", "ini/tum_fr1_xyz.ini", "tum/fr1_xyz_first37", "tum",
           evals=("track", "bench"))
    p.real("real_7scenes_redkitchen_first300", "ini/7scenes_redkitchen.ini",
           "7scenes/redkitchen_first300", "7scenes")
    p.real("real_tum_fr3_cabinet_keyframes", None, "tum/fr3_cabinet_keyframes", "tum")
    # The shipped worlds, with the seeds of the earlier evaluations.
    p.sim("sim_office_robot_loop", "office", "office_robot_loop", 1, "320x240", ("track",))
    p.sim("sim_office_robot_fast", "office", "office_robot_fast", 3, "320x240", ("track",))
    p.sim("sim_office_handheld_fast", "office", "office_handheld_fast", 6, "320x240", ("track",))
    p.sim("sim_cluttered_lab_handheld_fast", "cluttered_lab", "cluttered_lab_handheld_fast", 7,
          "320x240", ("track",))
    p.sim("sim_office_handheld", "office", "office_handheld", 1, "320x240",
          ("track", "seg", "cls"), group="segmentation")
    # Generated rooms nobody tuned on.
    kinds = {1001: ("handheld", "handheld_fast", "robot", "robot_fast"),
             1002: ("handheld", "robot")}
    for s, ks in kinds.items():
        g = p.gen(s)
        for kind in ks:
            evals = ("track", "seg", "cls") if kind == "handheld" else ("track",)
            p.sim(f"gen{s}_{kind}", g, g[:-5] + f"_{kind}.yaml", s, "320x240", evals,
                  group="segmentation" if "seg" in evals else "tracking", pool=f"gen_{kind}")
    # The mission's own path at the README default's resolution: the world-frame drift of a robot
    # map shows at 640x480.
    p.sim("sim_office_robot_loop_640", "office", "office_robot_loop", 1, "640x480", ("track",))
    for planner in ("ig", "ig_greedy", "frontier", "random", "lawnmower"):
        p.explore(f"explore_gen1001_{planner}", p.gen(1001), planner, 1001, 180, "320x240",
                  pool="explore_gen_" + planner)
    for planner in ("ig", "ig_greedy", "random"):
        p.explore(f"explore_office_{planner}", "office", planner, 1, 180, "320x240")


def full(p, seeds=range(1001, 1011), explore_seeds=(1001, 1002)):
    """Hours on 2 cores (made for --jobs on a bigger machine or --slurm): 640x480, ten generated
    rooms with every kind of path (and the hand-held one kidnapped), every planner on the three
    shipped worlds and two generated rooms for 180 simulated s, the kidnapping of the 60 s office
    sweep, and 24 laps of the memory check."""
    p.real("real_tum_fr1_xyz_first37", "ini/tum_fr1_xyz.ini", "tum/fr1_xyz_first37", "tum",
           evals=("track", "bench"))
    p.real("real_7scenes_redkitchen_first300", "ini/7scenes_redkitchen.ini",
           "7scenes/redkitchen_first300", "7scenes", evals=("track", "bench"))
    p.real("real_tum_fr3_cabinet_keyframes", None, "tum/fr3_cabinet_keyframes", "tum")
    # The shipped worlds, with the seeds of the earlier evaluations (comparable numbers).
    p.sim("sim_office_robot_loop", "office", "office_robot_loop", 1, "640x480", ("track",))
    p.sim("sim_office_robot_loop_no_odometry", "office", "office_robot_loop", 1, "640x480",
          ("track",), sets=("--set", "robot.use_odometry=false"))
    p.sim("sim_office_robot_fast", "office", "office_robot_fast", 3, "640x480", ("track",))
    p.sim("sim_two_rooms_robot", "two_rooms", "two_rooms_robot", 2, "640x480", ("track",))
    p.sim("sim_office_handheld_fast", "office", "office_handheld_fast", 6, "640x480", ("track",))
    p.sim("sim_cluttered_lab_handheld_fast", "cluttered_lab", "cluttered_lab_handheld_fast", 7,
          "640x480", ("track",))
    p.sim("sim_office_handheld", "office", "office_handheld", 1, "640x480",
          ("track", "seg", "cls"), group="segmentation")
    p.sim("sim_cluttered_lab_handheld", "cluttered_lab", "cluttered_lab_handheld", 1, "640x480",
          ("track", "seg", "cls"), group="segmentation")
    p.sim("sim_office_robot_loop_semantic", "office", "office_robot_loop", 1, "640x480",
          ("seg", "cls"), group="segmentation")
    # 60 s hand-held sweep that revisits the room; kidnapped: a 2 s cut at 41 s and 1 s of
    # covered lens at 50 s, where the sweep comes back over mapped space.
    p.sim("sim_office_handheld_long", "office", "office_handheld_long", 5, "640x480", ("track",))
    p.sim("sim_office_handheld_long_kidnap", "office", "office_handheld_long", 5, "640x480",
          ("track",), sets=("--set", "source.drop_frames=1230-1289",
                            "--set", "source.blank_frames=1500-1529"))
    # Generated rooms nobody tuned on: every kind of path; segmentation and classification on
    # the hand-held and robot ones.
    for s in seeds:
        g = p.gen(s)
        for kind in ("handheld", "handheld_fast", "robot", "robot_fast"):
            evals = ("track", "seg", "cls") if kind in ("handheld", "robot") else ("track",)
            p.sim(f"gen{s}_{kind}", g, g[:-5] + f"_{kind}.yaml", s, "640x480", evals,
                  group="segmentation" if "seg" in evals else "tracking", pool=f"gen_{kind}")
        # Kidnapped on an unseen room: a 2 s cut at half the hand-held sweep, 1 s of covered lens
        # at three quarters.
        n = spec_frames(g[:-5] + "_handheld.yaml")
        p.sim(f"gen{s}_handheld_kidnap", g, g[:-5] + "_handheld.yaml", s, "640x480", ("track",),
              pool="gen_handheld_kidnap",
              sets=("--set", f"source.drop_frames={n // 2}-{n // 2 + 59}",
                    "--set", f"source.blank_frames={3 * n // 4}-{3 * n // 4 + 29}"))
    # Exploration: every planner on the shipped worlds, generated rooms and flats, 240 simulated
    # s, on tracked poses (the mission's loop); the planners alone on true poses: planners().
    for w, seed in explore_worlds(p, explore_seeds):
        wname = os.path.basename(w)[:-5] if w.endswith(".yaml") else w
        for planner in PLANNERS:
            p.explore(f"explore_{wname}_{planner}", w, planner, seed, 240, "640x480",
                      pool=f"explore_gen_{planner}" if w.endswith(".yaml") else "")
    # Memory: 24 laps of the office loop (~10 simulated minutes) at 10 Hz.
    p.memory("memory_office_24laps", 24, "640x480")


PLANNERS = ("ig", "ig_greedy", "frontier", "random", "lawnmower", "oracle")


def explore_worlds(p, seeds, flat_seeds=(2001, 2002)):
    """(world, seed) of the exploration comparisons: the shipped worlds, generated rooms of
    `seeds` and flats of 3 and 4 rooms of `flat_seeds` (nobody tuned on any seed >= 1001)."""
    worlds = [("office", 1), ("cluttered_lab", 1), ("two_rooms", 1)]
    worlds += [(p.gen(s), s) for s in seeds]
    worlds += [(p.gen(s, rooms=3 + i % 2), s) for i, s in enumerate(flat_seeds)]
    return worlds


def planners(p, seeds=(1101, 1102, 1103, 1104, 1105),
             flat_seeds=(2101, 2102, 2103, 2104, 2105), run_seeds=2):
    """The planners alone (exploration group only): every planner on the shipped worlds, five
    generated rooms and five flats (3 and 4 rooms off a hallway), fused at the true poses
    ([mapper] poses = groundtruth: no tracking error mixed in), 240 simulated s at 160x120 (the
    planners see the same octree and map they would at 640x480, only sparser), each world with
    `run_seeds` seeds: the world's own seed s (tasks planners_<world>_<planner>) and s + 1, s + 2,
    ... (planners_<world>_<planner>_s2, ...: the same world, another sensor noise and planner
    randomness). 156 tasks, ~2.5 h on 2 cores."""
    worlds = explore_worlds(p, seeds, flat_seeds)
    shipped, rooms, flats = worlds[:3], worlds[3:3 + len(seeds)], worlds[3 + len(seeds):]
    # The generated worlds first (the targets are on them), a room and a flat in turn, so that a
    # panel stopped early has whole worlds of both kinds.
    mixed = [w for pair in zip(rooms, flats) for w in pair] + rooms[len(flats):] + flats[len(rooms):]
    for w, seed in mixed + shipped:
        wname = os.path.basename(w)[:-5] if w.endswith(".yaml") else w
        for k in range(run_seeds):
            for planner in PLANNERS:
                suffix = f"_s{k + 1}" if k else ""
                p.explore(f"planners_{wname}_{planner}{suffix}", w, planner, seed + k, 240,
                          "160x120", poses="groundtruth")


def worldframe(p, seeds=(3901, 3902, 3903, 3904, 3905),
               flat_seeds=(3951, 3952, 3953, 3954, 3955), run_seeds=2):
    """The map in the world frame while the robot explores (exploration and tracking groups):
    ig exploring five generated rooms, five flats (3 and 4 rooms) and two_rooms for 180 simulated
    s at 320x240, each world-seed twice, on tracked poses (wf_<world>_tracked) and fused at the
    true poses (wf_<world>_truth), the pair that shows what the tracking error costs the coverage;
    seeds s and s + 1 (_s2). scripts/scoreboard/worldframe_summary.py DIR states the targets
    (world-frame error, tilt, frames lost, coverage over the true poses'). Pairs come together,
    a room and a flat in turn, the first seed of every world first: a panel stopped early has
    whole pairs of both kinds. 44 tasks, ~1.5 h on 2 cores (the first seed: 39 min)."""
    rooms = [(p.gen(s), s) for s in seeds]
    flats = [(p.gen(s, rooms=3 + i % 2), s) for i, s in enumerate(flat_seeds)]
    mixed = [w for pair in zip(rooms, flats) for w in pair] + [("two_rooms", 1)]
    for k in range(run_seeds):
        for w, seed in mixed:
            wname = os.path.basename(w)[:-5] if w.endswith(".yaml") else w
            suffix = f"_s{k + 1}" if k else ""
            for poses, tag in (("tracked", "tracked"), ("groundtruth", "truth")):
                p.explore(f"wf_{wname}_{tag}{suffix}", w, "ig", seed + k, 180, "320x240",
                          poses=poses)


# The global tour before the planning grid's and the tour's frontier changes of 2026-12-07
# (docs/exploration.md "Rooms off the hallway"): the same binary, those changes switched off.
IG_BEFORE = ["--set", "exploration.frontier_max_radius_m=0",
             "--set", "exploration.clearance_from_unknown=true",
             "--set", "exploration.frontier_behind_m=0",
             "--set", "exploration.tour_object_context_radius_m=0",
             "--set", "exploration.tour_revisit_frontiers=true"]


def flats(p, worlds=((2101, 3), (2102, 4), (2103, 3), (2104, 4), (2105, 3), (2106, 3), (2107, 4))):
    """Multi-room flats at the mission's camera (640x480), true poses, 240 s, seed = the world's:
    ig, ig as it was before the frontier changes (flats_<world>_ig_before) and the oracle. 2101-2105
    were looked at while the changes were made, 2106 and 2107 were not. 21 tasks, ~2.5 h on 2
    cores."""
    for seed, rooms in worlds:
        w = p.gen(seed, rooms=rooms)
        wname = os.path.basename(w)[:-5]
        for planner, name, sets in (("ig", "ig", ()), ("ig", "ig_before", IG_BEFORE),
                                    ("oracle", "oracle", ())):
            p.explore(f"flats_{wname}_{name}", w, planner, seed, 240, "640x480",
                      poses="groundtruth", sets=sets)


PANELS = {"smoke": smoke, "quick": quick, "full": full, "planners": planners,
          "worldframe": worldframe, "flats": flats}


def main(argv):
    extra = []
    if "--" in argv:
        extra = argv[argv.index("--") + 1:]
        argv = argv[:argv.index("--")]
    if len(argv) != 5 or argv[1] not in PANELS:
        sys.exit(__doc__)
    _, panel, out, rasm, data = argv
    p = Panel(os.path.abspath(out), rasm, os.path.abspath(data), extra)
    PANELS[panel](p)
    tmp = os.path.join(out, "tasks.tsv.tmp")
    with open(tmp, "w") as f:
        f.write("task\tname\tgroup\tevals\tpool\tneeds\test_s\targs\n")
        for i, t in enumerate(p.tasks, 1):
            f.write(f"{i}\t{t['name']}\t{t['group']}\t{t['evals']}\t{t['pool']}\t{t['needs']}\t"
                    f"{t['est_s']}\t{shlex.join(t['args'])}\n")
    os.replace(tmp, os.path.join(out, "tasks.tsv"))


if __name__ == "__main__":
    main(sys.argv)
