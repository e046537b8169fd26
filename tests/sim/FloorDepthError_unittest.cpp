// The simulated sensor's depth error on a floor seen by the robot's camera, against range and
// incidence angle, compared with the published Kinect v1 models: Nguyen, Izadi & Lovell 2012
// (axial sigma_z(z, theta), fitted to the residuals of planes at known angles) and the disparity
// quantization of Khoshelham & Elberink 2012 (depth step z^2 / (f b) / 8). A real Kinect's depth
// on a smooth plane is unbiased to well under its noise; its errors are the axial noise and the
// quantization. The table this prints (one row per 0.5 m of range) is in docs/sim.md "Depth error
// on a floor".
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <vector>

#include "rasm/sim/CameraPoses.h"
#include "rasm/sim/RayScene.h"
#include "rasm/sim/RgbdSensor.h"
#include "rasm/sim/World.h"

using namespace rasm;
using namespace rasm::sim;

namespace {

/// Per range bin: the measured depth minus the true depth along the optical axis.
struct RangeBin {
  double z_lo_m = 0, z_hi_m = 0;
  long n = 0;
  double sum_err_m = 0, sum_err2_m2 = 0;
  double sum_theta_rad = 0;
  double sum_expected_var_m2 = 0;  ///< Nguyen sigma_z^2 + quantization step^2 / 12
  double mean() const { return sum_err_m / double(n); }
  double sd() const { return std::sqrt(sum_err2_m2 / double(n) - mean() * mean()); }
  double expectedSd() const { return std::sqrt(sum_expected_var_m2 / double(n)); }
  double meanThetaDeg() const { return sum_theta_rad / double(n) * 180.0 / M_PI; }
};

/// Renders `frames` frames of an infinite floor (z = 0) from the robot's camera mount (0.55 m,
/// pitched 10 deg down, 640x480 Kinect preset) and bins every measured floor pixel by its true
/// depth, 0.5 m per bin from 0.5 to 4.5 m.
std::vector<RangeBin> floorDepthError(const TSensorParams& p, int frames) {
  const World w = loadWorldFromString(
      "objects:\n  - {id: 1, class: floor, primitive: box, size: [80, 80, 0.2], position: [0, 0, "
      "-0.1]}\n",
      "floor");
  const RayScene scene(w);
  const RgbdSensor sensor(scene, p);
  const DepthModelParams model = p.depthModel();
  const Eigen::Isometry3d T_world_cam =
      cameraPoseFromHeading(Eigen::Vector3d(0, 0, 0.55), 0.0, -10.0);
  const Eigen::Vector3d up_cam = T_world_cam.linear().transpose() * Eigen::Vector3d::UnitZ();
  std::vector<RangeBin> bins;
  for (double z = 0.5; z < 4.49; z += 0.5) bins.push_back({z, z + 0.5});
  for (int k = 0; k < frames; ++k) {
    const RgbdFrame f = sensor.render(T_world_cam, 100 + k, k);
    const CameraIntrinsics& K = f.intrinsics;
    for (int y = 0; y < f.height(); ++y)
      for (int x = 0; x < f.width(); ++x) {
        const float zm = f.depth_m(x, y);
        if (!(zm > 0.f)) continue;
        const Eigen::Vector3d ray((x - K.cx) / K.fx, (y - K.cy) / K.fy, 1.0);  // z component 1
        const double down = -ray.dot(up_cam);
        if (down <= 1e-6) continue;
        const double z_true = 0.55 / down;  // depth along the optical axis of the floor hit
        const double theta = std::acos(std::min(1.0, down / ray.norm()));
        const int k = int(std::floor((z_true - 0.5) / 0.5));
        if (k < 0 || k >= int(bins.size())) continue;
        RangeBin& b = bins[std::size_t(k)];
        const double e = zm - z_true;
        const double s = axialSigma(model, float(z_true), float(theta));
        const double q = quantizationStep(model, float(z_true));
        ++b.n;
        b.sum_err_m += e;
        b.sum_err2_m2 += e * e;
        b.sum_theta_rad += theta;
        b.sum_expected_var_m2 += s * s + q * q / 12.0;
      }
  }
  return bins;
}

void printTable(const std::vector<RangeBin>& bins) {
  std::printf("range_m  pixels  incidence_deg  bias_mm  sd_mm  expected_sd_mm  sd/expected\n");
  for (const RangeBin& b : bins)
    if (b.n > 0)
      std::printf("%.1f-%.1f  %6ld  %13.1f  %7.2f  %5.2f  %14.2f  %11.3f\n", b.z_lo_m, b.z_hi_m,
                  b.n, b.meanThetaDeg(), b.mean() * 1e3, b.sd() * 1e3, b.expectedSd() * 1e3,
                  b.sd() / b.expectedSd());
}

}  // namespace

TEST(FloorDepthError, IsUnbiasedWithTheNoiseOfTheNguyenModelAtEveryRange) {
  TSensorParams p;      // the shipped model: Kinect v1 preset, every noise term and quantization on
  p.dropouts = false;   // every floor pixel, also the grazing ones
  p.max_depth_m = 6.0;  // no bin cut by the range limit (it would bias the last one)
  const std::vector<RangeBin> bins = floorDepthError(p, 16);
  printTable(bins);
  int checked = 0;
  for (const RangeBin& b : bins) {
    if (b.n < 2000) continue;  // the bins the floor fills
    ++checked;
    // The spread is the axial noise plus the quantization, as Nguyen et al. fitted it on planes
    // at these angles; the tolerance is the sampling error of sd over >= 2000 correlated pixels
    // with room for the Gaussian's tail clipped by the disparity grid.
    EXPECT_NEAR(b.sd() / b.expectedSd(), 1.0, 0.1) << b.z_lo_m << "-" << b.z_hi_m << " m";
    // No bias: the mean error is within 4 standard errors of 0 (the pixels' noise is drawn
    // independently; 0.1-0.4 mm here, where lateral offsets on the smooth floor gave +1 mm at
    // 3.5-4 m and nothing near the camera, a range-dependent bias that tilts a fitted floor).
    const double se = b.sd() / std::sqrt(double(b.n));
    EXPECT_LT(std::abs(b.mean()), 4.0 * se) << b.z_lo_m << "-" << b.z_hi_m << " m";
  }
  EXPECT_GE(checked, 6) << "the floor should fill the bins from 1 to 4.5 m";
}
