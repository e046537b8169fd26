#pragma once
// Plain value types shared by kernels on both backends.

#include <Eigen/Core>
#include <Eigen/Geometry>  // cross()
#include <cstdint>

#include "rasm/compute/Platform.h"

namespace rasm {

using Vec2f = Eigen::Vector2f;
using Vec3f = Eigen::Vector3f;
using Vec4f = Eigen::Vector4f;
using Mat3f = Eigen::Matrix3f;
using Mat4f = Eigen::Matrix4f;

/// 8-bit colour in OpenCV / mrpt::img::CImage channel order (B, G, R).
struct Bgr8 {
  std::uint8_t b = 0, g = 0, r = 0;
};

/// Rigid transform as a plain 3x4 row-major [R | t] usable in device code (T_a_b maps b into a).
struct RigidF {
  float m[12] = {1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0};

  RASM_HD_INLINE Vec3f apply(const Vec3f& p) const {
    return Vec3f(m[0] * p.x() + m[1] * p.y() + m[2] * p.z() + m[3],
                 m[4] * p.x() + m[5] * p.y() + m[6] * p.z() + m[7],
                 m[8] * p.x() + m[9] * p.y() + m[10] * p.z() + m[11]);
  }
  RASM_HD_INLINE Vec3f rotate(const Vec3f& v) const {
    return Vec3f(m[0] * v.x() + m[1] * v.y() + m[2] * v.z(),
                 m[4] * v.x() + m[5] * v.y() + m[6] * v.z(),
                 m[8] * v.x() + m[9] * v.y() + m[10] * v.z());
  }
  RASM_HD_INLINE Vec3f translation() const { return Vec3f(m[3], m[7], m[11]); }

  static RigidF fromMatrix(const Eigen::Matrix4f& T) {
    RigidF r;
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 4; ++j) r.m[i * 4 + j] = T(i, j);
    return r;
  }
  Eigen::Matrix4f toMatrix() const {
    Eigen::Matrix4f T = Eigen::Matrix4f::Identity();
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 4; ++j) T(i, j) = m[i * 4 + j];
    return T;
  }
};

/// Pinhole intrinsics as plain data for kernels (see rasm::CameraIntrinsics for the full class).
struct PinholeF {
  float fx = 0, fy = 0, cx = 0, cy = 0;
  int width = 0, height = 0;

  /// u = pi(p) (II-A): pixel coordinates of a camera-frame point (z > 0 assumed).
  RASM_HD_INLINE Vec2f project(const Vec3f& p) const {
    return Vec2f(fx * p.x() / p.z() + cx, fy * p.y() / p.z() + cy);
  }
  /// p = D(u) K^-1 u^H (II-A).
  RASM_HD_INLINE Vec3f backProject(float u, float v, float depth_m) const {
    return Vec3f((u - cx) / fx * depth_m, (v - cy) / fy * depth_m, depth_m);
  }
};

}  // namespace rasm
