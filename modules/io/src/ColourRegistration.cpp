#include "ColourRegistration.h"

#include <algorithm>
#include <cmath>
#include <vector>

namespace rasm::io::detail {

void registerColourToDepthFilled(const Image<float>& depth_m, const CameraIntrinsics& K_depth,
                                 const Image<Bgr8>& colour, const CameraIntrinsics& K_colour,
                                 const Eigen::Isometry3d& T_colour_depth, Image<Bgr8>& out) {
  registerColourToDepth(depth_m, K_depth, colour, K_colour, T_colour_depth, out);

  std::vector<float> sample;
  sample.reserve(std::size_t(depth_m.width()) * depth_m.height() / 16 + 1);
  for (int y = 0; y < depth_m.height(); y += 4)
    for (int x = 0; x < depth_m.width(); x += 4)
      if (depth_m(x, y) > 0.0f) sample.push_back(depth_m(x, y));
  float z_fill = 2.0f;  // no valid depth at all: a typical indoor distance
  if (!sample.empty()) {
    std::nth_element(sample.begin(), sample.begin() + sample.size() / 2, sample.end());
    z_fill = sample[sample.size() / 2];
  }
  const Eigen::Matrix3f R = T_colour_depth.linear().cast<float>();
  const Eigen::Vector3f t = T_colour_depth.translation().cast<float>();
  const PinholeF Kd = K_depth.plain(), Kc = K_colour.plain();
#pragma omp parallel for schedule(static)
  for (int y = 0; y < depth_m.height(); ++y)
    for (int x = 0; x < depth_m.width(); ++x) {
      if (depth_m(x, y) > 0.0f) continue;
      const Eigen::Vector3f pc = R * Kd.backProject(float(x), float(y), z_fill) + t;
      int u = 0, v = 0;
      if (nearestPixel(Kc, pc, colour.width(), colour.height(), u, v)) out(x, y) = colour(u, v);
    }
}

}  // namespace rasm::io::detail
