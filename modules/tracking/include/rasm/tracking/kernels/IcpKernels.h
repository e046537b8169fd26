#pragma once
// Kernels of the point-to-plane ICP of section II-C (projective data association, KinectFusion
// [30]), written once for the CPU (compute::reduce1D over rows) and CUDA (cuda/IcpReduce.cu).
// Plain header: only compute/ and Eigen, so .cu files include it.
//
// Linearisation. The pose is updated left-multiplicatively about a pivot c (the camera centre of
// the current estimate, in world coordinates):
//     T_world_cam <- P * exp(xi) * P^-1 * T_world_cam,   P = translation(c),  xi = [rho; omega]
// i.e. the increment is a twist in a frame with the world's axes centred on the camera. Centring
// keeps rotation and translation decoupled (J^T J well conditioned) wherever the world origin is.
// For a frame vertex v (camera frame) moved to world p = T_world_cam v, and its projectively
// associated model vertex q with normal n (world frame), the point-to-plane residual and its
// Jacobian w.r.t. xi at xi = 0 are
//     r = n . (p - q),      J = [ n^T , ((p - c) x n)^T ].
// The reduction sums J^T J (21 unique entries), J^T r, r^2 and counts; the host solves
// (J^T J) xi = -J^T r.

#include <cmath>

#include "rasm/compute/ImageView.h"
#include "rasm/compute/Types.h"

namespace rasm::tracking::kernels {

/// Sums of the normal equations, a flat array so both backends reduce it element-wise:
/// s[kJtJ + k]: upper triangle of J^T J row-major, (0,0) (0,1) .. (0,5) (1,1) .. (5,5);
/// s[kJtr + i]: J^T r; s[kR2]: sum of squared (unweighted) inlier residuals; s[kInliers];
/// s[kValid]: frame pixels with a valid vertex and normal; s[kDepth]: sum of inlier depths
/// (the scale that balances the rotation columns, see IcpTracker).
struct IcpAccumulator {
  static constexpr int kJtJ = 0, kJtr = 21, kR2 = 27, kInliers = 28, kValid = 29, kDepth = 30;
  static constexpr int kSize = 31;
  double s[kSize] = {};

  RASM_HD_INLINE double inliers() const { return s[kInliers]; }
  RASM_HD_INLINE double valid() const { return s[kValid]; }
  RASM_HD_INLINE IcpAccumulator& operator+=(const IcpAccumulator& o) {
    for (int i = 0; i < kSize; ++i) s[i] += o.s[i];
    return *this;
  }
};

/// Outcome of one pixel.
enum IcpPixel : int { kIcpInvalid = 0, kIcpRejected = 1, kIcpInlier = 2 };

/// Association, residual and Jacobian of the point-to-plane ICP (II-C) for one level.
struct IcpReduceKernel {
  ImageView<const Vec3f> frame_vertex;  ///< camera frame, this level
  ImageView<const Vec3f> frame_normal;  ///< camera frame, this level
  ImageView<const Vec3f> model_vertex;  ///< world frame, this level
  ImageView<const Vec3f> model_normal;  ///< world frame, this level
  PinholeF K_model;                     ///< intrinsics of the model maps at this level
  RigidF T_world_cam;                   ///< current estimate
  RigidF T_model_cam;                   ///< T_world_model^-1 * T_world_cam (for association)
  Vec3f pivot_world = Vec3f::Zero();    ///< c: centre of the rotation increment
  float max_dist_m = 0.1f;              ///< |p - q| limit
  float min_normal_cos = 0.866f;        ///< cos of the max angle between normals
  float huber_delta_m = 0.0f;           ///< 0 = no robust weight
  int stride = 1;                       ///< process every stride-th pixel in x and y

  /// Work items of the CPU reduction: row segments of kSegment processed pixels (rows alone are
  /// too few work items for compute::reduce1D to split them over threads at coarse levels).
  static constexpr int kSegment = 64;
  RASM_HD_INLINE int rows() const { return (frame_vertex.height + stride - 1) / stride; }
  RASM_HD_INLINE int cols() const { return (frame_vertex.width + stride - 1) / stride; }
  RASM_HD_INLINE int segmentsPerRow() const { return (cols() + kSegment - 1) / kSegment; }
  RASM_HD_INLINE int items() const { return rows() * segmentsPerRow(); }

