"""The scoreboard's metrics in one place (scripts/scoreboard.sh, docs/scoreboard.md).

Every column of docs/results.md and every metric of docs/results.json is declared here once:
its key in a row file (rows/<task>.json "metrics"), its column label, how to print it, which
direction is better and how large a change must be before `--compare` calls it better or worse
(the noise threshold), and how a pooled row over generated worlds combines the runs.

Noise rule: a change from `prev` to `cur` is beyond noise when
    |cur - prev| > max(abs_noise, rel_noise * |prev|)
so "ATE +-20% and +-0.5 cm" is abs_noise 0.5 (cm), rel_noise 0.20: a change must exceed both.
`better` is "low" (lower is better: errors, times, memory), "high" (fractions recovered or
correct, frame rates) or None (context: counts, path length; never compared).
"""

from dataclasses import dataclass, field
from typing import Optional, Tuple


@dataclass(frozen=True)
class Metric:
    key: str                    # key in a row's "metrics"
    label: str                  # column header in results.md
    fmt: str = ".2f"            # format spec; "d" for counts, "s" for text
    better: Optional[str] = None  # "low", "high" or None (not compared)
    abs_noise: float = 0.0      # in the metric's unit
    rel_noise: float = 0.0      # fraction of the previous value
    # Pooled row over generated worlds: "median" of the runs, "sum" (counts), or
    # ("ratio", numerator key, denominator key): sum over the runs of one / sum of the other.
    pool: object = "median"
    md: bool = True             # a column of results.md (False: results.json only)

    def noise(self, prev: float) -> float:
        return max(self.abs_noise, self.rel_noise * abs(prev))


def ratio(num: str, den: str) -> Tuple[str, str, str]:
    return ("ratio", num, den)


# ---- tracking (`track`): report.json, trajectory.txt vs groundtruth.txt, rasm eval ate / rpe -----
TRACKING = [
    Metric("frames", "frames", "d", pool="sum"),
    Metric("frames_tracked", "tracked frames", "d", pool="sum", md=False),
    Metric("tracked_fraction", "tracked", ".3f", "high", 0.01, 0.0,
           pool=ratio("frames_tracked", "frames")),
    Metric("ate_all_cm", "ATE all (cm)", ".2f", "low", 0.5, 0.20),
    Metric("ate_tracked_cm", "ATE tracked (cm)", ".2f", "low", 0.5, 0.20),
    Metric("ate_sim3_cm", "ATE Sim(3) (cm)", ".2f", "low", 0.5, 0.20, md=False),
    Metric("rpe_1s_cm", "RPE 1 s (cm)", ".2f", "low", 0.3, 0.20),
    Metric("rpe_1s_deg", "RPE 1 s (deg)", ".2f", "low", 0.2, 0.20, md=False),
    Metric("silent_frames", "silent >5 cm", "d", "low", 3, 0.20, pool="sum"),
    Metric("off_floor_frames", "off floor >5 cm", "d", None, pool="sum"),
    Metric("lost_intervals", "lost intervals", "d", None, pool="sum"),
    Metric("relocalisations", "relocs", "d", None, pool="sum"),
    Metric("reloc_delay_max_frames", "reloc delay max", "d", "low", 5, 0.5, md=False),
    # Unaligned world-frame error (simulated runs, which start at the true pose): what the
    # aligned ATE hides (height and tilt drift). z is the world's up axis.
    Metric("pos_max_cm", "unaligned max (cm)", ".1f", "low", 1.0, 0.20),
    Metric("pos_rms_cm", "unaligned RMS (cm)", ".1f", "low", 0.5, 0.20),
    Metric("z_max_cm", "z max (cm)", ".1f", "low", 0.5, 0.20),
    Metric("z_rms_cm", "z RMS (cm)", ".1f", "low", 0.5, 0.20),
    # report.json world_frame_error.all.tilt_deg.max: the camera's up direction against the
    # truth's (roll and pitch, not heading), the floor's tilt.
    Metric("tilt_max_deg", "tilt max (deg)", ".2f", "low", 0.05, 0.20),
    # ... .heading_deg.rmse: the yaw error about the world's up, which becomes horizontal drift
    # at (distance driven) x (heading error) (docs/results-worldframe.md "Heading").
    Metric("heading_rms_deg", "heading RMS (deg)", ".2f", "low", 0.05, 0.20),
    Metric("unaligned_over_5cm", "unaligned >5 cm", "d", None, pool="sum", md=False),
]

# ---- segmentation (`seg`): rasm eval segmentation ------------------------------------------------
SEGMENTATION = [
    Metric("seg_objects_evaluated", "objects", "d", pool="sum"),
    Metric("seg_objects_recovered", "recovered", "d", pool="sum"),
    Metric("objects_recovered_fraction", "recovered fraction", ".3f", "high", 0.05, 0.0,
           pool=ratio("seg_objects_recovered", "seg_objects_evaluated")),
    Metric("pq", "PQ", ".3f", "high", 0.03, 0.0),
    Metric("sq", "SQ", ".3f", None),
    Metric("rq", "RQ", ".3f", None),
    Metric("segments_per_object", "segments/object", ".2f", None),
    Metric("undersegmented_objects", "under-segmented", "d", "low", 1, 0.20, pool="sum"),
    Metric("label_changes_per_stable_surfel", "label changes/stable surfel", ".3f", "low",
           0.005, 0.20),
    Metric("seg_ms", "segmentation ms/frame", ".1f", "low", 0.5, 0.15),
]

