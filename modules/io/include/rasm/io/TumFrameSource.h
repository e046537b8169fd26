#pragma once
// Frames from a TUM RGB-D benchmark sequence folder (Sturm et al. 2012), also ICL-NUIM in its
// TUM-compatible layout:
//   rgb.txt, depth.txt      "timestamp filename" per line, '#' comments
//   rgb/*.png, depth/*.png  8-bit colour; 16-bit depth, depth_factor (5000) units per metre, 0 =
//   none groundtruth.txt         optional, "t tx ty tz qx qy qz qw" (T_world_cam of the colour
//   camera)
//
// Association (associate.py): rgb and depth stamps are paired greedily by smallest |dt| below
// max_association_dt_s (0.02 s), each used once, sorted by time; unpaired images are dropped.
// The frame's timestamp is the DEPTH stamp (depth is what tracking and fusion consume).
// TUM depth is registered to colour by the sensor driver, so colour is used as is.
//
// Ground truth: gt_T_world_cam = interpolatePose(groundtruth, t_depth, 0.02 s): linear / slerp
// between the bracketing mocap samples when one lies within 0.02 s, else none for that frame.
//
// Intrinsics: the folder name picks the camera: "freiburg1"/"fr1" -> tum_fr1 (517.3 516.5 318.6
// 255.3), fr2 -> tum_fr2, fr3 -> tum_fr3, otherwise tum_default (525 525 319.5 239.5);
// intrinsics_override replaces it (e.g. the icl_nuim preset). Width / height come from the images.
// Lens distortion of the freiburg cameras is ignored (the benchmark's depth is undistorted only by
// the driver's registration).
//
// Negative fy (ICL-NUIM's published fy = -480: its image v axis grows against the camera's +y):
// the model v = cy + fy y / z is honoured exactly by flipping the image rows and using
// fy' = -fy, cy' = (H - 1) - cy, which is the same projection with a positive focal length. With
// ICL-NUIM's cy = 239.5 and H = 480 this is cy' = cy. The map then lives in the (mirrored) frame of
// ICL-NUIM's ground truth, so ATE against it is meaningful. Pass a positive fy to keep the images
// upright instead (what many SLAM systems do).

#include <memory>
#include <optional>
#include <string>

#include "rasm/io/FrameSource.h"

namespace rasm::io {

struct TumSourceOptions {
  std::optional<CameraIntrinsics> intrinsics_override;
  double depth_factor = 5000.0;  ///< depth PNG units per metre
  double max_association_dt_s = 0.02;
  double max_groundtruth_dt_s = 0.02;
};

class TumFrameSource : public FrameSource {
 public:
  /// Reads the lists (images are read lazily by next()). InputError names the folder and the
  /// missing or malformed file.
  explicit TumFrameSource(const std::string& folder, const TumSourceOptions& opt = {});
  ~TumFrameSource() override;

  std::optional<RgbdFrame> next() override;
  long long sizeHint() const override;
  std::string describe() const override;

  /// Intrinsics the frames get (after the negative-fy handling).
  const CameraIntrinsics& intrinsics() const;
  /// True when the given fy was negative and rows are flipped (see above).
  bool flipsRows() const;
  /// Intrinsics picked from the folder name: tum_fr1/2/3 or tum_default.
  static CameraIntrinsics intrinsicsForFolderName(const std::string& folder);
  /// True when `folder` holds rgb.txt and depth.txt.
  static bool looksLikeTumFolder(const std::string& folder);

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace rasm::io
