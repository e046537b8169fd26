#pragma once
// Frames from one Microsoft 7-Scenes sequence folder (Shotton et al. 2013):
//   frame-NNNNNN.color.png|jpg  640x480 colour
//   frame-NNNNNN.depth.png      16-bit millimetres; 0 and 65535 are invalid
//   frame-NNNNNN.pose.txt       4x4 camera-to-world (T_world_cam), metres
//   camera-intrinsics.txt       optional 3x3 K (default: fx = fy = 585, cx 320, cy 240)
// Timestamps are index / 30 Hz (the Kinect's rate; the dataset has no stamps).
//
// Registration: 7-Scenes depth comes from the Kinect's IR camera and is NOT registered to the
// colour image; its poses come from KinectFusion on depth, i.e. they are depth-camera poses. By
// default this reader does what the dataset's users commonly do: it treats the pair as registered
// (same K, colour used as is). The colour is then offset by the IR-RGB baseline (~2.5 cm, i.e.
// ~7 px at 2 m) at depth edges; geometry and poses are exact. Setting colour_registration gives
// a proper resampling with registerColourToDepth for users who know their extrinsic.

#include <Eigen/Geometry>
#include <memory>
#include <optional>
#include <string>

#include "rasm/io/FrameSource.h"

namespace rasm::io {

struct SevenScenesSourceOptions {
  std::optional<CameraIntrinsics> intrinsics_override;
  double frame_rate_hz = 30.0;
  struct ColourRegistration {
    CameraIntrinsics K_colour;
    Eigen::Isometry3d T_colour_depth = Eigen::Isometry3d::Identity();
  };
  std::optional<ColourRegistration> colour_registration;
};

class SevenScenesFrameSource : public FrameSource {
 public:
  explicit SevenScenesFrameSource(const std::string& folder, const SevenScenesSourceOptions& opt = {});
  ~SevenScenesFrameSource() override;

  std::optional<RgbdFrame> next() override;
  long long sizeHint() const override;
  std::string describe() const override;

  const CameraIntrinsics& intrinsics() const;
  /// True when `folder` holds frame-000000.depth.png (or any frame-*.depth.png).
  static bool looksLikeSevenScenesFolder(const std::string& folder);

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace rasm::io