# ---- classification (`cls`): rasm eval classification -------------------------------------------
CLASSIFICATION = [
    Metric("cls_objects_evaluated", "objects", "d", pool="sum"),
    Metric("cls_objects_correct", "correct", "d", pool="sum"),
    Metric("object_accuracy", "object accuracy", ".3f", "high", 0.05, 0.0,
           pool=ratio("cls_objects_correct", "cls_objects_evaluated")),
    Metric("segmented_coco_objects", "segmented COCO objects", "d", pool="sum", md=False),
    Metric("segmented_coco_accuracy", "segmented COCO accuracy", ".3f", "high", 0.05, 0.0),
    Metric("macro_precision", "macro precision", ".3f", "high", 0.05, 0.0),
    # Object level (objects.json): a reported object counts when it covers an object of its
    # class with IoU > 0.5 (ClassificationMetrics.h).
    Metric("objects_reported", "objects listed", "d", pool="sum"),
    Metric("objects_reported_correct", "listed right", "d", pool="sum", md=False),
    Metric("object_precision", "object precision", ".3f", "high", 0.05, 0.0,
           pool=ratio("objects_reported_correct", "objects_reported")),
    Metric("objects_coco", "COCO objects", "d", pool="sum", md=False),
    Metric("objects_found", "objects found", "d", pool="sum", md=False),
    Metric("object_recall", "object recall", ".3f", "high", 0.05, 0.0,
           pool=ratio("objects_found", "objects_coco")),
    Metric("detections_fused", "detections fused", "d", pool="sum"),
    Metric("detections", "detections", "d", pool="sum"),
]

# ---- exploration (`expl`): rasm eval exploration, one run --------------------------------------
# coverage_T / objects_correct_T: at T simulated seconds (null beyond the task's time budget).
EXPLORATION = [
    Metric("coverage_60", "coverage @60 s", ".3f", "high", 0.03, 0.0),
    Metric("coverage_120", "coverage @120 s", ".3f", "high", 0.03, 0.0),
    Metric("coverage_180", "coverage @180 s", ".3f", "high", 0.03, 0.0),
    Metric("objects_correct_60", "objects correct @60 s", ".3f", "high", 0.05, 0.0),
    Metric("objects_correct_120", "objects correct @120 s", ".3f", "high", 0.05, 0.0),
    Metric("objects_correct_180", "objects correct @180 s", ".3f", "high", 0.05, 0.0),
    Metric("coverage_final", "final coverage", ".3f", None),
    Metric("objects_correct_final", "final objects correct", ".3f", None),
    Metric("path_m", "path (m)", ".1f", None),
    Metric("sim_s", "simulated (s)", ".0f", None),
    Metric("lost_fraction", "frames lost", ".3f", "low", 0.02, 0.20),
    Metric("ate_all_cm", "ATE all (cm)", ".2f", "low", 0.5, 0.20),
    Metric("stop_reason", "stopped by", "s", pool=None),
]

# ---- speed and memory (every task): report.json, rasm eval memory (`mem`) -----------------------
# Speed noise: the same binary's quick panel run twice an hour apart on the 2-core VM differed by
# up to 21% in CPU ms/frame and frames/s (every task of the later run by about the same factor);
# compare speed in paired runs (docs/slam-eval.md), not against a committed table.
SPEED = [
    Metric("fps", "frames/s", ".2f", "high", 0.0, 0.25),
    Metric("cpu_ms_per_frame", "CPU ms/frame", ".0f", "low", 0.0, 0.25),
    Metric("fps_preloaded", "frames/s preloaded", ".2f", "high", 0.0, 0.25),
    Metric("peak_rss_mb", "peak RSS (MB)", ".0f", "low", 0.0, 0.10),
    Metric("surfels", "surfels", "d", None),
    Metric("rss_growth_second_half", "RSS growth 2nd half", ".3f", "low", 0.02, 0.0),
    Metric("surfels_growth_second_half", "surfel growth 2nd half", ".3f", "low", 0.02, 0.0),
    Metric("map_bytes_per_surfel", "map bytes/surfel", ".0f", "low", 0.0, 0.10, md=False),
    Metric("wall_s", "task wall (s)", ".0f", None),
]

# (section title, the eval whose rows it lists (None: every row), its metrics)
SECTIONS = [
    ("Tracking", "track", TRACKING),
    ("Segmentation", "seg", SEGMENTATION),
    ("Classification", "cls", CLASSIFICATION),
    ("Exploration", "expl", EXPLORATION),
    ("Speed and memory", None, SPEED),
]

EVALS = ("track", "seg", "cls", "expl", "mem", "bench")


def section_metrics():
    """(section title, eval, Metric) for every compared metric of every section."""
    for title, ev, metrics in SECTIONS:
        for m in metrics:
            yield title, ev, m


def in_section(row, ev):
    """Whether a row belongs in a section listing the rows of eval `ev` (None: every row)."""
    return ev is None or ev in row.get("evals", [])


def fmt(value, spec):
    """A metric value as results.md prints it ('-' when absent)."""
    if value is None:
        return "-"
    if spec == "s":
        return str(value)
    if spec == "d":
        return str(int(round(value)))
    return format(value, spec)
