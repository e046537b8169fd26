#pragma once
// One RGB-D frame as every stage sees it (II-A: colour C_t, depth D_t).
//  - depth_m: float metres in the DEPTH camera; 0 = invalid (no measurement). Never NaN/inf:
//    readers reject non-finite depth with an InputError (validate()).
//  - colour: 8-bit B,G,R (the order of OpenCV and mrpt::img::CImage, so no copies at the
//    boundaries), registered to the depth image: same size, pixel (u,v) of both is the same ray.
//    Readers of unregistered sensors resample colour into the depth camera (registerColourToDepth).
//  - intrinsics: of the depth camera (and hence of the registered colour).
//  - Optional ground truth (datasets, simulator): camera pose and per-pixel instance/class ids.

#include <Eigen/Geometry>
#include <optional>
#include <string>

#include "rasm/compute/Platform.h"
#include "rasm/compute/Types.h"
#include "rasm/core/CameraIntrinsics.h"
#include "rasm/core/Image.h"

namespace rasm {

struct RgbdFrame {
  double timestamp_s = 0.0;  ///< seconds (dataset or UNIX time)
  std::size_t index = 0;     ///< position in its sequence
  CameraIntrinsics intrinsics;
  Image<float> depth_m;
  Image<Bgr8> colour;

  /// Ground-truth T_world_cam (optical frame: x right, y down, z forward), when known.
  std::optional<Eigen::Isometry3d> gt_T_world_cam;
  /// Odometry of the robot base in SE(2) (x, y, yaw) when the source has it.
  std::optional<Eigen::Vector3d> odometry_xyyaw;
  /// Ground-truth labels (simulator): instance id and class id per pixel, 0 = none; may be empty.
  Image<std::uint16_t> gt_instance;
  Image<std::uint16_t> gt_class;

  int width() const { return depth_m.width(); }
  int height() const { return depth_m.height(); }

  /// Checks sizes agree with the intrinsics and depth is finite and >= 0; throws InputError
  /// naming `source` (e.g. "rawlog foo.rawlog, frame 12") and what was expected.
  void validate(const std::string& source) const;
};

/// Resamples a colour image of another camera into the depth camera: every valid depth pixel is
/// back-projected, moved by T_colour_depth and projected into the colour image (nearest pixel).
/// Pixels that fall outside get black.
void registerColourToDepth(const Image<float>& depth_m, const CameraIntrinsics& K_depth,
                           const Image<Bgr8>& colour, const CameraIntrinsics& K_colour,
                           const Eigen::Isometry3d& T_colour_depth, Image<Bgr8>& out);

/// The nearest pixel (u, v) of a `width` x `height` image that the camera-frame point p_cam
/// projects to, or false when it is behind the camera or outside the image. Bounds are checked
/// before rounding, so a NaN or huge projection (extreme intrinsics or poses from a corrupt
/// file) is never converted to int.
inline bool nearestPixel(const PinholeF& K, const Eigen::Vector3f& p_cam, int width, int height,
                         int& u, int& v) {
  if (!(p_cam.z() > 0.0f)) return false;
  const Eigen::Vector2f uv = K.project(p_cam);
  if (!(uv.x() > -1.0f && uv.y() > -1.0f && uv.x() < float(width) && uv.y() < float(height)))
    return false;
  u = compute::roundHalfAway(uv.x());
  v = compute::roundHalfAway(uv.y());
  return u >= 0 && v >= 0 && u < width && v < height;
}

}  // namespace rasm
