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
#include "rasm/core/kernels/DepthNoiseModel.h"

namespace rasm::tracking::kernels {

/// Sums of the normal equations, a flat array so both backends reduce it element-wise:
/// s[kJtJ + k]: upper triangle of J^T W J row-major, (0,0) (0,1) .. (0,5) (1,1) .. (5,5);
/// s[kJtr + i]: J^T W r; s[kR2]: sum of squared (unweighted) inlier residuals; s[kInliers];
/// s[kValid]: pixels with valid input (frame vertex and normal for ICP, model vertex and
/// intensity for the photometric term); s[kDepth]: sum of inlier depths (the scale that balances
/// the rotation columns, see IcpTracker); s[kW]: sum of the weights; s[kWR2]: sum of w r^2.
struct IcpAccumulator {
  static constexpr int kJtJ = 0, kJtr = 21, kR2 = 27, kInliers = 28, kValid = 29, kDepth = 30,
                       kW = 31, kWR2 = 32;
  static constexpr int kSize = 33;
  double s[kSize] = {};

  RASM_HD_INLINE double inliers() const { return s[kInliers]; }
  RASM_HD_INLINE double valid() const { return s[kValid]; }
  RASM_HD_INLINE IcpAccumulator& operator+=(const IcpAccumulator& o) {
    for (int i = 0; i < kSize; ++i) s[i] += o.s[i];
    return *this;
  }
};

/// Axial noise of Kinect-type depth at normal incidence, sigma_z(z, 0) of Nguyen et al.
/// (core/kernels/DepthNoiseModel.h; sigma(1 m) = 1.9 mm, sigma(3 m) = 14 mm).
RASM_HD_INLINE float depthNoiseSigma(float z_m) {
  return rasm::sensor::AxialNoiseModel().sigmaG(z_m, 0.0f);
}

/// Adds one weighted term to a flat array of IcpAccumulator layout (CUDA path).
template <typename T>
RASM_HD_INLINE void accumulateTerm(T* a, const float J[6], float r, float w, float depth) {
  int k = IcpAccumulator::kJtJ;
  for (int i = 0; i < 6; ++i) {
    const float wJi = w * J[i];
    for (int j = i; j < 6; ++j) a[k++] += T(wJi * J[j]);
  }
  for (int i = 0; i < 6; ++i) a[IcpAccumulator::kJtr + i] += T(w * J[i] * r);
  a[IcpAccumulator::kR2] += T(r * r);
  a[IcpAccumulator::kInliers] += T(1);
  a[IcpAccumulator::kDepth] += T(depth);
  a[IcpAccumulator::kW] += T(w);
  a[IcpAccumulator::kWR2] += T(w * r * r);
}

/// Outcome of one pixel.
enum IcpPixel : int { kIcpInvalid = 0, kIcpRejected = 1, kIcpInlier = 2 };

/// The sums of a row segment's n inliers (SoA buffers: J, w J, r, w), valid pixels and inlier
/// depth sum into acc: dot products over the inliers (SIMD across pixels) in float over <=
/// kSegment terms, then added to the double accumulator (reduceRowSegment's sums).
template <int kSegment>
inline void accumulateSegment(const float (&Jb)[6][kSegment], const float (&wJb)[6][kSegment],
                              const float (&rb)[kSegment], const float (&wb)[kSegment], int n,
                              int valid, float depth_sum, IcpAccumulator& acc) {
  double* a = acc.s;
  int kk = IcpAccumulator::kJtJ;
  for (int c = 0; c < 6; ++c)
    for (int d = c; d < 6; ++d) {
      float sum = 0.f;
#pragma omp simd reduction(+ : sum)
      for (int p = 0; p < n; ++p) sum += wJb[c][p] * Jb[d][p];
      a[kk++] += double(sum);
    }
  for (int c = 0; c < 6; ++c) {
    float sum = 0.f;
#pragma omp simd reduction(+ : sum)
    for (int p = 0; p < n; ++p) sum += wJb[c][p] * rb[p];
    a[IcpAccumulator::kJtr + c] += double(sum);
  }
  float r2 = 0.f, wsum = 0.f, wr2 = 0.f;
#pragma omp simd reduction(+ : r2, wsum, wr2)
  for (int p = 0; p < n; ++p) {
    r2 += rb[p] * rb[p];
    wsum += wb[p];
    wr2 += wb[p] * rb[p] * rb[p];
  }
  a[IcpAccumulator::kR2] += double(r2);
  a[IcpAccumulator::kInliers] += double(n);
  a[IcpAccumulator::kValid] += double(valid);
  a[IcpAccumulator::kDepth] += double(depth_sum);
  a[IcpAccumulator::kW] += double(wsum);
  a[IcpAccumulator::kWR2] += double(wr2);
}

/// CPU reduction of one work item (a row segment of kSegment processed pixels) of a kernel with
/// `int pixel(x, y, J, r, w, depth)`, `stride`, `cols()` and `segmentsPerRow()`. Two passes, so
/// the arithmetic vectorises: (1) the kernel's pixels, inliers compacted into
/// structure-of-arrays buffers; (2) the sums as dot products over the inliers (SIMD across
/// pixels), in float over <= kSegment terms, then added to the double accumulator.
/// Work item i of a CPU reduction: frame row y (stride applied) and the strided column range
/// [xs0, xs1) of its kSegment-pixel segment.
struct RowSegment {
  int y, xs0, xs1;
};
template <int kSegment, typename Kernel>
inline RowSegment rowSegment(const Kernel& k, int i) {
  const int spr = k.segmentsPerRow();
  const int xs0 = (i % spr) * kSegment;
  return {(i / spr) * k.stride, xs0, xs0 + kSegment < k.cols() ? xs0 + kSegment : k.cols()};
}

template <int kSegment, typename Kernel>
inline void reduceRowSegment(const Kernel& k, int i, IcpAccumulator& acc) {
  const auto [y, xs0, xs1] = rowSegment<kSegment>(k, i);
  alignas(64) float Jb[6][kSegment];
  alignas(64) float wJb[6][kSegment];
  alignas(64) float rb[kSegment];
  alignas(64) float wb[kSegment];
  float J[6], r = 0.f, w = 0.f, depth = 0.f, depth_sum = 0.f;
  int valid = 0, n = 0;
  for (int xs = xs0; xs < xs1; ++xs) {
    const int s = k.pixel(xs * k.stride, y, J, r, w, depth);
    if (s == kIcpInvalid) continue;
    ++valid;
    if (s != kIcpInlier) continue;
    for (int c = 0; c < 6; ++c) {
      Jb[c][n] = J[c];
      wJb[c][n] = w * J[c];
    }
    rb[n] = r;
    wb[n] = w;
    depth_sum += depth;
    ++n;
  }
  accumulateSegment<kSegment>(Jb, wJb, rb, wb, n, valid, depth_sum, acc);
}

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
  float huber_delta_m = 0.0f;           ///< 0 = no robust weight (on the noise-scaled residual)
  /// Weight residuals by (sigma(1 m) / sigma)^2, sigma = sigma_z of the frame point: at its
  /// depth only (depthNoiseSigma), or with depth_noise_incidence also at its incidence angle, the
  /// angle between the frame normal and the viewing ray (Nguyen et al.'s angle term).
  bool depth_noise_weighting = false;
  bool depth_noise_incidence = false;
  /// Optional (data = nullptr: none): confidence of the model surfel of each model pixel; the
  /// residual's weight is multiplied by min(1, confidence / confidence_full).
  ImageView<const float> model_confidence;
  float confidence_full = 10.0f;
  int stride = 1;  ///< process every stride-th pixel in x and y

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
    // IRLS weight: sensor noise (the residual's expected scale relative to a point at 1 m), then
    // Huber on the residual in those units.
    const float s = depth_noise_weighting ? depthNoiseSigma(1.0f) / frameNoiseSigma(v, nc) : 1.0f;
    const float ar = fabsf(r) * s;
    w = s * s * ((huber_delta_m > 0.0f && ar > huber_delta_m) ? huber_delta_m / ar : 1.0f);
    if (model_confidence.data) {
      const float c = model_confidence(ui, vi) / confidence_full;
      w *= c < 1.0f ? c : 1.0f;
    }
    depth = v.z();
    return kIcpInlier;
  }

  /// sigma_z (m) of the frame point v (camera frame) with normal nc: at its depth, and with
  /// depth_noise_incidence at its incidence angle too.
  RASM_HD_INLINE float frameNoiseSigma(const Vec3f& v, const Vec3f& nc) const {
    float g = 0.0f;
    if (depth_noise_incidence) {
      const float cos_incidence = fabsf(nc.dot(v)) / v.norm();
      g = rasm::sensor::incidenceAngleFactor(rasm::sensor::fastAcos01(cos_incidence));
    }
    return rasm::sensor::AxialNoiseModel().sigmaG(v.z(), g);
  }

  /// CPU path: work item i = one row segment (reduceRowSegment).
  void operator()(int i, IcpAccumulator& acc) const { reduceRowSegment<kSegment>(*this, i, acc); }
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
  /// Optional (data = nullptr: none): the model's intensity (NaN = none), averaged over the same
  /// samples as the vertices, for the photometric term.
  ImageView<const float> in_intensity;
  ImageView<float> out_intensity;
  /// Optional likewise: the model's surfel confidence.
  ImageView<const float> in_confidence;
  ImageView<float> out_confidence;

  RASM_HD_INLINE void operator()(int x, int y) const {
    Vec3f vs[4], ns[4];
    float zs[4], is[4], cs[4];
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
        is[n] = out_intensity.data ? in_intensity(sx, sy) : 0.0f;
        cs[n] = out_confidence.data ? in_confidence(sx, sy) : 0.0f;
        if (z < nearest) nearest = z;
        ++n;
      }
    const float nan = compute::invalidFloat();
    if (n == 0) {
      out_vertex(x, y) = Vec3f(nan, nan, nan);
      out_normal(x, y) = Vec3f(nan, nan, nan);
      if (out_intensity.data) out_intensity(x, y) = nan;
      if (out_confidence.data) out_confidence(x, y) = 0.0f;
      return;
    }
    Vec3f vsum = Vec3f::Zero(), nsum = Vec3f::Zero();
    float isum = 0.0f, csum = 0.0f;
    int cnt = 0, icnt = 0;
    for (int i = 0; i < n; ++i)
      if (zs[i] - nearest <= max_diff_m) {
        vsum += vs[i];
        nsum += ns[i];
        csum += cs[i];
        ++cnt;
        if (is[i] == is[i]) {
          isum += is[i];
          ++icnt;
        }
      }
    const float len = nsum.norm();
    if (len > 1e-6f) {
      out_vertex(x, y) = vsum / float(cnt);
      out_normal(x, y) = nsum / len;
      if (out_intensity.data) out_intensity(x, y) = icnt > 0 ? isum / float(icnt) : nan;
      if (out_confidence.data) out_confidence(x, y) = csum / float(cnt);
    } else {  // opposing normals (a thin sheet seen edge-on): no reliable sample
      out_vertex(x, y) = Vec3f(nan, nan, nan);
      out_normal(x, y) = Vec3f(nan, nan, nan);
      if (out_intensity.data) out_intensity(x, y) = nan;
      if (out_confidence.data) out_confidence(x, y) = 0.0f;
    }
  }
};

