#include "rasm/core/CameraIntrinsics.h"

#include <mrpt/img/TCamera.h>

#include <cmath>
#include <sstream>

#include "rasm/core/Error.h"

namespace rasm {

std::string CameraIntrinsics::problem() const {
  std::ostringstream s;
  const auto focal = [&](const char* name, double f) {
    // Above 1e5 px the field of view is below 0.4 degrees: no depth camera, and every surfel
    // radius (f in II-B's formula) collapses to nothing.
    if (!(std::isfinite(f) && f > 0 && f <= 1e5))
      s << name << " = " << f << ": expected a finite focal length in (0, 100000] (pixels)";
  };
  focal("fx", fx);
  if (!s.str().empty()) return s.str();
  focal("fy", fy);
  if (!s.str().empty()) return s.str();
  if (width <= 0 || height <= 0) {
    s << "image size " << width << "x" << height << ": expected a width and height > 0";
  } else if (!(std::isfinite(cx) && cx >= -0.5 && cx <= width - 0.5)) {
    s << "cx = " << cx << ": expected the principal point inside the image, in [-0.5, "
      << width - 0.5 << "] for a width of " << width;
  } else if (!(std::isfinite(cy) && cy >= -0.5 && cy <= height - 0.5)) {
    s << "cy = " << cy << ": expected the principal point inside the image, in [-0.5, "
      << height - 0.5 << "] for a height of " << height;
  }
  return s.str();
}

CameraIntrinsics CameraIntrinsics::resized(int w, int h) const {
  const double sx = double(w) / width, sy = double(h) / height;
  return CameraIntrinsics(fx * sx, fy * sy, (cx + 0.5) * sx - 0.5, (cy + 0.5) * sy - 0.5, w, h);
}

CameraIntrinsics CameraIntrinsics::level(int lvl) const {
  CameraIntrinsics k = *this;
  for (int i = 0; i < lvl; ++i) {
    k.fx *= 0.5;
    k.fy *= 0.5;
    k.cx = (k.cx + 0.5) * 0.5 - 0.5;
    k.cy = (k.cy + 0.5) * 0.5 - 0.5;
    k.width = (k.width + 1) / 2;
    k.height = (k.height + 1) / 2;
  }
  return k;
}

CameraIntrinsics CameraIntrinsics::fromTCamera(const mrpt::img::TCamera& c) {
  return CameraIntrinsics(c.fx(), c.fy(), c.cx(), c.cy(), int(c.ncols), int(c.nrows));
}

void CameraIntrinsics::toTCamera(mrpt::img::TCamera& c) const {
  c.ncols = uint32_t(width);
  c.nrows = uint32_t(height);
  c.setIntrinsicParamsFromValues(fx, fy, cx, cy);
  c.dist.fill(0.0);
}

CameraIntrinsics CameraIntrinsics::preset(const std::string& name) {
  if (name == "kinect_v1") return {525.0, 525.0, 319.5, 239.5, 640, 480};
  if (name == "kinect_v2_depth") return {365.5, 365.5, 255.5, 211.5, 512, 424};
  if (name == "xtion") return {570.3, 570.3, 319.5, 239.5, 640, 480};
  if (name == "tum_fr1") return {517.3, 516.5, 318.6, 255.3, 640, 480};
  if (name == "tum_fr2") return {520.9, 521.0, 325.1, 249.7, 640, 480};
  if (name == "tum_fr3") return {535.4, 539.2, 320.1, 247.6, 640, 480};
  if (name == "tum_default") return {525.0, 525.0, 319.5, 239.5, 640, 480};
  if (name == "icl_nuim") return {481.20, -480.0, 319.5, 239.5, 640, 480};
  if (name == "7scenes") return {585.0, 585.0, 320.0, 240.0, 640, 480};
  throwInputError("camera preset '" + name + "'",
                  "unknown; expected one of kinect_v1, kinect_v2_depth, xtion, tum_fr1, tum_fr2, "
                  "tum_fr3, tum_default, icl_nuim, 7scenes");
}

std::string CameraIntrinsics::toString() const {
  std::ostringstream s;
  s << width << "x" << height << " fx=" << fx << " fy=" << fy << " cx=" << cx << " cy=" << cy;
  return s.str();
}

}  // namespace rasm
