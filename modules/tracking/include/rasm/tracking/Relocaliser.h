#pragma once
// rasm::tracking::Relocaliser: finds the camera pose again against keyframes stored with the map
// when tracking is lost, and makes those keyframes while tracking is good.
//
// Method. ElasticFusion (Whelan et al., RSS 2015 / IJRR 2016, "Global loop closure") finds
// lost poses with randomised ferns over downsampled keyframe images (Glocker et al., TVCG 2015)
// and takes the pose of the most similar keyframe; rasm uses sparse features instead, as the
// relocalisation of ORB-SLAM (Mur-Artal et al., T-RO 2015) does, because a fern code only finds
// keyframes seen from nearly the same viewpoint, while features match across the large viewpoint
// changes of a kidnapped camera and give the frame's own pose:
//  - a keyframe (rasm::maps::Keyframe, serialized with CSurfelMap) keeps the ORB features
//    (Rublee et al. 2011, cv::ORB) of one tracked frame that have valid depth, as WORLD points
//    (the frame's depth back-projected through its tracked pose) with their descriptors;
//  - relocalise() detects ORB in the lost frame and ranks all keyframes by the ratio-test
//    matches of the frame's strongest features (brute-force Hamming, Lowe's ratio test, one
//    frame feature per keyframe point);
//  - for the best few keyframes it solves 2-D (frame keypoints) to 3-D (keyframe world points)
//    PnP in RANSAC (cv::solvePnPRansac, AP3P);
//  - each pose hypothesis, best first, is verified against the matches of its keyframe AND of
//    the keyframes nearest to it (the map points it should see), refined by Levenberg-Marquardt
//    on the inliers (cv::solvePnPRefineLM), and accepted only when (a) enough frame keypoints
//    are inliers and the RANSAC inliers form enough of the keyframe's matches, and (b) the
//    frame's OWN depth at the inliers, moved by the pose, lands on the matched world points
//    (depth check). A pose that fits the keypoints but not the geometry is rejected: a false
//    positive is worse than a few more lost frames.
//
// Measured (Relocaliser_unittest, 2-core machine): simulated office, 640x480 with Kinect noise,
// 10 of 10 frames between keyframes relocalised within 2.2 cm / 0.9 deg, no pose accepted on 16
// views of unseen parts of the room, 8 frames of another world, mirrored, black or depth-less
// frames; TUM fr3_cabinet leave-one-out, 58 sparse keyframes: 49 within 5 cm / 3 deg, 4 within
// 15 cm / 6 deg, 5 not relocalised, none worse; 14-35 ms per call. Limitation: repeated structure
// (identical drawers, tiles) can yield wrong poses that pass every local check, as 2 of the 58
// did (16 and 26 cm off) with orb_fast_threshold = 10: the Mapper's ICP verification, with the
// photometric term where available, remains necessary.
//
// How the Mapper uses it (rasm::pipeline::Mapper):
//   Relocaliser reloc(params);                       // TRelocalisationParams, [relocalisation]
//   std::vector<maps::Keyframe>& db = map.keyframes();
//   per frame, when tracking is ok (a pose trusted enough to fuse):
//     reloc.maybeAddKeyframe(frame, T_world_cam, db);  // cheap unless it adds one (~ORB cost)
//   per frame, while lost (fuse nothing):
//     if (auto r = reloc.relocalise(frame, db)) {
//       // r->T_world_cam is a candidate: verify by ICP against the map rendered at it, and
//       // resume tracking from the ICP pose only if ICP accepts it.
//     }
//   reloc.lastStats() tells why the last call returned nullopt (for frames.csv / logs).
// A map reloaded from a .surfelmap file brings its keyframes; relocalise() against them puts a
// new run into the old map's frame.
//
// Frames need colour (BGR8 registered to depth) and depth; relocalise() never throws on a blank,
// black or depth-less frame: it returns nullopt. One Relocaliser per thread (it keeps the ORB
// detector and scratch images); the keyframe database is only read by relocalise().

#include <Eigen/Geometry>
#include <cstddef>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "rasm/core/RgbdFrame.h"
#include "rasm/surfel_map/Keyframe.h"
#include "rasm/tracking/RelocalisationParams.h"

