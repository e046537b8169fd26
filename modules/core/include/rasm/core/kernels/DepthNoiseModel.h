#pragma once
// Axial depth noise of a Kinect v1 class structured-light sensor (Nguyen, Izadi & Lovell,
// "Modeling Kinect Sensor Noise for Improved 3D Reconstruction and Tracking", 3DIMPVT 2012,
// eq. 3 with their fitted constants), fitted to the residuals of planes at known distances and
// angles, so it is all the noise a smooth surface shows:
//   sigma_z(z, theta) = 0.0012 + 0.0019 (z - 0.4)^2 + 0.0001 / sqrt(z) * theta^2 / (pi/2 - theta)^2
// z the depth in metres, theta the incidence angle between the surface normal and the viewing ray.
// The one home of the formula: the simulator draws its depth noise from it, the tracker weights its
// residuals by it. Plain header (any backend).

#include <cmath>

#include "rasm/compute/ImageView.h"

namespace rasm::sensor {

/// acos for x in [0, 1] (Abramowitz & Stegun 4.4.45, |error| <= 7e-5 rad): the incidence angle
/// only feeds the noise model, so libm's exact acos is not worth its cost per pixel.
RASM_HD_INLINE float fastAcos01(float x) {
  x = x < 0.f ? 0.f : (x > 1.f ? 1.f : x);
  return std::sqrt(1.f - x) * (1.5707288f + x * (-0.2121144f + x * (0.0742610f - 0.0187293f * x)));
}

/// The angle factor theta / (pi/2 - theta) of Nguyen et al.'s axial and lateral formulas (theta
/// clamped to 1.5 rad = 86 deg, where the factor is 21).
RASM_HD_INLINE float incidenceAngleFactor(float theta_rad) {
  const float th = theta_rad < 1.5f ? theta_rad : 1.5f;
  return th / (1.57079633f - th);
}

/// The constants of sigma_z; the defaults are Nguyen et al.'s fit for the Kinect v1.
struct AxialNoiseModel {
  float sigma0_m = 0.0012f;     ///< constant term
  float sigma_quad = 0.0019f;   ///< coefficient of (z - z0)^2 (1/m)
  float z0_m = 0.4f;            ///< z0 of the quadratic term
  float sigma_angle = 0.0001f;  ///< coefficient of the angle term (m^1.5)

  /// sigma_z (m) at depth z_m for the angle factor g = incidenceAngleFactor(theta).
  RASM_HD_INLINE float sigmaG(float z_m, float g) const {
    const float dz = z_m - z0_m;
    return sigma0_m + sigma_quad * dz * dz + sigma_angle / std::sqrt(z_m) * g * g;
  }
  /// sigma_z (m) at depth z_m and incidence theta_rad.
  RASM_HD_INLINE float sigma(float z_m, float theta_rad) const {
    return sigmaG(z_m, incidenceAngleFactor(theta_rad));
  }
};

}  // namespace rasm::sensor
