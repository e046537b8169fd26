#pragma once
// Frames from one Microsoft 7-Scenes sequence folder (Shotton et al. 2013):
//   frame-NNNNNN.color.png|jpg  640x480 colour
//   frame-NNNNNN.depth.png      16-bit millimetres; 0 and 65535 are invalid
//   frame-NNNNNN.pose.txt       4x4 camera-to-world (T_world_cam), metres: finite and rigid;
//                               when frame 0 has one every frame must (else an error naming it)
//   camera-intrinsics.txt       optional 3x3 K (default: fx = fy = 585, cx 320, cy 240)
// Timestamps are index / 30 Hz (the Kinect's rate; the dataset has no stamps).
//
// Registration: 7-Scenes depth comes from the Kinect's IR camera and is NOT registered to the
// colour image; the poses come from KinectFusion on depth, i.e. they are depth-camera poses, and
// the published K (585) is the depth camera's. Frames are therefore in the depth camera and the
// colour is resampled into it (registerColourToDepth, holes filled at the median depth) with an
// approximate Kinect v1 calibration: colour K = (525, 525, 320, 240) and the depth-to-colour
// extrinsic of the LIRIS Kinect calibration (~2.56 cm baseline, < 1 deg), both as used by the
// visual-relocalisation community for this dataset (DSAC* / ACE setup scripts). Checked on
// redkitchen: treating the pair as registered leaves 10-30 px offsets between colour and depth
// edges (different fields of view), this calibration brings them to a few pixels.
// register_colour = false treats the pair as registered (colour used as is).

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
  /// false: colour used as is (treated as registered to depth).
  bool register_colour = true;
  /// Calibration used when register_colour (default: approximateKinectV1Calibration()).
  std::optional<ColourRegistration> colour_registration;

  /// Colour K (525, 525, 320, 240) and T_colour_depth of the LIRIS Kinect v1 calibration.
  static ColourRegistration approximateKinectV1Calibration();
};

class SevenScenesFrameSource : public FrameSource {
 public:
  explicit SevenScenesFrameSource(const std::string& folder,
                                  const SevenScenesSourceOptions& opt = {});
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
