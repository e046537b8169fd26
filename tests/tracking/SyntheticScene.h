#pragma once
// Analytic test scenes for the tracker: a set of planes, axis-aligned boxes and spheres ray-cast
// exactly into a depth image for any camera pose (no sampling, no mesh), so the ground-truth
// motion between two frames is known to machine precision.

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <functional>
#include <limits>
#include <random>
#include <vector>

#include "rasm/core/CameraIntrinsics.h"
#include "rasm/core/FrameProcessing.h"
#include "rasm/core/Image.h"

namespace rasm::test {

struct Scene {
  struct Plane {  // n . x = d, one-sided: visible from where n . x < d would be "behind"
    Eigen::Vector3d n;
    double d;
  };
  struct Box {  // axis-aligned, solid (seen from outside) or room (seen from inside)
    Eigen::Vector3d lo, hi;
    bool inside = false;
  };
  struct Sphere {
    Eigen::Vector3d c;
    double r;
  };
  std::vector<Plane> planes;
  std::vector<Box> boxes;
  std::vector<Sphere> spheres;
  /// Grey level of the surfaces at a world point, in [0, 1] (renderColour); none = uniform 0.5.
  std::function<double(const Eigen::Vector3d&)> texture;

  /// Distance along the unit ray o + t d to the first surface (t > 1e-6), or +inf.
  double cast(const Eigen::Vector3d& o, const Eigen::Vector3d& d) const {
    double best = std::numeric_limits<double>::infinity();
    for (const auto& p : planes) {
      const double den = p.n.dot(d);
      if (std::abs(den) < 1e-12) continue;
      const double t = (p.d - p.n.dot(o)) / den;
      if (t > 1e-6 && t < best) best = t;
    }
    for (const auto& b : boxes) {
      double t0 = -std::numeric_limits<double>::infinity(),
             t1 = std::numeric_limits<double>::infinity();
      for (int i = 0; i < 3; ++i) {
        if (std::abs(d[i]) < 1e-15) {
          if (o[i] < b.lo[i] || o[i] > b.hi[i]) t0 = std::numeric_limits<double>::infinity();
          continue;
        }
        double ta = (b.lo[i] - o[i]) / d[i], tb = (b.hi[i] - o[i]) / d[i];
        if (ta > tb) std::swap(ta, tb);
        t0 = std::max(t0, ta);
        t1 = std::min(t1, tb);
      }
      if (t0 > t1) continue;
      const double t = b.inside ? t1 : t0;
      if (t > 1e-6 && t < best) best = t;
    }
    for (const auto& s : spheres) {
      const Eigen::Vector3d oc = o - s.c;
      const double bq = oc.dot(d), c = oc.squaredNorm() - s.r * s.r, disc = bq * bq - c;
      if (disc < 0) continue;
      const double t = -bq - std::sqrt(disc);
      if (t > 1e-6 && t < best) best = t;
    }
    return best;
  }

  /// Depth image (z along the optical axis, metres; 0 = no hit or beyond max_depth_m) seen from
  /// T_world_cam, with optional Gaussian noise of sigma_m on each valid depth.
  Image<float> render(const CameraIntrinsics& K, const Eigen::Isometry3d& T_world_cam,
                      double sigma_m = 0.0, unsigned seed = 1, double max_depth_m = 8.0) const {
    Image<float> depth(K.width, K.height, 0.0f);
    const Eigen::Matrix3d R = T_world_cam.linear();
    const Eigen::Vector3d o = T_world_cam.translation();
#pragma omp parallel for schedule(static)
    for (int y = 0; y < K.height; ++y)
      for (int x = 0; x < K.width; ++x) {
        const Eigen::Vector3d ray_c((x - K.cx) / K.fx, (y - K.cy) / K.fy, 1.0);
        const double t = cast(o, (R * ray_c).normalized());
        if (!std::isfinite(t)) continue;
        const double z = t / ray_c.norm();  // depth along the optical axis
        if (z > 0 && z <= max_depth_m) depth(x, y) = float(z);
      }
    if (sigma_m > 0) {  // sequential, so the noise does not depend on the thread count
      std::mt19937 rng(seed);
      std::normal_distribution<double> noise(0.0, sigma_m);
      for (int y = 0; y < K.height; ++y)
        for (int x = 0; x < K.width; ++x)
          if (depth(x, y) > 0) depth(x, y) = float(std::max(1e-3, depth(x, y) + noise(rng)));
    }
    return depth;
  }