// ---- photometric term ----------------------------------------------------------------------
// Joint geometric + photometric tracking as ElasticFusion / Kintinuous (RGB-D odometry of
// Steinbruecker et al. 2011 combined with ICP): for a model pixel with world vertex q and
// intensity I_m, warped into the frame by the current estimate, p = T_world_cam^-1 q,
//     r = I_f(pi(p)) - I_m,
// I_f bilinearly interpolated. With the increment of IcpReduceKernel (T <- P exp(xi) P^-1 T,
// pivot c), p(xi) = R^T (exp(-xi) (q - c) + c - t), so dp/dxi = R^T [-I, [q - c]_x] at xi = 0 and
//     J = [ -b^T, (b x (q - c))^T ],   b = R a,   a = dpi/dp^T grad I_f(pi(p)),
// with dpi/dp = [fx/z 0 -fx x/z^2; 0 fy/z -fy y/z^2] and R = rotation of T_world_cam.
// Intensity is luma in [0, 1].

/// Luma in [0, 1] of a B,G,R pixel (ITU-R BT.601 weights).
RASM_HD_INLINE float luma(const Bgr8& c) {
  return (0.114f * float(c.b) + 0.587f * float(c.g) + 0.299f * float(c.r)) * (1.0f / 255.0f);
}

