// View-information bins of V-B: the bin of a camera direction against the angles computed in
// double precision, for the layouts with a comparison fast path and for the generic one.

#include "rasm/surfel_map/kernels/ViewBins.h"

#include <gtest/gtest.h>

#include <cmath>
#include <random>

using namespace rasm;
using namespace rasm::maps::kernels;

namespace {

/// Reference bin, or -1 when the direction lies within `margin` rad of a ring or sector border
/// (where float rounding may legitimately pick either side).
int referenceBin(const Eigen::Vector3d& n, const Eigen::Vector3d& b, const Eigen::Vector3d& d,
                 int n_az, int n_el, double margin) {
  const Eigen::Vector3d c = n.cross(b);
  const double s = std::min(1.0, std::max(0.0, d.dot(n)));
  const double el_angle = std::asin(s);
  const double az = std::atan2(d.dot(c), d.dot(b));
  const double ring = M_PI / 2 / n_el, sector = 2 * M_PI / n_az;
  const double el_pos = el_angle / ring, az_pos = (az + M_PI) / sector;
  const bool el_clamped = d.dot(n) <= 0.0;  // back-facing: ring 0 by definition
  if (!el_clamped && std::abs(el_pos - std::round(el_pos)) * ring < margin && el_pos > 0.5 &&
      el_pos < n_el - 0.5)
    return -1;
  if (std::abs(az_pos - std::round(az_pos)) * sector < margin) return -1;
  const int el = std::min(n_el - 1, int(std::floor(el_pos)));
  const int sec = std::min(n_az - 1, std::max(0, int(std::floor(az_pos))));
  return el * n_az + sec;
}

}  // namespace

TEST(ViewBins, BinOfCameraDirectionMatchesTheAngles) {
  std::mt19937 rng(5);
  std::normal_distribution<double> g(0.0, 1.0);
  const int layouts[][2] = {{8, 1}, {8, 2}, {8, 3}, {8, 4}, {6, 2}, {8, 5}, {12, 3}};
  for (const auto& l : layouts) {
    const int n_az = l[0], n_el = l[1];
    int checked = 0;
    for (int k = 0; k < 20000; ++k) {
      const Eigen::Vector3d n = Eigen::Vector3d(g(rng), g(rng), g(rng)).normalized();
      const Eigen::Vector3d b = n.cross(Eigen::Vector3d(g(rng), g(rng), g(rng))).normalized();
      const Eigen::Vector3d d = Eigen::Vector3d(g(rng), g(rng), g(rng)).normalized();
      const int ref = referenceBin(n, b, d, n_az, n_el, 1e-4);
      if (ref < 0) continue;
      ++checked;
      ASSERT_EQ(viewBinIndex(n.cast<float>(), b.cast<float>(), d.cast<float>(), n_az, n_el), ref)
          << n_az << "x" << n_el << " sample " << k;
    }
    EXPECT_GT(checked, 19000);
  }
}
