#pragma once
// rasm::maps::Keyframe: what relocalisation (rasm::tracking::Relocaliser) keeps
// of one tracked frame, stored with the map (CSurfelMap::keyframes(), serialized with it) so that
// a saved map can be reloaded and a camera relocalised in it.
//
// Plain data, no OpenCV types: ORB features as world points + 32-byte descriptors, one row per
// feature (points_world[i], keypoints_px[i], descriptors[32 i .. 32 i + 31] belong together),
// only features whose pixel had valid depth; optionally a small grey thumbnail of the frame.

#include <Eigen/Geometry>
#include <cstddef>
#include <cstdint>
#include <vector>

#include "rasm/core/CameraIntrinsics.h"

namespace rasm::maps {

struct Keyframe {
  static constexpr int kDescriptorBytes = 32;  ///< ORB (rBRIEF, 256 bits)

  std::uint64_t frame_index = 0;  ///< RgbdFrame::index of the source frame
  double timestamp_s = 0.0;       ///< RgbdFrame::timestamp_s
  /// Pose of the frame when it was added (optical frame: x right, y down, z forward).
  Eigen::Isometry3d T_world_cam = Eigen::Isometry3d::Identity();
  /// Intrinsics of the frame the features were detected in (keypoints_px, thumbnail).
  CameraIntrinsics intrinsics;

  /// Per feature: 3-D position in the WORLD frame (from the frame's depth at the keypoint),
  /// metres.
  std::vector<Eigen::Vector3f> points_world;
  /// Per feature: keypoint position in the keyframe image (pixels, level-0 coordinates).
  std::vector<Eigen::Vector2f> keypoints_px;
  /// Per feature: ORB descriptor, kDescriptorBytes bytes each, row-major.
  std::vector<std::uint8_t> descriptors;

  /// Optional downsampled grey image of the frame (row-major, thumb_width x thumb_height bytes,
  /// cv::INTER_AREA); empty when not stored. For appearance lookups (ElasticFusion-style ferns)
  /// and display; the Relocaliser's feature matching does not use it.
  int thumb_width = 0, thumb_height = 0;
  std::vector<std::uint8_t> thumbnail;

  std::size_t numFeatures() const { return points_world.size(); }
  const std::uint8_t* descriptor(std::size_t i) const {
    return descriptors.data() + kDescriptorBytes * i;
  }
  /// The per-feature arrays have matching lengths and the thumbnail its declared size.
  bool consistent() const {
    return keypoints_px.size() == points_world.size() &&
           descriptors.size() == std::size_t(kDescriptorBytes) * points_world.size() &&
           thumb_width >= 0 && thumb_height >= 0 &&
           thumbnail.size() == std::size_t(thumb_width) * std::size_t(thumb_height);
  }
};

}  // namespace rasm::maps
