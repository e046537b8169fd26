#pragma once
// Pinhole camera model of II-A (K, image size) with conversion to and from mrpt::img::TCamera.
// Pixel centres are at integer coordinates (OpenCV / MRPT convention).

#include <string>

#include "rasm/compute/Types.h"

namespace mrpt::img {
class TCamera;
}

namespace rasm {

struct CameraIntrinsics {
  double fx = 525.0, fy = 525.0, cx = 319.5, cy = 239.5;
  int width = 640, height = 480;

  CameraIntrinsics() = default;
  CameraIntrinsics(double fx_, double fy_, double cx_, double cy_, int w, int h)
      : fx(fx_), fy(fy_), cx(cx_), cy(cy_), width(w), height(h) {}

  /// Plain copy for kernels.
  PinholeF plain() const {
    return PinholeF{float(fx), float(fy), float(cx), float(cy), width, height};
  }
  /// Intrinsics of pyramid level `level` (each level halves the resolution; pixel centres of the
  /// 2x2 block average sit at (x + 0.5) / 2 - 0.5).
  CameraIntrinsics level(int level) const;
  /// The same camera rendering width x height pixels (focal lengths scaled per axis, pixel
  /// centres at integer coordinates as level()): the predicted views of V, the mesh's renders.
  CameraIntrinsics resized(int width, int height) const;
  /// Mean focal length (f in the radius formula of II-B).
  double focal() const { return 0.5 * (fx + fy); }
  /// Finite focal lengths > 0, an image size > 0 and the principal point inside the image.
  bool valid() const { return problem().empty(); }
  /// "" when valid(), else what is wrong ("fx = nan: expected a finite focal length > 0 (pixels)").
  std::string problem() const;

  static CameraIntrinsics fromTCamera(const mrpt::img::TCamera& c);
  void toTCamera(mrpt::img::TCamera& c) const;

  /// Named presets: "kinect_v1" (640x480, f 525), "kinect_v2_depth" (512x424, f 365.5),
  /// "xtion" (640x480, f 570.3), "tum_fr1", "tum_fr2", "tum_fr3", "icl_nuim", "7scenes".
  static CameraIntrinsics preset(const std::string& name);

  std::string toString() const;
  bool operator==(const CameraIntrinsics& o) const {
    return fx == o.fx && fy == o.fy && cx == o.cx && cy == o.cy && width == o.width &&
           height == o.height;
  }
};

}  // namespace rasm
