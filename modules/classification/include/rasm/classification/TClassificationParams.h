#pragma once
// [classification]: the classification stage of section IV (docs/classification.md). Each
// detector has its own section with its own thresholds: [sim_detector] (the simulator's
// detector, SimulatedDetector.h in modules/sim, added by pipeline/SimDetector.h), [dnn_detector]
// (YOLO family, DnnDetector.h), [zero_shot] (IV-A, ZeroShotDetector.h).

#include <mrpt/config/CLoadableOptions.h>

#include <string>
#include <vector>

#include "rasm/classification/ClassFusion.h"

namespace rasm::classification {

struct TClassificationParams : mrpt::config::CLoadableOptions {
  bool enabled = true;
  /// The detectors to run, by section name, comma separated: sim_detector, dnn_detector,
  /// zero_shot (empty: none), or auto: sim_detector on the simulator's frames (it needs their
  /// ground truth), dnn_detector (NanoDet-m by default) on every other source (resolveAuto).
  /// Each runs on its own worker thread on the same frames.
  std::string detectors = "auto";
  /// Offer every n-th fused frame to the detectors (a busy detector skips it, counted).
  int every_n_frames = 5;
  /// true: detectors on worker threads, results fused when they arrive (never blocking mapping);
  /// false: detect on the mapping thread and fuse in the same frame (deterministic runs);
  /// auto (threaded_auto): false on the simulator's frames (the same seed gives the same run),
  /// true on every other source (resolveAuto).
  bool threaded = true;
  bool threaded_auto = true;
  /// A detection is fused into the segment of L^p with the highest IoU with its box when that
  /// IoU reaches this (IV).
  double min_iou = 0.25;
  /// How a score becomes p_d (ClassFusion.h): "probability" (p_d = score, the paper's reading:
  /// a score below 0.5 is evidence against the class) or "vote" (p_d = 0.5 + 0.5 (score - s0) /
  /// (1 - s0) above the neutral score s0, no evidence below it). docs/classification.md
  /// "Score model" has the measurements behind the default.
  std::string score_model = "vote";
  /// s0 of the vote model.
  double vote_neutral_score = 0.25;
  /// true: a detection's log-odds are scaled by its IoU with the segment, L += IoU logit(p_d)
  /// (a box that explains the segment well says more about it than one that overlaps a corner of
  /// it: a keyboard's box on the desk segment it was merged into, next to the desk's own box);
  /// false: the paper's full update whatever the overlap.
  bool iou_weighted_evidence = true;
  /// p_d is clamped to [1 - max, max], so one detection never saturates a surfel (ClassEvidence.h:
  /// 0.9 is 2.2 nats of the 7-nat clamp).
  double max_detection_probability = 0.9;
  /// A segment is an object of its best class (objects.json, the class map's eval) when the mean
  /// posterior of that class over its surfels reaches this; below it the segment has no class
  /// ("none"): a few surfels that carried evidence into a large segment do not name it.
  double min_object_probability = 0.6;
  /// objects.json reports a named segment as an object only when it holds at least
  /// min_object_surfels surfels and its largest extent exceeds min_object_size_m (the
  /// evaluation's object thresholds: ClassificationMetrics.h); smaller ones are fragments (a
  /// detection box fused into a few stray surfels: a "chair" of 1 surfel at 0.83).
  int min_object_surfels = 50;
  double min_object_size_m = 0.10;
  /// ... and when it is not structure: a thin plane whose two larger extents both exceed
  /// structure_min_extent_m is a floor, wall or ceiling, larger than any object of the COCO
  /// classes a table's top could be taken for (the office's 7.7 x 5.0 m floor was reported as a
  /// "dining table" at 0.71). Thin: its smallest extent below structure_max_thickness_m or below
  /// structure_max_thickness_fraction of its middle extent (a floor segment that took in a few
  /// percent of low furniture surfaces measured 7.9 x 5.8 x 0.31 m between its 1st and 99th
  /// percentiles; a 2.5 x 2.2 m desk with its 0.75 m legs stays an object).
  double structure_min_extent_m = 2.0;
  double structure_max_thickness_m = 0.15;
  double structure_max_thickness_fraction = 0.1;
  /// ... and a piece of structure: an object all of whose segments are thin planes (smallest
  /// extent below structure_max_thickness_m) at least structure_piece_min_extent_m both ways in
  /// the plane of a structure segment (normals within 10 degrees, the piece's centroid within
  /// structure_piece_max_offset_m of that plane) is part of that floor, wall or ceiling (the
  /// office's 2.9 x 1.5 m floor piece under a desk, whose boxes fused 27 "dining table"
  /// detections into it).
  double structure_piece_min_extent_m = 0.5;
  double structure_piece_max_offset_m = 0.05;
  /// VII-A: a detection with a template pose (the zero-shot classifier's) is fused only when a
  /// detection of its class on its segment, from a view at least pose_min_view_change_deg away,
  /// implies the same orientation of the object within pose_agreement_deg and within
  /// pose_max_fraction_of_view_change of the view change (PoseConsensus.h); false: fused as it
  /// comes, as the paper's IV-A does.
  bool pose_consensus = true;
  double pose_agreement_deg = 30.0;
  double pose_min_view_change_deg = 10.0;
  double pose_max_fraction_of_view_change = 0.7;
  /// Seed of the simulated detector's noise (sim_detector only).
  int seed = 1;

  std::vector<std::string> detectorList() const;
  /// Resolves detectors = auto and threaded = auto for the source the run maps (the simulator's
  /// frames or not); nothing else changes. Idempotent.
  void resolveAuto(bool simulated_source);
  ScoreModel scoreModel() const;

  void loadFromConfigFile(const mrpt::config::CConfigFileBase& c, const std::string& s) override;
  void saveToConfigFile(mrpt::config::CConfigFileBase& c, const std::string& s) const override;
};

}  // namespace rasm::classification
