#pragma once
// Analytic RGB-D frames for fusion tests: a ray caster over a back wall (plane z_world = wall_z)
// and axis-aligned boxes, exact depth, colour from the hit surface, vertex/normal maps from core.

#include <Eigen/Geometry>
#include <cmath>
#include <vector>

#include "rasm/core/FrameProcessing.h"
#include "rasm/core/RgbdFrame.h"
#include "rasm/fusion/SurfelFusion.h"

namespace rasm::fusiontest {

struct Box {
  Eigen::Vector3d lo, hi;
  Bgr8 colour{0, 0, 255};
};

struct Scene {
  double wall_z = 3.0;  ///< plane z = wall_z (world), facing -z
  Bgr8 wall_colour{200, 200, 200};
  std::vector<Box> boxes;
};

/// Slab test; returns the ray parameter of the entry point or +inf.
inline double hitBox(const Box& b, const Eigen::Vector3d& o, const Eigen::Vector3d& d) {
  double t0 = 0.0, t1 = 1e30;
  for (int a = 0; a < 3; ++a) {
    if (std::abs(d[a]) < 1e-12) {
      if (o[a] < b.lo[a] || o[a] > b.hi[a]) return 1e30;
      continue;
    }
    double ta = (b.lo[a] - o[a]) / d[a], tb = (b.hi[a] - o[a]) / d[a];
    if (ta > tb) std::swap(ta, tb);
    t0 = std::max(t0, ta);
    t1 = std::min(t1, tb);
    if (t0 > t1) return 1e30;
  }
  return t0 > 0.0 ? t0 : 1e30;
}

struct SyntheticFrame {
  RgbdFrame frame;
  Image<Vec3f> vertex, normal;
  Eigen::Isometry3d T_world_cam = Eigen::Isometry3d::Identity();

  fusion::FusionInput input(const Image<std::uint32_t>* labels = nullptr) const {
    return fusion::makeFusionInput(frame, vertex, normal, T_world_cam, labels);
  }
};

/// Renders `scene` from T_world_cam (optical). Depth is the exact camera z of the first hit.
inline SyntheticFrame renderScene(const Scene& scene, const CameraIntrinsics& K,
                                  const Eigen::Isometry3d& T_world_cam, double t_s,
                                  double max_depth_m = 10.0) {
  SyntheticFrame f;
  f.T_world_cam = T_world_cam;
  f.frame.intrinsics = K;
  f.frame.timestamp_s = t_s;
  f.frame.depth_m.resize(K.width, K.height);
  f.frame.colour.resize(K.width, K.height);
  const Eigen::Vector3d o = T_world_cam.translation();
  for (int y = 0; y < K.height; ++y)
    for (int x = 0; x < K.width; ++x) {
      const Eigen::Vector3d dc((x - K.cx) / K.fx, (y - K.cy) / K.fy, 1.0);  // camera z = 1
      const Eigen::Vector3d dw = T_world_cam.linear() * dc;
      double best = 1e30;
      Bgr8 col{0, 0, 0};
      if (dw.z() > 1e-9) {
        const double t = (scene.wall_z - o.z()) / dw.z();
        if (t > 0) {
          best = t;
          col = scene.wall_colour;
        }
      }
      for (const Box& b : scene.boxes) {
        const double t = hitBox(b, o, dw);
        if (t < best) {
          best = t;
          col = b.colour;
        }
      }
      const bool valid = best < 1e29 && best <= max_depth_m;
      f.frame.depth_m(x, y) = valid ? float(best) : 0.0f;  // t is the camera z (dc.z = 1)
      f.frame.colour(x, y) = valid ? col : Bgr8{};
    }
  computeVertexMap(f.frame.depth_m, K, f.vertex);
  computeNormalMap(f.vertex, f.normal);
  return f;
}

}  // namespace rasm::fusiontest
