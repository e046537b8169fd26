#include "rasm/sim/ViewStats.h"

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>

#include "rasm/models/ClassVocabulary.h"

namespace rasm::sim {

ViewStats viewStats(const RgbdFrame& f, double max_depth_m) {
  ViewStats s;
  const int W = f.depth_m.width(), H = f.depth_m.height();
  if (W == 0 || H == 0) return s;
  const bool labels = f.gt_instance.width() == W && f.gt_instance.height() == H &&
                      f.gt_class.width() == W && f.gt_class.height() == H;
  const float zmax = float(max_depth_m);
  const auto valid = [&](int x, int y) {
    const float z = f.depth_m.row(y)[x];
    return z > 0.f && z <= zmax;
  };
  const double fx = f.intrinsics.fx, fy = f.intrinsics.fy, cx = f.intrinsics.cx,
               cy = f.intrinsics.cy;
  const auto point = [&](int x, int y) {
    const double z = f.depth_m.row(y)[x];
    return Eigen::Vector3d((x - cx) / fx * z, (y - cy) / fy * z, z);
  };
  std::size_t n_valid = 0, n_object = 0, n_normal = 0;
  Eigen::Matrix3d scatter = Eigen::Matrix3d::Zero();
  // Point-to-plane rows [n; p x n] (camera frame), the rotation part scaled below by 1 / mean
  // depth.
  Eigen::Matrix3d nq = Eigen::Matrix3d::Zero(), qq = Eigen::Matrix3d::Zero();
  double depth_sum = 0.0;
  for (int y = 0; y < H; ++y)
    for (int x = 0; x < W; ++x) {
      if (!valid(x, y)) continue;
      ++n_valid;
      if (labels && f.gt_instance.row(y)[x] != 0 && !models::isStructureClass(f.gt_class.row(y)[x]))
        ++n_object;
      if (x == 0 || y == 0 || x == W - 1 || y == H - 1) continue;
      const float z = f.depth_m.row(y)[x];
      bool smooth = true;
      for (const auto& [u, v] : {std::pair{x - 1, y}, {x + 1, y}, {x, y - 1}, {x, y + 1}})
        smooth = smooth && valid(u, v) && std::abs(f.depth_m.row(v)[u] - z) <= 0.05f * z;
      if (!smooth) continue;
      const Eigen::Vector3d n =
          (point(x + 1, y) - point(x - 1, y)).cross(point(x, y + 1) - point(x, y - 1));
      const double len = n.norm();
      if (!(len > 0.0)) continue;
      const Eigen::Vector3d u = n / len, q = point(x, y).cross(u);
      scatter += u * u.transpose();
      nq += u * q.transpose();
      qq += q * q.transpose();
      depth_sum += z;
      ++n_normal;
    }
  s.valid_fraction = double(n_valid) / double(W * H);
  s.object_fraction = n_valid ? double(n_object) / double(n_valid) : 0.0;
  s.normal_fraction = double(n_normal) / double(W * H);
  if (n_normal > 0) {
    const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> es(scatter / double(n_normal),
                                                            Eigen::EigenvaluesOnly);
    s.normal_min_eig = std::max(0.0, es.eigenvalues()(0));
    const double d = depth_sum / double(n_normal);
    Eigen::Matrix<double, 6, 6> info;
    info << scatter, nq / d, nq.transpose() / d, qq / (d * d);
    const Eigen::SelfAdjointEigenSolver<Eigen::Matrix<double, 6, 6>> es6(info / double(n_normal),
                                                                         Eigen::EigenvaluesOnly);
    s.icp_min_eig = std::max(0.0, es6.eigenvalues()(0));
  }
  return s;
}

}  // namespace rasm::sim
