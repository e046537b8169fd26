#pragma once
// Options of the relocaliser (rasm::tracking::Relocaliser), INI section
// [relocalisation]. Keys are the member names. Distances in metres, angles in degrees, image
// quantities in pixels of the frame's full resolution.

#include <mrpt/config/CLoadableOptions.h>

#include <string>

namespace rasm::tracking {

struct TRelocalisationParams : public mrpt::config::CLoadableOptions {
  // ---- ORB features (cv::ORB, Rublee et al. 2011) ----
  /// Features detected per frame, both for keyframes and at relocalisation.
  int orb_features = 1000;
  /// Pyramid levels and scale step of the ORB detector (OpenCV's defaults, as ORB-SLAM).
  int orb_levels = 8;
  double orb_scale_factor = 1.2;
  /// FAST threshold (grey levels); lower finds more corners on weak texture. Leave-one-out on
  /// TUM fr3_cabinet's 58 keyframes (Relocaliser_unittest): 20 (OpenCV's default) relocalised
  /// 9, 10 27, 7 49 (with match_ratio 0.9; 5: 50, but 25% slower).
  int orb_fast_threshold = 7;
  /// ORB looks at images at least this wide (px): a narrower frame's grey image is enlarged by
  /// the smallest integer factor that reaches it (bilinear) before detection, and the keypoints
  /// are given back at the frame's resolution. ORB's 31-px patch and border and its 8 levels
  /// were made for VGA; at 320x240 the kidnapped office hand-held sweep (a 2 s cut, then 1 s
  /// of blank frames) found too few RANSAC inliers on 463 lost frames and lost 494 of 841
  /// frames, where at 640x480 it relocalised on the first frame after each gap
  /// (docs/slam-eval.md "Relocalisation at 320x240"). 0 = the frame as it is.
  int orb_min_image_width = 640;

  // ---- keyframes (maybeAddKeyframe) ----
  /// A frame becomes a keyframe when no existing keyframe is within BOTH this distance and
  /// keyframe_rotation_deg of its pose (so a camera turning in place adds keyframes too). A zero
  /// limit is never met: with both 0, every keyframe_min_interval_frames-th frame is a keyframe.
  /// Was 0.3 m / 20 deg: on kidnapped generated hand-held worlds (320x240) views 12-16 deg from
  /// the nearest fused frame were never relocalised (4-7 RANSAC inliers against the 7 keyframes
  /// of 314 frames); at 0.15 m / 10 deg they relocalise 1-3 frames after the cut, with no false
  /// relocalisation, the same kidnapped office result (62 -> 129 keyframes in 1741 frames) and
  /// the same CPU per frame within noise (docs/slam-eval.md).
  double keyframe_translation_m = 0.15;
  double keyframe_rotation_deg = 10.0;
  /// At least this many frames (RgbdFrame::index) between two keyframes, and between two
  /// attempts on frames with too few features: bounds the ORB cost during fast motion.
  int keyframe_min_interval_frames = 5;
  /// Strongest features with valid depth kept per keyframe.
  int keyframe_max_features = 500;
  /// Frames with fewer depth-backed features (blank wall, covered lens) make no keyframe.
  int keyframe_min_features = 50;
  /// Database size bound: when full, a new keyframe replaces the most redundant one (the one
  /// closest to another keyframe in the spacing metric), so coverage keeps growing.
  int max_keyframes = 200;
  /// Depth range (m) accepted at a keypoint, in keyframes and in the depth check.
  double min_depth_m = 0.3;
  double max_depth_m = 4.0;
  /// A keypoint whose 3x3 depth neighbourhood spans more than this fraction of its depth sits
  /// on a depth edge (its 3-D point is ambiguous) and is not used.
  double max_depth_step_ratio = 0.03;
  /// Width (px) of the grey thumbnail stored with each keyframe (height keeps the aspect);
  /// 0 = none.
  int thumbnail_width = 80;