  /// Colour image (grey, B = G = R) of the texture seen from T_world_cam, registered to render()'s
  /// depth; black where no surface is hit.
  Image<Bgr8> renderColour(const CameraIntrinsics& K, const Eigen::Isometry3d& T_world_cam) const {
    Image<Bgr8> colour(K.width, K.height, Bgr8{});
    const Eigen::Matrix3d R = T_world_cam.linear();
    const Eigen::Vector3d o = T_world_cam.translation();
#pragma omp parallel for schedule(static)
    for (int y = 0; y < K.height; ++y)
      for (int x = 0; x < K.width; ++x) {
        const Eigen::Vector3d d =
            (R * Eigen::Vector3d((x - K.cx) / K.fx, (y - K.cy) / K.fy, 1.0)).normalized();
        const double t = cast(o, d);
        if (!std::isfinite(t)) continue;
        const double g = texture ? texture(o + t * d) : 0.5;
        const auto v = std::uint8_t(std::lround(255.0 * std::clamp(g, 0.0, 1.0)));
        colour(x, y) = Bgr8{v, v, v};
      }
    return colour;
  }

  /// A smooth grey-level pattern (periods 11-30 cm: 20-80 px at 2 m with f = 525 px), so image
  /// gradients are well defined at every pyramid level.
  static double smoothTexture(const Eigen::Vector3d& p) {
    const double k = 2.0 * M_PI;
    return 0.5 + 0.2 * std::sin(k * p.x() / 0.3) * std::sin(k * p.z() / 0.25) +
           0.12 * std::sin(k * (p.x() + p.y() + p.z()) / 0.11);
  }

  /// A room (4 x 4 x 3 m, seen from inside) with two boxes and a sphere: every direction of
  /// motion is constrained.
  static Scene room() {
    Scene s;
    s.boxes.push_back({{-2, -2, 0}, {2, 2, 3}, true});
    s.boxes.push_back({{-0.6, 0.8, 0}, {0.2, 1.4, 0.7}, false});
    s.boxes.push_back({{0.7, 0.2, 0}, {1.2, 0.6, 1.1}, false});
    s.spheres.push_back({{-1.0, 0.3, 0.5}, 0.35});
    return s;
  }
  /// A single infinite wall y = 2 (normal -y towards the camera): degenerate for ICP.
  static Scene wall() {
    Scene s;
    s.planes.push_back({{0, 1, 0}, 2.0});
    return s;
  }
  /// The same wall with smoothTexture painted on it: degenerate geometry, informative colour.
  static Scene texturedWall() {
    Scene s = wall();
    s.texture = smoothTexture;
    return s;
  }
};

/// Camera pose looking from `eye` at `target` with world up +z (optical frame: x right, y down,
/// z forward).
inline Eigen::Isometry3d lookAt(const Eigen::Vector3d& eye, const Eigen::Vector3d& target) {
  const Eigen::Vector3d z = (target - eye).normalized();
  const Eigen::Vector3d x = z.cross(Eigen::Vector3d::UnitZ()).normalized();
  const Eigen::Vector3d y = z.cross(x);
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.linear().col(0) = x;
  T.linear().col(1) = y;
  T.linear().col(2) = z;
  T.translation() = eye;
  return T;
}

/// Small rigid motion: translation (m) and rotation (deg) about a unit axis.
inline Eigen::Isometry3d motion(const Eigen::Vector3d& t, const Eigen::Vector3d& axis,
                                double angle_deg) {
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.linear() = Eigen::AngleAxisd(angle_deg * M_PI / 180.0, axis.normalized()).toRotationMatrix();
  T.translation() = t;
  return T;
}

/// Model maps as the tracker expects them: the level-0 vertex/normal of a frame seen from
/// T_world_cam, moved to the world frame.
struct WorldMaps {
  Image<Vec3f> vertex, normal;
  WorldMaps(const FrameLevel& L, const Eigen::Isometry3d& T_world_cam) {
    vertex = L.vertex;
    normal = L.normal;
    const Eigen::Matrix3f R = T_world_cam.linear().cast<float>();
    const Eigen::Vector3f t = T_world_cam.translation().cast<float>();
    for (int y = 0; y < vertex.height(); ++y)
      for (int x = 0; x < vertex.width(); ++x) {
        if (vertex(x, y).x() == vertex(x, y).x()) vertex(x, y) = R * vertex(x, y) + t;
        if (normal(x, y).x() == normal(x, y).x()) normal(x, y) = R * normal(x, y);
      }
  }
};

}  // namespace rasm::test
