#include "rasm/sim/SurfaceDistance.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace rasm::sim {

namespace {

/// The fixed directions: six axes and eight cube diagonals.
const std::vector<Eigen::Vector3f>& fixedDirections() {
  static const std::vector<Eigen::Vector3f> dirs = [] {
    std::vector<Eigen::Vector3f> d;
    for (int a = 0; a < 3; ++a)
      for (float s : {1.f, -1.f}) {
        Eigen::Vector3f v = Eigen::Vector3f::Zero();
        v[a] = s;
        d.push_back(v);
      }
    for (float x : {1.f, -1.f})
      for (float y : {1.f, -1.f})
        for (float z : {1.f, -1.f}) d.push_back(Eigen::Vector3f(x, y, z).normalized());
    return d;
  }();
  return dirs;
}

}  // namespace

float surfaceDistanceBound(const RayScene& scene, const Eigen::Vector3f& p,
                           const Eigen::Vector3f& n, float cap_m) {
  // Each ray starts kBack behind p, so a surface through p (or just behind it) is hit at
  // t ~ kBack instead of at t ~ 0, where Embree may miss it; |t - kBack| is the distance from p
  // to the hit point.
  constexpr float kBack = 1e-3f;
  float best = cap_m;
  const auto cast = [&](const Eigen::Vector3f& d) {
    const RayHit h = scene.castRay(p - kBack * d, d, 0.f, best + kBack);
    if (h.hit) best = std::min(best, std::abs(h.t - kBack));
  };
  const float len = n.norm();
  if (std::isfinite(len) && len > 1e-6f) {
    cast(-n / len);
    cast(n / len);
  }
  for (const Eigen::Vector3f& d : fixedDirections()) cast(d);
  return best;
}

SurfaceDistanceStats surfaceDistanceStats(const RayScene& scene,
                                          const std::vector<Eigen::Vector3f>& positions,
                                          const std::vector<Eigen::Vector3f>& normals,
                                          double max_dist_m, double cap_m,
                                          std::vector<float>* distances_m) {
  if (!normals.empty() && normals.size() != positions.size())
    throw std::invalid_argument("surfaceDistanceStats: normals and positions differ in size");
  if (!(max_dist_m >= 0.0) || !(cap_m > 0.0))
    throw std::invalid_argument("surfaceDistanceStats: max_dist_m >= 0 and cap_m > 0 expected");
  const long long N = (long long)positions.size();
  std::vector<float> d(positions.size());
  const float cap = float(cap_m);
#pragma omp parallel for schedule(dynamic, 4096)
  for (long long i = 0; i < N; ++i) {
    const Eigen::Vector3f& p = positions[std::size_t(i)];
    d[std::size_t(i)] =
        p.allFinite()
            ? surfaceDistanceBound(
                  scene, p, normals.empty() ? Eigen::Vector3f::Zero() : normals[std::size_t(i)],
                  cap)
            : cap;
  }
  SurfaceDistanceStats s;
  s.points = positions.size();
  s.max_dist_m = max_dist_m;
  s.cap_m = cap_m;
  double sum = 0.0;
  for (float v : d) {
    const bool in = double(v) <= max_dist_m && v < cap;
    s.within += in ? 1 : 0;
    sum += v;
  }
  s.beyond = s.points - s.within;
  if (s.points > 0) {
    s.fraction_beyond = double(s.beyond) / double(s.points);
    s.mean_m = sum / double(s.points);
    std::vector<float> sorted = d;
    std::sort(sorted.begin(), sorted.end());
    const auto q = [&](double f) {
      return double(sorted[std::size_t(std::llround(f * double(sorted.size() - 1)))]);
    };
    s.p50_m = q(0.5);
    s.p90_m = q(0.9);
    s.p95_m = q(0.95);
    s.p99_m = q(0.99);
    s.max_m = double(sorted.back());
  }
  if (distances_m) *distances_m = std::move(d);
  return s;
}

}  // namespace rasm::sim
