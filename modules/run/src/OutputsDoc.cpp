// `rasm help outputs` / docs/outputs.md: what every file and field of a run folder holds. The
// frames.csv table is built from the Mapper's stage list; the meanings are the tables below (a
// field or column without an entry here fails tests/app/OutputsDoc_unittest.cpp).
#include "rasm/run/OutputsDoc.h"

#include <map>
#include <sstream>

#include "rasm/pipeline/Mapper.h"
#include "rasm/pipeline/OutputFiles.h"

namespace rasm::run {

using namespace rasm::pipeline;

namespace {

struct Doc {
  const char* name;
  const char* meaning;
};

// ---- the files of a run folder (OutputFolder::knownNames)
const Doc kFiles[] = {
    {"config.ini",
     "every key of the effective configuration (defaults included); "
     "`rasm run config.ini` repeats the run"},
    {"report.json", "the run's summary, written last and always (below)"},
    {"run.log",
     "every message of the run, one per line: UTC time, level (debug, info, warning, error), "
     "text; the console shows those from `[output] log_level` up (`rasm run -q` / `-v`)"},
    {"frames.csv", "one row per frame processed (below)"},
    {"trajectory.txt", "the estimated camera pose of every frame (below)"},
    {"groundtruth.txt", "the source's ground-truth poses, same format, when it has them"},
    {"map.ply", "the surfel map (below); `[output] write_ply`"},
    {"map.3Dscene",
     "the map as an MRPT scene (gzip; open with SceneViewer3D); `[output] "
     "write_3dscene`"},
    {"map.surfelmap",
     "the serialized `rasm::maps::CSurfelMap` with its relocalisation "
     "keyframes (gzip); `rasm run --map` continues in it; `[output] save_map`"},
    {"mesh.ply",
     "a triangle mesh of the map (binary PLY, vertex normals and RGB; MeshLab, Open3D, Blender): "
     "the stable surfels rendered at up to `[mesh] max_views` poses along the path, fused into a "
     "TSDF of `[mesh] voxel_m` cells, marching cubes; `[output] write_mesh`"},
    {"mesh_classes.ply",
     "mesh.ply with each vertex in the class colour of its nearest surfel, when a surfel carries "
     "a class"},
    {"preview.png", "the map rendered from the last pose; `[output] preview_png`"},
    {"plot_objects.png",
     "objects listed (frames.csv `objects`) and detections fused so far, per frame; "
     "`[output] preview_png`, when classification runs"},
    {"preview_segments.png", "the same view coloured by segment, when the map has segments"},
    {"preview_classes.png",
     "the same view coloured by class (faded to grey as the probability "
     "falls to 0.5; black: no surfel), once the map carries classes"},
    {"segments.json", "the segment table (below); `[segmentation] enabled`"},
    {"map_segments.ply", "map.ply's layout, coloured by segment; `[output] write_ply`"},
    {"map_segments.3Dscene", "map.3Dscene coloured by segment, when the map has segments"},
    {"classes.json", "the map's class list (below); `[classification] enabled`"},
    {"classes_legend.png",
     "the key to the class colours: each class that is some stable surfel's best, its colour, "
     "name and surfel count"},
    {"objects.json",
     "the objects (each once, over its segments) and the other classified segments (below); "
     "`rasm objects <run folder>` prints them"},
    {"map_classes.ply", "map.ply's layout, coloured by class; `[output] write_ply`"},
    {"map_classes.3Dscene", "map.3Dscene coloured by class, when a surfel carries one"},
    {"exploration.json", "an exploring run's plans, goals and ground-truth metrics (below)"},
    {"exploration.png", "coverage (blue) and objects correct (red) against simulated time"},
    {"plot_trajectory.png",
     "top view of the estimated path over the ground truth (when there is one), lost frames "
     "in red"},
    {"plot_timing.png",
     "ms per frame of each stage, stacked so the layers add up to the frame's total (10-frame "
     "running means), from frames.csv"},
    {"plot_tracking.png",
     "per frame: ICP inlier fraction and pose-check agreement, ICP residual (mm) and, with "
     "ground truth, the world-frame position error (cm, no alignment); lost frames shaded red"},
    {"floorplan.png",
     "the map from above: floor, furniture and walls, the camera path, goals, each object's "
     "outline with its class and probability, a legend, a scale bar; the caption says how up "
     "was found (world z in the simulator, else the map's horizontal surfaces near the "
     "cameras' up, `run/FloorPlan.h`); `[output] floorplan`"},
    {"floorplan.svg", "the same plan with the labels, path and outlines as vectors"},
    {"annotated.rawlog",
     "`[output] write_rawlog`: each input observation with the estimated pose "
     "as sensorPose, followed by `MAP_VIEW` (the map rendered from it) and, "
     "once the map carries classes, `CLASS_VIEW` images; for RawLogViewer"},
};

// ---- report.json
const Doc kReport[] = {
    {"report_schema", "version of this layout (an integer; see \"Schema versions\")"},
    {"frames_schema", "version of frames.csv's columns (frames.csv itself has only its header)"},
    {"rasm",
     "the binary: `version`, `commit` (git SHA-1; `-dirty`: built with uncommitted "
     "changes; `unknown`: not built from git), `build_date` (UTC)"},
    {"started_utc", "when the run started, ISO 8601 UTC (`2025-01-31T14:05:09Z`)"},
    {"finished_utc", "when report.json was written, ISO 8601 UTC"},
    {"status",
     "`ok`, `failed` (see `error`), `interrupted` (SIGINT / SIGTERM: the outputs hold "
     "the frames done) or `aborted` (a second signal: only complete files, a short "
     "report)"},
    {"error",
     "why the run failed (bad input, an output that could not be written, or nothing fused: an "
     "empty map or every frame lost)"},
    {"interrupted_by", "`SIGINT` or `SIGTERM`"},
    {"files_listed_in",
     "`aborted` only: the short report has no `files`; the run folder's marker (.rasm-run.json) "
     "lists every name the run may have written, and those present are complete"},
    {"interrupted_during", "`frames` or `outputs`"},
    {"config_source", "the INI file, or the embedded default"},
    {"source", "the frame source, in words (with a WARNING when its intrinsics are a guess)"},
    {"intrinsics",
     "the camera intrinsics the frames were mapped with: fx, fy, cx, cy (pixels), "
     "width, height"},
    {"files", "the files this run wrote, in order (report.json itself excluded)"},
    {"frames", "frames processed"},
    {"frames_read", "frames the source yielded (before start_frame / frame_step / drop_frames)"},
    {"frames_tracked", "frames tracked (frames - frames_lost)"},
    {"frames_lost", "frames whose tracking failed (their pose propagated; frames.csv tracked = 0)"},
    {"tracked_fraction", "frames_tracked / frames"},
    {"lost_intervals", "runs of consecutive lost frames"},
    {"longest_lost_interval_frames", "the longest of them, in frames"},
    {"relocalisations", "times tracking was found again against the map's keyframes"},
    {"loop_closure",
     "`[loop_closure]`: `enabled`, `checks` (frames registered against the map made long ago), "
     "`refused` (corrections beyond the drift bound), `closed` and `loops`: per loop closed the "
     "`frame`, `timestamp_s`, `old_map_time_s`, `correction_m`, `correction_deg`, `path_m` "
     "since the old map, `surfels_moved`, `ms`"},
    {"frames_off_floor",
     "tracked robot frames whose camera left the first frame's floor "
     "(`[robot] floor_max_height_m` / `floor_max_tilt_deg`)"},
    {"frames_before_map",
     "frames skipped before the map started: too little valid depth to start it (fewer valid "
     "pixels than `[tracking] min_inliers`, at most a tenth of the image); not fused, counted in "
     "frames_lost"},
    {"warnings", "the run's warnings, when it has any (a late map start)"},
    {"floor_drift",
     "robot runs with odometry: the tracked frames' camera against the first frame's floor and "
     "the mount, no ground truth needed: `frames`, `height_error_m` {median, max} (of "
     "the absolute floor_height_m), `tilt_deg` {median, max}, `target_height_m`, "
     "`target_tilt_deg`, "
     "`max_fraction` (`[robot] floor_target_*`), `frames_beyond_target`, "
     "`fraction_beyond_target`, `drifted` (fraction_beyond_target > max_fraction: the run's "
     "warning), `comment`"},
    {"keyframes", "relocalisation keyframes in the map"},
    {"seconds", "wall time of the frame loop (s), without a preload"},
    {"preloaded", "whether the frames were decoded before the clock started (`[source] preload`)"},
    {"preload_seconds", "time the preload took (s), with preload"},
    {"fps", "frames / seconds"},
    {"cpu_ms_per_frame", "CPU time of the whole process (all threads) per frame, ms"},
    {"surfels", "surfels in the final map"},
    {"map_memory_bytes", "memory of the final map's arrays, bytes"},
    {"peak_rss_mb", "peak resident memory of the process (VmHWM), MB"},
    {"stages",
     "per timer (every stage, its parts, `map_lock_wait`, `total`; the frames.csv "
     "`ms_*` columns): `mean_ms` over the frames and `max_ms`"},
    {"stage_order",
     "the stages' own timers in pipeline order (each holds its parts; with the rest of the "
     "frame they add up to `total`): what plot_timing.png and scripts/plots.py stack"},
    {"final_pose",
     "the last good camera pose T_world_cam (optical frame): `t` [x, y, z] m, "
     "`q_xyzw`"},
    {"ate",
     "with ground truth: ATE after SE(3) alignment over every frame (lost ones at their "
     "propagated pose), "
     "as `rasm eval ate --json` writes it: `translation_m` {rmse, mean, median, std, min, "
     "max, count}, `pairs`, `alignment` {T_gt_est, scale}, `options`"},
    {"ate_tracked", "the same over the tracked frames only"},
    {"world_frame_error",
     "with ground truth, when the run started at its pose (first estimate within 1 mm and 0.05 "
     "deg): the error in the world frame, **without** alignment (the aligned `ate` rotates a "
     "tilt and lifts a height drift away): `started_at_ground_truth`, `comment`, `all` (every "
     "frame) and `tracked` (tracked frames), each {`pairs`, `position_m`, `vertical_m` (along "
     "the world's up, z), `horizontal_m`, `tilt_deg` (angle between the estimated and the true "
     "camera's up direction: roll and pitch, not heading), `heading_deg` (rotation about the "
     "world's up: the yaw error, which becomes horizontal drift as the robot drives), each "
     "{rmse, mean, median, std, min, max, count}; `start_error`, `options`}; when the run did not "
     "start there, only `started_at_ground_truth` false, `start_error` and `comment`"},
    {"ate_error", "why the ground truth ([source] groundtruth) could not be read"},
    {"ate_tracked_error", "why the ATE over the tracked frames could not be computed"},
    {"segmentation",
     "segmentation (III): `enabled`, `frames_segmented`, `merges`, "
     "`psi_pairs_max`, `label_changes_stable`, `stable_surfels`, `segments`"},
    {"classification",
     "classification (IV): `enabled`, `threaded`, `every_n_frames`, "
     "`frames_offered`, `results_fused`, `detections`, `detections_fused`, "
     "`detections_without_segment`, `surfel_updates`, `pose_consensus` {`enabled`, "
     "`detections_released`, `detections_held` (zero-shot detections whose views never agreed "
     "on the object's orientation, never fused)}, "
     "`surfel_updates_dropped`, `class_evidence_bytes_per_surfel`, `classes`, "
     "`detectors` [{name, frames_offered, frames_detected, frames_skipped, "
     "detections, ms_per_call, ms_max, disabled}], `warnings`, `objects`, "
     "`objects_by_class` {class: count}; a simulated source that is not explored adds "
     "`objects_correct` and `objects_detectable` (against the world's truth, at the end)"},
    {"occupancy",
     "the exploration octree (V): `frames_inserted`, `resolution_m`, "
     "`entropy_nats`, `workspace_cells`, `cells_free`, `cells_occupied`, "
     "`cells_unknown`"},
    {"exploration",
     "an exploring run: `planner`, `plans`, `goals`, `goals_reached`, "
     "`goals_not_reached`, `objects_correct`, `objects_detectable`, "
     "`time_to_90_coverage_s` (null: not reached), `ground_truth` (false on a real robot: no "
     "coverage or object metrics), `navigation` {`stepping` (`substeps`: the simulator's, "
     "between frames; `thread`: a thread of its own on the wall clock), `steps` and `rate_hz` "
     "(thread)}, `metrics_cover`"},
    {"coverage_fraction",
     "exploring run: fraction of the world's observable surface within 2 cm "
     "of a stable surfel, at the end (null on a real robot: no ground truth)"},
    {"objects_correct_fraction",
     "simulated source (or an exploring run): detectable objects of the world carrying their "
     "class, at the end (null on a real robot)"},
    {"real_time",
     "`[source] real_time` or a live camera: `paced_by`, `frames_offered`, `frames_dropped` "
     "(arrived while the mapper was busy), `frames_processed`, `offered_fps`, "
     "`processed_fps`, `dropped_frames` (index ranges, e.g. \"3-5,9\")"},
    {"robot",
     "`[robot] type = segway_rmp`: `type`, `address`, `link_ok`, `commands_sent`, `responses`, "
     "`bad_responses`, `watchdog_stops`, `operational_state`, `fault_status`, "
     "`battery_soc_pct`, `odometry_xyyaw` (docs/hardware.md)"},
    {"path_length_m", "exploring run: distance the robot drove (m)"},
    {"sim_time_s",
     "exploring run: seconds since the first frame (simulated time; wall time on a real robot)"},
    {"stop_reason",
     "exploring run: `time_budget`, `path_budget`, `wall_budget`, "
     "`information_gain_below_threshold`, `no_reachable_views`, `planner_done`, "
     "`source_end`, `interrupted` or `error`"},
};

// ---- frames.csv
const Doc kColumns[] = {
    {"index", "the frame's index as its source numbers it"},
    {"timestamp_s", "the frame's timestamp (s; the source's clock)"},
    {"tracked", "1 when tracking succeeded, 0 while lost (the pose is then propagated)"},
    {"status",
     "ICP outcome: ok, degenerate, too_few_inliers, high_residual, excessive_motion, "
     "inconsistent, prior_conflict, diverged, not_initialized (docs/tracking.md)"},
    {"inliers", "ICP inliers at full resolution"},
    {"inlier_fraction", "inliers / valid frame pixels at full resolution"},
    {"rms_m", "RMS point-to-plane residual of the inliers (m)"},
    {"model_pixels", "valid pixels of the model rendered for ICP"},
    {"model_all_surfels",
     "1 when the model was rendered from every surfel: the stable-only one was too sparse, or "
     "the frame failed against it for lack of support and was retried (docs/tracking.md)"},
    {"icp_iterations", "ICP iterations, all pyramid levels"},
    {"icp_iterations_level0", "of those, at full resolution"},
    {"pose_source", "tracked, odometry, motion_model or relocalised"},
    {"check_overlap", "pose check: fraction of the frame's pixels landing on the model"},
    {"check_agreement", "of those, fraction agreeing with the model's surface"},
    {"check_behind", "of those, fraction lying behind it"},
    {"used_prior", "1 when the odometry motion prior was used"},
    {"on_motion_model",
     "1 when a degenerate frame was accepted on the constant-velocity guess alone (no prior)"},
    {"prior_sigmas", "Mahalanobis distance of the result from the prior"},
    {"odometry_sigmas", "the same in the odometry's directions only (x, y, yaw)"},
    {"heading_drift_sigmas", "accumulated heading disagreement with the odometry, in sigmas"},
    {"floor_height_m",
     "robot camera height above the first frame's floor (m); nan without "
     "odometry"},
    {"floor_tilt_deg", "its tilt from the first frame's (deg); nan without odometry"},
    {"relocalisation_failure", "while lost: why relocalisation found nothing this frame"},
    {"loop_closure",
     "`[loop_closure]`: on frames registered against the map made more than inactive_after_s "
     "ago: agrees, candidate (waiting for confirmation), closed, refused (beyond the drift bound: "
     "a false loop), unconfirmed: <why> (the colour or the features put the camera elsewhere), "
     "unregistered: <why> (ICP against that part of the map failed); empty otherwise"},
    {"loop_correction_m", "the correction of the camera position that registration asked for (m)"},
    {"loop_correction_deg", "and of its orientation (deg)"},
    {"seg_frame_segments", "segments of this frame's edge map (III)"},
    {"seg_matched", "of those, matched to a map segment"},
    {"seg_created", "new map segments"},
    {"seg_merged", "segment merges this frame"},
    {"seg_psi_pairs", "segment pairs with merge evidence (Psi)"},
    {"valid_pixels", "pixels with a valid vertex and normal in the depth range"},
    {"associated", "pixels associated with a surfel (II-D)"},
    {"added", "new surfels (II-B)"},
    {"removed_unstable", "old unstable surfels removed"},
    {"removed_carved", "surfels removed as free-space violators"},
    {"merged", "redundant surfels merged"},
    {"surfels", "surfels in the map after the frame"},
    {"cls_detections", "detections fused this frame (IV)"},
    {"cls_fused", "of those, associated with a segment"},
    {"cls_pending", "detector results waiting to be fused"},
    {"objects",
     "objects the object layer would list now (objects.json's rule, as of the last results "
     "fused; the final list is regrouped with the final segments)"},
    {"octree_updated", "1 when the frame was inserted into the exploration octree"},
    {"rss_mb", "resident memory of the process after the frame (MB)"},
    {"map_memory_bytes", "memory of the map's arrays after the frame (bytes)"},
    {"objects_correct",
     "simulated source: detectable objects of the world whose class the map names right "
     "(SimObjectScore), measured every [output] objects_score_period_s of the sequence (an "
     "exploring run: every [exploration] metrics_period_s) and on the last row after the run's "
     "final regrouping; empty on the other rows"},
    {"objects_detectable",
     "simulated source: detectable (COCO class) objects of the world, on "
     "the rows that measured objects_correct"},
};

// ---- the JSON files of the stages, the trajectory and the PLY layout
const char* kOtherFiles = R"doc(## trajectory.txt, groundtruth.txt

TUM format: `#` comment lines, then one line per frame `timestamp tx ty tz qx qy qz qw`
(seconds; metres; the camera pose T_world_cam in the optical frame: x right, y down, z forward).
Every frame has a pose: while tracking is lost it is propagated (frames.csv `pose_source`).
`rasm eval ate groundtruth.txt trajectory.txt` compares them.

## segments.json (III)

`comment`; `stable_surfels` (stable surfels in the final map); `label_changes_stable` (how often
a stable surfel's segment changed); `segments`: one entry per segment of the final map:
`id` (the PLY `segment`), `surfels`, `stable_surfels`, `centroid` [x, y, z], `axes` (3 unit PCA
directions, by decreasing variance), `extents_m` (spread of the surfel centres along them, 1st-99th
percentile), `upright_axes` (the two horizontal principal directions; z is up),
`upright_extents_m`, `bbox_min`, `bbox_max`, `last_seen_s` (map time). World frame, metres.

## objects.json (IV)

`comment`; `objects`: the objects of the object layer (`classification/ObjectMap.h`), each once:
one or more segments whose own classes agree with `[objects] link_min_probability`, whose boxes
touch (`link_max_gap_m`) and which detections saw together (`link_min_codetection_fraction`) or,
never in one view, one's box mostly inside the other's (`link_min_box_containment`), reported when the object's class reaches `[classification]
min_object_probability`, it holds at least `min_object_surfels` surfels and `min_object_size_m` of
extent, it is not a thin plane larger than `structure_min_extent_m` both ways nor a thin plane in
the plane of one (`structure_piece_*`: a piece of the floor), and its existence
probability reaches `[objects] min_existence_probability`. Each object: `id` (kept over the run
while its segments merge, change or are joined), `class` (best of its histogram), `class_id`
(classes.json id), `probability`, `runner_up`, `runner_up_probability`, `histogram` [{`class`,
`class_id`, `probability`}] (up to 4 classes by decreasing posterior: the log-odds of every
detection fused into its segments, IV), `existence_probability` ((`views_detected` + 1) /
(`views` + 2)), `views` (frames a detector that reports its class processed in which a segment of
it covered `min_view_pixels` of L^p, or a detection went to it), `views_detected`, `frames`
{`first_seen`, `last_seen`, `seen`, `detected`} (frame indices and counts over every detector),
`segments` (the PLY `segment` ids), `surfels`, `detections_fused`, `centroid`, `box` {`min`,
`max`, `centre`, `size_m`} (axis-aligned, over its segments), `oriented_box` {`centre`, `axes`
(upright, z up; its largest segment's), `extents_m`}; `pose_hint` {`class`, `azimuth_deg`,
`elevation_deg`, `template`, `score`} when the zero-shot detector matched a template.
`other_segments`: the segments of the objects not reported that carry a class or had detections
fused: `segment`, `object` (its object's id), `class` (`none` below min_object_probability),
`class_id`, `best_class`, `probability` (the segment's own histogram), `detections_fused`,
`surfels`, `centroid`, `pca_extents_m`, `oriented_box`, `not_an_object` (its object's reason:
`unconfirmed`, `fragment`, `structure` or `rarely_detected`). World frame, metres.

## classes.json (IV)

`comment`; `none_colour` [r, g, b]; `classes`: [{`id`, `name`, `source`, `colour`}]: the ids of
the surfel class evidence and of the PLY `class` column (1-based; 0 = none). `source`: `coco` (the
80 COCO classes, in order), `rasm` (the project's own) or the detector that added the name.
`colour` [r, g, b]: the class's colour in map_classes.ply / .3Dscene and preview_classes.png at
probability 1; it fades towards `none_colour` as the probability falls to the 0.5 prior.

## exploration.json (V, VI)

`comment`; `planner`; `stop_reason` (as in report.json); `plans`: one per plan {`t` (simulated s
when planned), `applied_t`, `robot` [x, y, yaw rad], `reachable`, `unreachable`, `blacklisted`
(candidate views), `best_entropy_reduction`, `best_information`, `ms` (the whole plan, wall
clock), `snapshot_ms` (of it: copying the map and indexing the copy), `while_driving`, `low`
(counts towards the stopping rule), `best` {`pose`, `source` (object, frontier, sweep, random),
`gain`, `rate`, `path_length_m`}, `current_goal_score`, `frontiers` (`ig`, `frontier`: the
planning grid's frontiers {`centroid` [x, y], `cells`, `found`: whether a reachable cell near it
gave it a view}), and for `ig` `tour_clusters`,
`screened_out` and `tour`: the clusters' views in tour order {`pose`, `source`, `gain`,
`entropy_reduction`, `information`, `entropy_behind` (a frontier view: the best dH of the views
past the frontier), `weight` (the tour's weight), `travel_time_s`}}; `goals`: the goals driven to {`goal`
[x, y, yaw], `t_start`, `t_end`, `source`, `outcome` (reached, switched, stopped or the
navigator's failure), `gain`, `entropy_reduction`, `information`, `route` (the waypoints [x, y]
the navigator passed first: the planned path's corners, through doorways)}; `metrics`: over time {`t`,
`frames`, `path_m`, `entropy_nats`, `surfels`, and with the simulator's ground truth `coverage`,
`objects_correct_fraction`, `objects_correct`, `objects_detectable`}. Times in s since the first
frame; poses in the map frame.

## map.ply, map_segments.ply, map_classes.ply

Binary little-endian PLY, one `vertex` per surfel, in this order:

| property | type | meaning |
|---|---|---|
| `x` `y` `z` | float | position (m, world frame) |
| `nx` `ny` `nz` | float | unit normal |
| `red` `green` `blue` | uchar | colour (map.ply); the segment's / class's colour in the others |
| `radius` | float | surfel radius (m) |
| `confidence` | float | accumulated confidence (II-B) |
| `segment` | int | segment id (segments.json `id`; 0 = none) |
| `class` | int | best class id (classes.json; 0 = none above the 0.5 prior) |
| `class_probability` | float | its probability |
| `stable` | uchar | 1 when the surfel is stable (confidence above the threshold) |

Open3D (`o3d.t.io.read_point_cloud`), PCL, CloudCompare and MeshLab read every column (`int`,
not `uint`, which Open3D's tensor reader drops). `rasm sim check-map` and `rasm eval
segmentation` read them back.

## Sweeps (scripts/sweep.sh, rasm sweep gather)

`scripts/sweep.sh` runs a grid of independent `rasm run`s: worlds x planners x seeds of exploring
simulated runs, or `--inputs` (INI files, rawlogs, dataset folders) x `--seeds`; arguments after
`--` go to every task (`--set source.max_frames=300`). Locally GNU parallel runs the tasks
(`--jobs J`); `--slurm file.sbatch` writes a Slurm array job instead and runs nothing. Both run
the same command per task, `run_task.sh N`. Then `rasm sweep gather <sweep folder>`.

```
scripts/sweep.sh --out sweeps/planners --worlds "office two_rooms" --planners "ig frontier" \
    --seeds "1 2 3" --jobs 2 -- --set exploration.time_budget_s=120
scripts/sweep.sh --out sweeps/real --inputs "ini/tum_fr1_xyz.ini ini/7scenes_redkitchen.ini"
scripts/sweep.sh --out /cluster/sweeps/a --seeds "$(seq -s ' ' 1 20)" --slurm a.sbatch \
    --slurm-time 00:30:00 --sbatch --partition=cpu   # then: sbatch a.sbatch
rasm sweep gather /cluster/sweeps/a                  # after the array job
```

The sweep folder:

| file | content |
|---|---|
| `tasks.tsv` | one line per task: `task` (1..N), `name`, `world`, `planner`, `seed`, `input`, `args` (the `rasm run` arguments, shell-quoted) |
| `run_task.sh` | `run_task.sh N` runs task N: `rasm run <args>` into `runs/<name>/` (`RASM=` overrides the binary) |
| `runs/<name>/` | the task's run folder (everything above) |
| `runs/<name>.log` | the command and its output |
| `joblog.tsv` | GNU parallel's job log (exit value and time per task; `--resume` skips the done ones) |
| `slurm/` | the array job's output files (`%A_%a.out`), with `--slurm` |
| `results.md`, `results.json`, `results.csv` | `rasm sweep gather`: one row per task: the task's columns, then `status` (`missing`: no report.json yet), `frames`, `tracked_fraction`, `ate_cm`, `fps`, `segments`, `objects`, `coverage`, `objects_correct`, `path_m`, `sim_s`, `wall_s`, `stop_reason`, `commit`, `error` (empty where a run has no such field); results.json adds `sweep`, `tasks` and `not_ok` |
| `exploration.md`, `exploration.json` | when every finished task explored: `rasm eval exploration`'s table over them (by world and planner, means over the seeds) |
)doc";

std::map<std::string, std::string> toMap(const Doc* begin, const Doc* end) {
  std::map<std::string, std::string> m;
  for (const Doc* d = begin; d != end; ++d) m[d->name] = d->meaning;
  return m;
}

/// The meaning of a timer's ms_ column, from the stage list: a stage, a part of one, or the
/// Mapper's own.
std::string timerMeaning(const Mapper& mapper, const std::string& timer) {
  if (timer == "total") return "the whole frame in the Mapper (ms)";
  if (timer == "map_lock_wait")
    return "time the mapping thread waited for a map snapshot to finish copying (ms)";
  for (const auto& s : mapper.stages()) {
    if (s->name() == timer) return "the `" + timer + "` stage (ms, its parts included)";
    for (const std::string& p : s->parts())
      if (p == timer) return "part of the `" + s->name() + "` stage (ms)";
  }
  return "";
}

void table(std::ostringstream& md, const Doc* begin, const Doc* end) {
  md << "| field | meaning |\n|---|---|\n";
  for (const Doc* d = begin; d != end; ++d)
    md << "| `" << d->name << "` | " << d->meaning << " |\n";
}

}  // namespace

std::vector<CsvColumnDoc> framesCsvColumns(const Mapper& mapper) {
  static const std::map<std::string, std::string> meanings =
      toMap(std::begin(kColumns), std::end(kColumns));
  const auto meaning = [&](const std::string& c) {
    const auto it = meanings.find(c);
    return it == meanings.end() ? std::string() : it->second;
  };
  std::vector<CsvColumnDoc> out;
  for (const char* c : {"index", "timestamp_s", "tracked"})
    out.push_back({c, "mapper", meaning(c)});
  for (const auto& s : mapper.stages()) {
    std::vector<std::string> cols;
    s->csvColumns(cols);
    for (const std::string& c : cols) out.push_back({c, s->name(), meaning(c)});
  }
  for (const std::string& t : mapper.timerNames())
    out.push_back({"ms_" + t, "mapper", timerMeaning(mapper, t)});
  for (const std::string& c : runCsvColumns()) out.push_back({c, "run", meaning(c)});
  return out;
}

std::string outputsDocumentation(const Mapper& mapper) {
  std::ostringstream md;
  md << "# The outputs of `rasm run`\n\n"
        "<!-- Generated by `rasm help outputs` (modules/run/src/OutputsDoc.cpp and the "
        "Mapper's stage list): regenerate with `build/rasm help outputs > docs/outputs.md`. -->\n\n"
        "One folder per run (`[output] dir`, `rasm run --out DIR`; created when missing, in a "
        "folder that must exist). Files are written to "
        "temporary names and renamed when complete; `report.json` comes last and always. "
        "`.rasm-run.json` lists the files the run wrote: the next run into the folder removes "
        "those and nothing else, and refuses a folder holding other files unless `--force` "
        "(`[output] overwrite = true`); `.rasm.lock` keeps a second run out while one runs "
        "(docs/io.md \"What rasm writes, what it never touches, what it refuses\").\n\n"
        "## Schema versions\n\n"
        "report.json carries `report_schema` (now "
     << kReportSchema << ") and `frames_schema` (now " << kFramesSchema
     << "), the binary's version and git commit and the run's date. A version goes up when a "
        "field or column is renamed, removed or changes its meaning or unit; new fields and "
        "columns are added without a change, so read CSV columns by name. frames.csv has a "
        "plain header row and no comment line, so every CSV reader takes it.\n\n"
        "## Files\n\n"
        "| file | content |\n|---|---|\n";
  const std::map<std::string, std::string> files = toMap(std::begin(kFiles), std::end(kFiles));
  for (const std::string& f : OutputFolder::knownNames()) {
    const auto it = files.find(f);
    md << "| `" << f << "` | " << (it == files.end() ? "(undocumented)" : it->second) << " |\n";
  }
  md << "\n## report.json\n\nOne JSON object; fields that do not apply to a run are absent.\n\n";
  table(md, std::begin(kReport), std::end(kReport));
  md << "\n## frames.csv\n\nA header row, then one row per frame processed, comma-separated; "
        "columns in this order (built from the Mapper's stages: a stage's columns, then one "
        "`ms_` column per timer):\n\n| column | written by | meaning |\n|---|---|---|\n";
  for (const CsvColumnDoc& c : framesCsvColumns(mapper))
    md << "| `" << c.name << "` | " << c.writer << " | "
       << (c.meaning.empty() ? "(undocumented)" : c.meaning) << " |\n";
  md << "\n" << kOtherFiles;
  return md.str();
}

}  // namespace rasm::run