  /// Projective association and point-to-plane term of pixel (x, y) of the frame (II-C).
  /// On kIcpInlier fills J (6), the residual r (m) and the IRLS weight w.
  RASM_HD_INLINE int pixel(int x, int y, float J[6], float& r, float& w, float& depth) const {
    const Vec3f v = frame_vertex(x, y);
    const Vec3f nc = frame_normal(x, y);
    if (!(v.x() == v.x()) || !(nc.x() == nc.x())) return kIcpInvalid;
    // Projective association: project the moved vertex into the model camera.
    const Vec3f pm = T_model_cam.apply(v);
    if (!(pm.z() > 0.0f)) return kIcpRejected;
    const float iz = 1.0f / pm.z();
    const float u = K_model.fx * pm.x() * iz + K_model.cx;
    const float vv = K_model.fy * pm.y() * iz + K_model.cy;
    if (!(u > -0.5f && vv > -0.5f && u < float(model_vertex.width) - 0.5f &&
          vv < float(model_vertex.height) - 0.5f))
      return kIcpRejected;
    const int ui = int(u + 0.5f), vi = int(vv + 0.5f);
    const Vec3f q = model_vertex(ui, vi);
    const Vec3f n = model_normal(ui, vi);
    if (!(q.x() == q.x()) || !(n.x() == n.x())) return kIcpRejected;
    // Compatibility: distance and normal angle (KinectFusion's rejection tests).
    const Vec3f p = T_world_cam.apply(v);
    const Vec3f d = p - q;
    if (d.squaredNorm() > max_dist_m * max_dist_m) return kIcpRejected;
    if (T_world_cam.rotate(nc).dot(n) < min_normal_cos) return kIcpRejected;
    r = n.dot(d);
    const Vec3f pc = p - pivot_world;
    const Vec3f c = pc.cross(n);
    J[0] = n.x();
    J[1] = n.y();
    J[2] = n.z();
    J[3] = c.x();
    J[4] = c.y();
    J[5] = c.z();
    const float ar = fabsf(r);
    w = (huber_delta_m > 0.0f && ar > huber_delta_m) ? huber_delta_m / ar : 1.0f;
    depth = v.z();
    return kIcpInlier;
  }

  /// Adds one (weighted) inlier term to a flat array of IcpAccumulator layout (CUDA path).
  template <typename T>
  RASM_HD_INLINE static void accumulate(T* a, const float J[6], float r, float w, float depth) {
    int k = IcpAccumulator::kJtJ;
    for (int i = 0; i < 6; ++i) {
      const float wJi = w * J[i];
      for (int j = i; j < 6; ++j) a[k++] += T(wJi * J[j]);
    }
    for (int i = 0; i < 6; ++i) a[IcpAccumulator::kJtr + i] += T(w * J[i] * r);
    a[IcpAccumulator::kR2] += T(r * r);
    a[IcpAccumulator::kInliers] += T(1);
    a[IcpAccumulator::kDepth] += T(depth);
  }