/// Intensity of a colour image; where `valid_vertex` (optional) is invalid, NaN (the model's
/// rendered colour is black where nothing was rendered).
struct IntensityKernel {
  ImageView<const Bgr8> colour;
  ImageView<const Vec3f> valid_vertex;  ///< data = nullptr: every pixel valid
  ImageView<float> out;

  RASM_HD_INLINE void operator()(int x, int y) const {
    if (valid_vertex.data && !(valid_vertex(x, y).x() == valid_vertex(x, y).x()))
      out(x, y) = compute::invalidFloat();
    else
      out(x, y) = luma(colour(x, y));
  }
};

/// Half-resolution frame intensity: the mean of the 2x2 block (the pixel centres of core's depth
/// pyramid and CameraIntrinsics::level).
struct IntensityDownsampleKernel {
  ImageView<const float> in;
  ImageView<float> out;

  RASM_HD_INLINE void operator()(int x, int y) const {
    float sum = 0.0f;
    int n = 0;
    for (int dy = 0; dy < 2; ++dy)
      for (int dx = 0; dx < 2; ++dx) {
        const int sx = 2 * x + dx, sy = 2 * y + dy;
        if (sx >= in.width || sy >= in.height) continue;
        sum += in(sx, sy);
        ++n;
      }
    out(x, y) = sum / float(n);
  }
};