  // ---- relocalisation (relocalise) ----
  /// Try the last fused frame first (ORB-SLAM's reference keyframe), then the map's keyframes.
  /// Sparse or fast views jump further than the motion guess while the map's keyframes are
  /// spaced (keyframe_min_interval_frames); the last fused frame is the nearest view there is.
  /// Its features are detected only when a lost frame needs them (the frame is kept: one copy of
  /// its depth and colour per fused frame). Off by default: on TUM fr3_cabinet's keyframes it
  /// raised the frames tracked from 7 to 15 of 58 (3 relocalisations), but the longer run then
  /// met a false accept of ICP from the last good pose after 26 lost frames (frames 36-39 tracked
  /// 2.4 m from the truth: the box seen from its other side); docs/slam-eval.md.
  bool use_last_fused_frame = false;
  /// Against that one frame (a known neighbour, not a search over the map) the acceptance is
  /// looser; the ICP verification that follows every candidate is not. Measured on TUM
  /// fr3_cabinet's 58 keyframes, each against the one before it: min_inliers 30, ratio 0.3,
  /// depth 15 (the map's values) relocalised 33 of 57 pairs; 15 / 0.2 / 10 relocalised 51, the
  /// worst 7.6 cm / 3.8 deg from the truth (within ICP's reach), none wrong.
  int last_fused_min_inliers = 15;
  double last_fused_min_inlier_ratio = 0.2;
  int last_fused_min_depth_agreeing = 10;
  /// While lost without odometry for longer than this (s, frame timestamps), ICP from the last
  /// good pose is no longer tried; only relocalisation can find the camera again (status
  /// not_initialized). The camera has moved on by then, and ICP from a stale pose can lock onto
  /// a look-alike part of the map (fr3_cabinet: the cabinet's far side matched its front 2.4 m
  /// from the truth). 0 = always try (the default until measured beyond fr3_cabinet).
  double relocalise_only_after_lost_s = 0.0;
  /// Strongest frame features matched against every keyframe to rank them.
  int ranking_features = 300;
  /// Best-ranked keyframes whose matches go to PnP.
  int candidate_keyframes = 3;
  /// Lowe ratio test: best / second-best Hamming distance must be below this. On fr3_cabinet
  /// 0.8 relocalised 35 of 58 keyframes, 0.85 45, 0.9 49, none of them grossly wrong: the
  /// inlier and depth checks, not the ratio test, keep out false positives.
  double match_ratio = 0.9;
  /// Matches with a larger Hamming distance (bits of 256) are discarded.
  int max_hamming_distance = 64;
  /// Candidates with fewer ratio-test matches are not tried.
  int min_matches = 15;
  /// The matches of this many keyframes nearest (in pose) to a candidate join its verification:
  /// a pose hypothesis from one keyframe is checked against all the map points it should see.
  int neighbour_keyframes = 4;
  /// RANSAC PnP (cv::solvePnPRansac, AP3P minimal solver, then Levenberg-Marquardt on the
  /// inliers): iterations and inlier reprojection threshold (px).
  int ransac_iterations = 300;
  double ransac_reprojection_px = 4.0;
  /// Accepting a pose: the RANSAC inliers form at least min_inlier_ratio of the candidate
  /// keyframe's matches, and at least min_inliers frame keypoints reproject within
  /// ransac_reprojection_px of a matched point of the candidate or its neighbour keyframes.
  /// The ratio was 0.3: on the kidnapped office_handheld_long the first frame after the 2 s cut
  /// had a right hypothesis (2 cm from the truth) at 38 RANSAC inliers of 135 matches (28%), and
  /// right ones were seen at 14-28%, wrong ones at 7-15%; the pooled-inlier count, the depth
  /// check and the ICP verification are what tell them apart (0 false relocalisations on the
  /// unrelated views of Relocaliser_unittest and in the kidnapped generated worlds), and at 0.1
  /// that run relocalises on the first frame after the cut instead of 19 frames later
  /// (docs/slam-eval.md).
  int min_inliers = 30;
  double min_inlier_ratio = 0.1;
  /// Depth check: the inliers' 3-D points from the FRAME's depth, moved by the pose, must land
  /// within depth_check_tolerance_m + depth_check_relative * depth of their keyframe world points,
  /// for at least min_depth_agreement of the inliers that have valid frame depth, and for at
  /// least min_depth_agreeing of them. A pose that fits the 2-D keypoints but not the geometry
  /// is rejected.
  double depth_check_tolerance_m = 0.05;
  double depth_check_relative = 0.02;
  double min_depth_agreement = 0.7;
  int min_depth_agreeing = 15;

  void loadFromConfigFile(const mrpt::config::CConfigFileBase& cfg,
                          const std::string& section) override;
  void saveToConfigFile(mrpt::config::CConfigFileBase& cfg,
                        const std::string& section) const override;
  /// Throws InputError naming `section` and the offending key when a value is out of range.
  void validate(const std::string& section = "relocalisation") const;
  /// These params with the last_fused_* acceptance (for relocalising against the last fused
  /// frame alone).
  TRelocalisationParams forLastFusedFrame() const;
};

}  // namespace rasm::tracking