namespace rasm::tracking {

struct RelocalisationResult {
  /// The pose found (optical frame).
  Eigen::Isometry3d T_world_cam = Eigen::Isometry3d::Identity();
  /// Index in the database of the keyframe whose PnP hypothesis was accepted.
  std::size_t keyframe = 0;
  /// Correspondences verified: ratio-test matches of that keyframe and of its
  /// neighbour_keyframes nearest keyframes (a frame keypoint may appear once per keyframe).
  int matches = 0;
  /// Frame keypoints reprojecting within ransac_reprojection_px of a matched world point.
  int inliers = 0;
  /// RMS reprojection error of the inliers (px).
  double reprojection_rms_px = 0;
  /// Inliers with valid frame depth, and those whose 3-D point lands on the world point.
  int depth_checked = 0;
  int depth_agreeing = 0;
};

/// What the last relocalise() call did; reason is empty when it returned a pose.
struct RelocalisationStats {
  int features = 0;          ///< ORB features detected in the frame
  int candidates_tried = 0;  ///< keyframes that went to PnP
  /// Largest match count among the candidates, and the best verified hypothesis's counts.
  int best_matches = 0, best_inliers = 0;
  int best_depth_checked = 0, best_depth_agreeing = 0;
  double ms = 0;         ///< wall time of the call
  double detect_ms = 0;  ///< of which ORB detection
  double match_ms = 0;   ///< of which descriptor matching (ranking and candidates; the rest is PnP)
  /// Why nullopt: "empty database", "no colour", "too few features", "too few matches",
  /// "too few inliers", "inlier ratio", "depth check" (the furthest stage a candidate reached).
  std::string reason;
};

class Relocaliser {
 public:
  /// Throws InputError (naming [relocalisation] key) for out-of-range params.
  explicit Relocaliser(const TRelocalisationParams& params = {});
  ~Relocaliser();
  Relocaliser(Relocaliser&&) noexcept;
  Relocaliser& operator=(Relocaliser&&) noexcept;

  const TRelocalisationParams& params() const { return m_params; }

  /// Adds a keyframe made from `frame` at its (tracked, trusted) pose T_world_cam to `db` when
  /// the spacing rules ask for one (needsKeyframe) and the frame has at least
  /// keyframe_min_features depth-backed features; when db holds max_keyframes, the new keyframe
  /// replaces the most redundant one if that one is closer to its nearest keyframe than the new
  /// one is to its own. Returns true when db changed. Cost: the spacing test over db (pose
  /// distances) on every call; ORB detection (a few to ~15 ms for 640x480) only when it adds or
  /// tries to.
  bool maybeAddKeyframe(const RgbdFrame& frame, const Eigen::Isometry3d& T_world_cam,
                        std::vector<maps::Keyframe>& db);

  /// The spacing rule alone: true when no keyframe of db is within keyframe_translation_m AND
  /// keyframe_rotation_deg of T_world_cam, and at least keyframe_min_interval_frames frames
  /// passed since the last keyframe added or attempted by this object (a frame index below the
  /// last attempt counts as a new sequence).
  bool needsKeyframe(const Eigen::Isometry3d& T_world_cam, std::size_t frame_index,
                     const std::vector<maps::Keyframe>& db) const;

  /// ORB features of `frame` with valid depth (strongest keyframe_max_features), as world points
  /// through T_world_cam, and the thumbnail; nullopt with fewer than keyframe_min_features.
  std::optional<maps::Keyframe> makeKeyframe(const RgbdFrame& frame,
                                             const Eigen::Isometry3d& T_world_cam) const;

  /// Pose of `frame` against the keyframes of `db`, or nullopt when no candidate passes the
  /// inlier and depth checks (lastStats().reason says why). Tens of ms on a 640x480 frame.
  std::optional<RelocalisationResult> relocalise(const RgbdFrame& frame,
                                                 const std::vector<maps::Keyframe>& db);

  const RelocalisationStats& lastStats() const { return m_stats; }

  /// Forgets the frame index of the last keyframe attempt (start of a new sequence).
  void reset() { m_last_attempt.reset(); }

 private:
  struct Impl;  // OpenCV detector and scratch buffers (kept out of this header)
  TRelocalisationParams m_params;
  std::unique_ptr<Impl> m_impl;
  std::optional<std::size_t> m_last_attempt;  ///< frame index of the last keyframe attempt
  RelocalisationStats m_stats;
};

}  // namespace rasm::tracking