/// Intensity and its gradient per pixel (I, dI/du, dI/dv): Sobel, normalised to intensity per
/// pixel. Border pixels get a zero gradient (the photometric kernel never samples them).
struct IntensityGradientKernel {
  ImageView<const float> in;
  ImageView<Vec3f> out;

  RASM_HD_INLINE void operator()(int x, int y) const {
    const float c = in(x, y);
    if (x == 0 || y == 0 || x + 1 >= in.width || y + 1 >= in.height) {
      out(x, y) = Vec3f(c, 0.0f, 0.0f);
      return;
    }
    const float a = in(x - 1, y - 1), b = in(x, y - 1), d = in(x + 1, y - 1);
    const float e = in(x - 1, y), f = in(x + 1, y);
    const float g = in(x - 1, y + 1), h = in(x, y + 1), k = in(x + 1, y + 1);
    const float gx = ((d + 2.0f * f + k) - (a + 2.0f * e + g)) * 0.125f;
    const float gy = ((g + 2.0f * h + k) - (a + 2.0f * b + d)) * 0.125f;
    out(x, y) = Vec3f(c, gx, gy);
  }
};

/// Photometric residuals and Jacobians (see above) of the model pixels of one level, reduced
/// into an IcpAccumulator like IcpReduceKernel (depth = the model point's depth in the frame).
struct PhotometricReduceKernel {
  ImageView<const Vec3f> model_vertex;     ///< world frame, this level
  ImageView<const float> model_intensity;  ///< this level, NaN = none
  ImageView<const Vec3f> frame_igrad;      ///< (I, dI/du, dI/dv) of the frame, this level
  ImageView<const float> frame_depth_m;    ///< this level, 0 = invalid (occlusion test)
  PinholeF K_frame;                        ///< intrinsics of the frame at this level
  RigidF T_cam_world;                      ///< inverse of the current estimate
  RigidF T_world_cam;                      ///< current estimate (its rotation maps a to b)
  Vec3f pivot_world = Vec3f::Zero();       ///< c: centre of the rotation increment
  /// The warped point must lie within this distance (along the ray) of the frame's depth there:
  /// model points occluded in (or missing from) the frame are skipped.
  float max_depth_diff_m = 0.05f;
  float min_gradient = 0.0f;  ///< skip samples with |grad I_f| below (intensity per pixel)
  float huber_delta = 0.0f;   ///< Huber threshold on the intensity residual, 0 = none
  int stride = 1;             ///< every stride-th model pixel in x and y

