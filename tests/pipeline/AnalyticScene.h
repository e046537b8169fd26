#pragma once
// Analytic RGB-D scenes for the pipeline's stage tests: a room corner (back wall z = 3, floor
// y = 0.6, left wall x = -1.0: ICP is constrained in every direction) with axis-aligned boxes,
// noise-free depth, and a stage that replaces the tracked pose by the frame's ground truth.

#include <Eigen/Geometry>
#include <cmath>
#include <vector>

#include "rasm/pipeline/MapperStage.h"

namespace rasm::pipeline::testing {

inline const CameraIntrinsics kK(262.5, 262.5, 159.5, 119.5, 320, 240);

struct Box {
  Eigen::Vector3d lo, hi;
};

inline double hitBox(const Box& b, const Eigen::Vector3d& o, const Eigen::Vector3d& d) {
  double t0 = 0.0, t1 = INFINITY;
  for (int a = 0; a < 3; ++a) {
    double ta = (b.lo[a] - o[a]) / d[a], tb = (b.hi[a] - o[a]) / d[a];
    if (ta > tb) std::swap(ta, tb);
    t0 = std::max(t0, ta);
    t1 = std::min(t1, tb);
  }
  return t0 <= t1 && t0 > 0 ? t0 : INFINITY;
}

/// The room corner and boxes seen from T (optical frame = world axes, moved by T).
inline RgbdFrame render(const std::vector<Box>& boxes, const Eigen::Isometry3d& T, int index) {
  RgbdFrame f;
  f.intrinsics = kK;
  f.index = std::size_t(index);
  f.timestamp_s = index / 30.0;
  f.gt_T_world_cam = T;
  f.depth_m.resize(kK.width, kK.height);
  f.colour.resize(kK.width, kK.height);
  const Eigen::Vector3d o = T.translation();
  for (int y = 0; y < kK.height; ++y)
    for (int x = 0; x < kK.width; ++x) {
      const Eigen::Vector3d dc((x - kK.cx) / kK.fx, (y - kK.cy) / kK.fy, 1.0);
      const Eigen::Vector3d d = T.linear() * dc;
      double t = d.z() > 1e-9 ? (3.0 - o.z()) / d.z() : INFINITY;
      if (d.y() > 1e-9) t = std::min(t, (0.6 - o.y()) / d.y());
      if (d.x() < -1e-9) t = std::min(t, (-1.0 - o.x()) / d.x());
      for (const Box& b : boxes) t = std::min(t, hitBox(b, o, d));
      // d has camera z = 1: along the optical axis t is the depth.
      f.depth_m(x, y) = std::isfinite(t) ? float(t) : 0.0f;
      f.colour(x, y) = Bgr8{128, 128, 128};
    }
  return f;
}

inline Eigen::Isometry3d at(double x) {
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.translation().x() = x;
  return T;
}

/// Replaces the tracked pose by the frame's ground truth: these tests are about segmentation,
/// and noise-free boxes in a room corner are a poor ICP scene (degenerate with a sparse model).
class GroundTruthPose : public MapperStage {
 public:
  GroundTruthPose() : MapperStage("ground_truth_pose") {}
  void process(FrameContext& ctx, maps::CSurfelMap&) override {
    ctx.result.T_world_cam = *ctx.frame->gt_T_world_cam;
    ctx.result.tracked = true;
    ctx.result.relocalised = false;
    ctx.result.pose_source = PoseSource::Tracked;
  }
};

}  // namespace rasm::pipeline::testing