  /// CPU path: work item i = one row segment. Two passes, so the arithmetic vectorises: (1)
  /// association, residuals and Jacobians of the segment's pixels, inliers compacted into
  /// structure-of-arrays buffers; (2) the 21 + 6 + 1 sums as dot products over the inliers
  /// (SIMD across pixels), in float over <= kSegment terms, then added to the double accumulator.
  void operator()(int i, IcpAccumulator& acc) const {
    const int spr = segmentsPerRow();
    const int y = (i / spr) * stride;
    const int xs0 = (i % spr) * kSegment;
    const int xs1 = xs0 + kSegment < cols() ? xs0 + kSegment : cols();
    alignas(64) float Jb[6][kSegment];
    alignas(64) float wJb[6][kSegment];
    alignas(64) float rb[kSegment];
    float J[6], r = 0.f, w = 0.f, depth = 0.f, depth_sum = 0.f;
    int valid = 0, n = 0;
    for (int xs = xs0; xs < xs1; ++xs) {
      const int s = pixel(xs * stride, y, J, r, w, depth);
      if (s == kIcpInvalid) continue;
      ++valid;
      if (s != kIcpInlier) continue;
      for (int c = 0; c < 6; ++c) {
        Jb[c][n] = J[c];
        wJb[c][n] = w * J[c];
      }
      rb[n] = r;
      depth_sum += depth;
      ++n;
    }
    double* a = acc.s;
    int k = IcpAccumulator::kJtJ;
    for (int c = 0; c < 6; ++c)
      for (int d = c; d < 6; ++d) {
        float sum = 0.f;
#pragma omp simd reduction(+ : sum)
        for (int p = 0; p < n; ++p) sum += wJb[c][p] * Jb[d][p];
        a[k++] += double(sum);
      }
    for (int c = 0; c < 6; ++c) {
      float sum = 0.f;
#pragma omp simd reduction(+ : sum)
      for (int p = 0; p < n; ++p) sum += wJb[c][p] * rb[p];
      a[IcpAccumulator::kJtr + c] += double(sum);
    }
    float r2 = 0.f;
#pragma omp simd reduction(+ : r2)
    for (int p = 0; p < n; ++p) r2 += rb[p] * rb[p];
    a[IcpAccumulator::kR2] += double(r2);
    a[IcpAccumulator::kInliers] += double(n);
    a[IcpAccumulator::kValid] += double(valid);
    a[IcpAccumulator::kDepth] += double(depth_sum);
  }
};

/// Model pyramid (II-C): half-resolution world-frame vertex/normal maps. Of each 2x2 block, the
/// valid samples within `max_diff_m` (depth along the model camera) of the nearest one are
/// averaged, the normals renormalised: the same rule core's DepthDownsampleKernel applies to the
/// frame's depth, so model and frame pyramids sample the same surfaces at the same pixel centres.
struct ModelDownsampleKernel {
  ImageView<const Vec3f> in_vertex, in_normal;  ///< world frame, level l
  ImageView<Vec3f> out_vertex, out_normal;      ///< world frame, level l + 1
  RigidF T_model_world;                         ///< to measure depth along the model camera
  float max_diff_m = 0.03f;

  RASM_HD_INLINE void operator()(int x, int y) const {
    Vec3f vs[4], ns[4];
    float zs[4];
    int n = 0;
    float nearest = 1e30f;
    for (int dy = 0; dy < 2; ++dy)
      for (int dx = 0; dx < 2; ++dx) {
        const int sx = 2 * x + dx, sy = 2 * y + dy;
        if (sx >= in_vertex.width || sy >= in_vertex.height) continue;
        const Vec3f v = in_vertex(sx, sy), nn = in_normal(sx, sy);
        if (!(v.x() == v.x()) || !(nn.x() == nn.x())) continue;
        const float* m = T_model_world.m;  // depth along the model camera: row 2 of [R | t]
        const float z = m[8] * v.x() + m[9] * v.y() + m[10] * v.z() + m[11];
        vs[n] = v;
        ns[n] = nn;
        zs[n] = z;
        if (z < nearest) nearest = z;
        ++n;
      }
    if (n == 0) {
      const float nan = compute::invalidFloat();
      out_vertex(x, y) = Vec3f(nan, nan, nan);
      out_normal(x, y) = Vec3f(nan, nan, nan);
      return;
    }
    Vec3f vsum = Vec3f::Zero(), nsum = Vec3f::Zero();
    int cnt = 0;
    for (int i = 0; i < n; ++i)
      if (zs[i] - nearest <= max_diff_m) {
        vsum += vs[i];
        nsum += ns[i];
        ++cnt;
      }
    const float len = nsum.norm();
    if (len > 1e-6f) {
      out_vertex(x, y) = vsum / float(cnt);
      out_normal(x, y) = nsum / len;
    } else {  // opposing normals (a thin sheet seen edge-on): no reliable sample
      const float nan = compute::invalidFloat();
      out_vertex(x, y) = Vec3f(nan, nan, nan);
      out_normal(x, y) = Vec3f(nan, nan, nan);
    }
  }
};

}  // namespace rasm::tracking::kernels