  static constexpr int kSegment = 64;
  RASM_HD_INLINE int rows() const { return (model_vertex.height + stride - 1) / stride; }
  RASM_HD_INLINE int cols() const { return (model_vertex.width + stride - 1) / stride; }
  RASM_HD_INLINE int segmentsPerRow() const { return (cols() + kSegment - 1) / kSegment; }
  RASM_HD_INLINE int items() const { return rows() * segmentsPerRow(); }

  RASM_HD_INLINE int pixel(int x, int y, float J[6], float& r, float& w, float& depth) const {
    const Vec3f q = model_vertex(x, y);
    const float im = model_intensity(x, y);
    if (!(q.x() == q.x()) || !(im == im)) return kIcpInvalid;
    const Vec3f p = T_cam_world.apply(q);
    if (!(p.z() > 0.0f)) return kIcpRejected;
    const float iz = 1.0f / p.z();
    const float u = K_frame.fx * p.x() * iz + K_frame.cx;
    const float v = K_frame.fy * p.y() * iz + K_frame.cy;
    // Bilinear taps (u0, v0) .. (u0 + 1, v0 + 1), all inside the gradient image's interior.
    if (!(u >= 1.0f && v >= 1.0f && u < float(frame_igrad.width - 2) &&
          v < float(frame_igrad.height - 2)))
      return kIcpRejected;
    const float zf = frame_depth_m(int(u + 0.5f), int(v + 0.5f));
    if (!(zf > 0.0f) || fabsf(zf - p.z()) > max_depth_diff_m) return kIcpRejected;
    const int u0 = int(u), v0 = int(v);
    const float fu = u - float(u0), fv = v - float(v0);
    const Vec3f s =
        (1.0f - fv) * ((1.0f - fu) * frame_igrad(u0, v0) + fu * frame_igrad(u0 + 1, v0)) +
        fv * ((1.0f - fu) * frame_igrad(u0, v0 + 1) + fu * frame_igrad(u0 + 1, v0 + 1));
    const float gx = s.y(), gy = s.z();
    if (gx * gx + gy * gy < min_gradient * min_gradient) return kIcpRejected;
    r = s.x() - im;
    // a = dpi/dp^T grad I (camera frame), b = R a (world frame).
    const float ax = gx * K_frame.fx * iz, ay = gy * K_frame.fy * iz;
    const float az = -(ax * p.x() + ay * p.y()) * iz;
    const float* m = T_world_cam.m;
    const Vec3f b(m[0] * ax + m[1] * ay + m[2] * az, m[4] * ax + m[5] * ay + m[6] * az,
                  m[8] * ax + m[9] * ay + m[10] * az);
    const Vec3f c = b.cross(q - pivot_world);
    J[0] = -b.x();
    J[1] = -b.y();
    J[2] = -b.z();
    J[3] = c.x();
    J[4] = c.y();
    J[5] = c.z();
    const float ar = fabsf(r);
    w = (huber_delta > 0.0f && ar > huber_delta) ? huber_delta / ar : 1.0f;
    depth = p.z();
    return kIcpInlier;
  }

  void operator()(int i, IcpAccumulator& acc) const { reduceRowSegment<kSegment>(*this, i, acc); }
};

}  // namespace rasm::tracking::kernels
