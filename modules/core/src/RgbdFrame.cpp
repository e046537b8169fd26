#include "rasm/core/RgbdFrame.h"

#include <cmath>
#include <sstream>

#include "rasm/core/Error.h"

namespace rasm {

void RgbdFrame::validate(const std::string& source) const {
  if (!intrinsics.valid())
    throwInputError(source,
                    "invalid intrinsics " + intrinsics.toString() + ": " + intrinsics.problem());
  if (depth_m.empty()) throwInputError(source, "no depth image");
  if (!depth_m.sameSize(intrinsics.width, intrinsics.height)) {
    std::ostringstream s;
    s << "depth image is " << depth_m.width() << "x" << depth_m.height() << ", expected "
      << intrinsics.width << "x" << intrinsics.height << " (camera intrinsics)";
    throwInputError(source, s.str());
  }
  if (!colour.empty() && !colour.sameSize(depth_m)) {
    std::ostringstream s;
    s << "colour image is " << colour.width() << "x" << colour.height()
      << ", expected the depth size " << depth_m.width() << "x" << depth_m.height()
      << " (registered RGB-D)";
    throwInputError(source, s.str());
  }
  for (int y = 0; y < depth_m.height(); ++y) {
    const float* r = depth_m.row(y);
    for (int x = 0; x < depth_m.width(); ++x)
      if (!std::isfinite(r[x]) || r[x] < 0.0f) {
        std::ostringstream s;
        s << "depth at pixel (" << x << "," << y << ") is " << r[x]
          << ", expected a finite value >= 0 m (0 = no measurement)";
        throwInputError(source, s.str());
      }
  }
  for (const auto* lbl : {&gt_instance, &gt_class})
    if (!lbl->empty() && !lbl->sameSize(depth_m))
      throwInputError(source, "ground-truth label image size differs from the depth image");
}

void registerColourToDepth(const Image<float>& depth_m, const CameraIntrinsics& K_depth,
                           const Image<Bgr8>& colour, const CameraIntrinsics& K_colour,
                           const Eigen::Isometry3d& T_colour_depth, Image<Bgr8>& out) {
  out.resize(depth_m.width(), depth_m.height());
  out.setTo(Bgr8{});
  const Eigen::Matrix3f R = T_colour_depth.linear().cast<float>();
  const Eigen::Vector3f t = T_colour_depth.translation().cast<float>();
  const PinholeF Kd = K_depth.plain(), Kc = K_colour.plain();
#pragma omp parallel for schedule(static)
  for (int y = 0; y < depth_m.height(); ++y)
    for (int x = 0; x < depth_m.width(); ++x) {
      const float z = depth_m(x, y);
      if (!(z > 0.0f)) continue;
      const Eigen::Vector3f pc = R * Kd.backProject(float(x), float(y), z) + t;
      int u = 0, v = 0;
      if (nearestPixel(Kc, pc, colour.width(), colour.height(), u, v)) out(x, y) = colour(u, v);
    }
}

}  // namespace rasm
