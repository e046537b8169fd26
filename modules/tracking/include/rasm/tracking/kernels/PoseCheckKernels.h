#pragma once
// Verification of an aligned pose against the data ("failures are detected, not
// fused"): after ICP, every frame pixel is moved by the estimated pose and projected into the
// model (the map rendered at the reference pose, as for the association of II-C). Of the pixels
// that land on the model's surface, a correct pose makes nearly all agree with it (same point
// within the sensor noise, same orientation); a wrong one makes many of them fall in front of the
// surface or, worse, behind it, where the map says space is occupied and the camera cannot see
// through. Pixels that land where the model has nothing (new space) say nothing either way.
// Plain header: only compute/, so a CUDA launcher can run the same body.

#include "rasm/compute/ImageView.h"
#include "rasm/compute/Types.h"
#include "rasm/tracking/kernels/IcpKernels.h"

namespace rasm::tracking::kernels {

/// Counts of one pose check (PoseCheckKernel): pixels of the frame by what they meet in the model.
struct PoseCheckCounts {
  long long valid = 0;       ///< frame pixels with a vertex and a normal
  long long agree = 0;       ///< on the model surface: within the gate, normals compatible
  long long front = 0;       ///< on the model pixel but nearer the camera than its surface
  long long behind = 0;      ///< behind the model surface: seeing through mapped space
  long long misaligned = 0;  ///< at the model surface's depth but off the gate or normal test
  /// Far in front of the model surface (beyond PoseCheckKernel::occluder_margin_m): something the
  /// map does not hold yet stands before a mapped surface (a chair before a wall the robot turns
  /// to). Says nothing about the pose, like new space: not part of the overlap.
  long long occluding = 0;
  long long overlap() const { return agree + front + behind + misaligned; }
  RASM_HD_INLINE PoseCheckCounts& operator+=(const PoseCheckCounts& o) {
    valid += o.valid;
    agree += o.agree;
    front += o.front;
    behind += o.behind;
    misaligned += o.misaligned;
    occluding += o.occluding;
    return *this;
  }
};

struct PoseCheckKernel {
  ImageView<const Vec3f> frame_vertex;  ///< camera frame
  ImageView<const Vec3f> frame_normal;  ///< camera frame
  ImageView<const Vec3f> model_vertex;  ///< world frame
  ImageView<const Vec3f> model_normal;  ///< world frame
  PinholeF K_model;
  RigidF T_world_cam;  ///< the pose under test
  RigidF T_model_cam;  ///< T_world_model^-1 * T_world_cam
  RigidF T_model_world;
  /// Agreement gate: |p - q| <= base_gate_m + noise_sigmas * depthNoiseSigma(z).
  float base_gate_m = 0.01f;
  float noise_sigmas = 3.0f;
  float min_normal_cos = 0.7f;
  /// Frame points further than this in front of the model surface are occluders, not errors.
  float occluder_margin_m = 0.15f;
  int stride = 1;

  RASM_HD_INLINE int rows() const { return (frame_vertex.height + stride - 1) / stride; }

  /// One row (y = i * stride) of the frame.
  RASM_HD_INLINE void operator()(int i, PoseCheckCounts& c) const {
    const int y = i * stride;
    for (int x = 0; x < frame_vertex.width; x += stride) {
      const Vec3f v = frame_vertex(x, y);
      const Vec3f nc = frame_normal(x, y);
      if (!(v.x() == v.x()) || !(nc.x() == nc.x())) continue;
      ++c.valid;
      const Vec3f pm = T_model_cam.apply(v);
      if (!(pm.z() > 0.0f)) continue;
      const float iz = 1.0f / pm.z();
      const float u = K_model.fx * pm.x() * iz + K_model.cx;
      const float vv = K_model.fy * pm.y() * iz + K_model.cy;
      if (!(u > -0.5f && vv > -0.5f && u < float(model_vertex.width) - 0.5f &&
            vv < float(model_vertex.height) - 0.5f))
        continue;
      const int ui = int(u + 0.5f), vi = int(vv + 0.5f);
      const Vec3f q = model_vertex(ui, vi);
      const Vec3f n = model_normal(ui, vi);
      if (!(q.x() == q.x()) || !(n.x() == n.x())) continue;
      const float gate = base_gate_m + noise_sigmas * depthNoiseSigma(pm.z());
      // Point-to-plane, as ICP's association: the signed distance of the moved point from the
      // model surface's tangent plane, the normal turned towards the model camera (> 0: in
      // front). The model pixel a frame point lands on holds a neighbouring point of the same
      // surface, up to half a pixel away: on a surface seen at a grazing angle (a robot's floor)
      // that is centimetres along the surface, which a point-to-point gate would count.
      const Vec3f qm = T_model_world.apply(q);
      Vec3f nm = T_model_world.rotate(n);
      if (nm.dot(qm) > 0.0f) nm = -nm;
      const float d = nm.dot(pm - qm);
      if (d < -gate)
        ++c.behind;
      else if (d > gate && d > occluder_margin_m)
        ++c.occluding;
      else if (d > gate)
        ++c.front;
      else if (T_world_cam.rotate(nc).dot(n) >= min_normal_cos)
        ++c.agree;
      else
        ++c.misaligned;
    }
  }
};

}  // namespace rasm::tracking::kernels
