// Simulated RGB-D sensor against analytic geometry: exact depth of a plane with noise off, noise
// statistics against the Nguyen et al. model, disparity quantization, range / grazing / projector
// shadow dropouts, instance and class images against projected areas, determinism.
#include "rasm/sim/RgbdSensor.h"

#include <gtest/gtest.h>
#include <mrpt/config/CConfigFileMemory.h>
#include <omp.h>

#include <cmath>
#include <cstdio>
#include <cstring>
#include <tuple>

#include "rasm/core/Error.h"
#include "rasm/core/Params.h"
#include "rasm/models/ClassVocabulary.h"
#include "rasm/sim/CameraPoses.h"
#include "rasm/sim/RayScene.h"
#include "rasm/sim/SimulatedDetector.h"
#include "rasm/sim/SimulatedDiffDriveRobot.h"
#include "rasm/sim/World.h"
#include "rasm/sim/kernels/CounterRng.h"

using namespace rasm;
using namespace rasm::sim;
using namespace rasm::models;

namespace {

/// A wall (plane x = wall_x, facing -x) filling the view of a camera at the origin looking along
/// +x (world z up), optionally with a box whose front face is at x = box_x.
World planeWorld(double wall_x, const std::string& extra = "") {
  const std::string yaml =
      "objects:\n  - {id: 1, class: wall, primitive: box, size: [0.2, 60, 60], position: [" +
      std::to_string(wall_x + 0.1) + ", 0, 0], colour: [200, 200, 200]}\n" + extra;
  return loadWorldFromString(yaml, "test");
}

const Eigen::Isometry3d kCamAtOrigin = cameraPoseFromHeading(Eigen::Vector3d::Zero(), 0.0, 0.0);

TSensorParams exactParams() {
  TSensorParams p;
  p.noise = false;
  p.dropouts = false;
  return p;
}

bool sameImage(const Image<float>& a, const Image<float>& b) {
  if (!a.sameSize(b)) return false;
  for (int y = 0; y < a.height(); ++y)
    if (std::memcmp(a.row(y), b.row(y), sizeof(float) * a.width()) != 0) return false;
  return true;
}

/// Incidence angle of pixel (x, y) on the plane x = const (normal -x world = -z camera).
double planeIncidence(const CameraIntrinsics& K, int x, int y) {
  const Eigen::Vector3d d((x - K.cx) / K.fx, (y - K.cy) / K.fy, 1.0);
  return std::acos(1.0 / d.norm());
}

}  // namespace

TEST(DepthModel, NguyenFormulasAndQuantizationStep) {
  DepthModelParams p;
  EXPECT_NEAR(axialSigma(p, 1.0f, 0.f), 0.0012 + 0.0019 * 0.36, 1e-7);
  EXPECT_NEAR(axialSigma(p, 3.0f, 0.f), 0.0012 + 0.0019 * 2.6 * 2.6, 1e-6);
  const double th = 60 * M_PI / 180;
  EXPECT_NEAR(
      axialSigma(p, 2.0f, float(th)),
      0.0012 + 0.0019 * 1.6 * 1.6 + 0.0001 / std::sqrt(2.0) * std::pow(th / (M_PI / 2 - th), 2),
      1e-6);
  EXPECT_NEAR(lateralSigmaPx(p, 0.f), 0.8, 1e-6);
  // Kinect v1: step z^2 / (f b) / 8 with f = 580, b = 0.075.
  EXPECT_NEAR(quantizationStep(p, 2.0f), 4.0 / (580 * 0.075) / 8, 1e-6);
  // Quantized depths are f b / (k / 8) for integer k, and within half a step of the input.
  for (float z = 0.5f; z < 4.5f; z += 0.0137f) {
    const float q = quantizeDepth(p, z);
    const double k = 8.0 * 580 * 0.075 / q;
    EXPECT_NEAR(k, std::round(k), 1e-3);
    EXPECT_LE(std::abs(q - z), 0.5 * quantizationStep(p, z) * 1.02 + 1e-6);
  }
  EXPECT_NEAR(fastAcos01(0.5f), std::acos(0.5), 1e-4);
  EXPECT_NEAR(fastAcos01(0.999f), std::acos(0.999), 1e-4);
}

TEST(DepthModel, CounterRngIsStandardNormal) {
  CounterRng rng{0x1234};
  double s = 0, s2 = 0;
  int within1 = 0;
  const int n = 200000;
  for (int i = 0; i < n; ++i) {
    float a, b;
    rng.gaussian2(std::uint32_t(i), 3, a, b);
    for (float g : {a, b}) {
      s += g;
      s2 += double(g) * g;
      within1 += std::abs(g) < 1.f;
    }
  }
  const double mean = s / (2 * n), var = s2 / (2 * n) - mean * mean;
  EXPECT_NEAR(mean, 0.0, 4.0 / std::sqrt(2.0 * n));
  EXPECT_NEAR(var, 1.0, 4.0 * std::sqrt(2.0 / (2 * n)));
  EXPECT_NEAR(within1 / (2.0 * n), 0.682689, 0.004);
  EXPECT_NEAR(fastLog(0.3f), std::log(0.3f), 3e-6);
}

TEST(RgbdSensor, PlaneDepthIsExactWithNoiseOff) {
  const RayScene scene(planeWorld(2.0));
  const RgbdSensor sensor(scene, exactParams());
  const RgbdFrame f = sensor.render(kCamAtOrigin);
  ASSERT_EQ(f.width(), 640);
  ASSERT_EQ(f.height(), 480);
  double max_err = 0;
  for (int y = 0; y < f.height(); ++y)
    for (int x = 0; x < f.width(); ++x)
      max_err = std::max(max_err, std::abs(double(f.depth_m(x, y)) - 2.0));
  EXPECT_LT(max_err, 1e-4);
  EXPECT_NO_THROW(f.validate("sim"));
  ASSERT_TRUE(f.gt_T_world_cam.has_value());
  EXPECT_TRUE(f.gt_T_world_cam->isApprox(kCamAtOrigin));
}

TEST(RgbdSensor, BoxDepthIsExactWithNoiseOffFromAnObliqueView) {
  // A box face seen at 30 degrees: depth of every pixel on it matches the ray-plane intersection.
  const RayScene scene(planeWorld(
      6.0,
      "  - {id: 2, class: box, primitive: box, size: [0.5, 1.0, 1.0], position: [2.25, 0, 0]}\n"));
  TSensorParams p = exactParams();
  const RgbdSensor sensor(scene, p);
  const Eigen::Vector3d eye(0.0, -0.6, 0.1);
  const Eigen::Isometry3d T = cameraPoseFromHeading(eye, 20.0, -5.0);
  const RgbdFrame f = sensor.render(T);
  const CameraIntrinsics& K = f.intrinsics;
  int n = 0;
  for (int y = 0; y < f.height(); ++y)
    for (int x = 0; x < f.width(); ++x) {
      if (f.gt_instance(x, y) != 2) continue;
      const Eigen::Vector3d d_cam((x - K.cx) / K.fx, (y - K.cy) / K.fy, 1.0);
      const Eigen::Vector3d d = T.linear() * d_cam;
      const double t = (2.0 - eye.x()) / d.x();  // front face x = 2
      const Eigen::Vector3d hit = eye + t * d;
      if (std::abs(hit.y()) > 0.499 || std::abs(hit.z()) > 0.499) continue;  // side faces
      EXPECT_NEAR(f.depth_m(x, y), t, 1e-4) << x << "," << y;
      ++n;
    }
  EXPECT_GT(n, 10000);
}

TEST(RgbdSensor, AxialNoiseMatchesTheModel) {
  const RayScene scene(planeWorld(2.0));
  TSensorParams p;
  p.disparity_subpixel =
      0;  // axial + lateral noise only (a fronto-parallel plane hides lateral noise)
  const RgbdSensor sensor(scene, p);
  const RgbdFrame f = sensor.render(kCamAtOrigin, 7, 0);
  const DepthModelParams model = p.depthModel();
  double sum = 0, sum2 = 0, var_model = 0;
  long n = 0;
  for (int y = 0; y < f.height(); ++y)
    for (int x = 0; x < f.width(); ++x) {
      ASSERT_GT(f.depth_m(x, y), 0.f);
      const double e = f.depth_m(x, y) - 2.0;
      sum += e;
      sum2 += e * e;
      const double s = axialSigma(model, 2.0f, float(planeIncidence(f.intrinsics, x, y)));
      var_model += s * s;
      ++n;
    }
  const double mean = sum / n, sd = std::sqrt(sum2 / n - mean * mean),
               sd_model = std::sqrt(var_model / n);
  EXPECT_NEAR(sd_model, 0.0012 + 0.0019 * 1.6 * 1.6, 1e-4);  // angle term is small at 2 m
  EXPECT_LT(std::abs(mean), 3.0 * sd_model / std::sqrt(double(n)));
  EXPECT_NEAR(sd / sd_model, 1.0, 0.01);  // relative standard error of sd: 1/sqrt(2n) = 0.13 %
}

TEST(RgbdSensor, DisparityQuantizationPutsDepthOnTheGrid) {
  const RayScene scene(planeWorld(2.0));
  TSensorParams p;  // Kinect v1 defaults: 1/8 px disparity at f = 580, b = 0.075
  const RgbdSensor sensor(scene, p);
  const RgbdFrame f = sensor.render(kCamAtOrigin, 3, 0);
  const double fb8 = 8.0 * 580.0 * 0.075;
  const double sigma = 0.0012 + 0.0019 * 1.6 * 1.6, step = 4.0 / (580 * 0.075) / 8;
  double sum = 0, sum2 = 0;
  long n = 0;
  for (int y = 0; y < f.height(); y += 2)
    for (int x = 0; x < f.width(); x += 2) {
      const double z = f.depth_m(x, y);
      ASSERT_GT(z, 0.0);
      const double k = fb8 / z;
      ASSERT_NEAR(k, std::round(k), 2e-3) << "depth " << z << " is not on the disparity grid";
      sum += z - 2.0;
      sum2 += (z - 2.0) * (z - 2.0);
      ++n;
    }
  const double mean = sum / n, sd = std::sqrt(sum2 / n - mean * mean);
  // Gaussian noise plus uniform quantization error (Sheppard): sqrt(sigma^2 + step^2 / 12).
  EXPECT_NEAR(sd, std::sqrt(sigma * sigma + step * step / 12), 0.05 * sigma);
}

TEST(RgbdSensor, RangeLimits) {
  TSensorParams p = exactParams();
  for (double wall : {0.3, 5.0}) {
    const RayScene scene(planeWorld(wall));
    const RgbdFrame f = RgbdSensor(scene, p).render(kCamAtOrigin);
    for (int y = 0; y < f.height(); y += 8)
      for (int x = 0; x < f.width(); x += 8) ASSERT_EQ(f.depth_m(x, y), 0.f) << "wall at " << wall;
    // Labels and colour are ground truth / passive: still there.
    EXPECT_EQ(f.gt_instance(320, 240), 1);
  }
}

/// Lateral noise alone (axial noise and quantization off) at one resolution, a 1 m box 1.5 m in
/// front of a wall 3 m away, both seen 15 deg off their normal (depth changes along each row, as
/// on any slanted surface): returns the pixels of the box's rows that measured the other
/// surface's depth against the number the model predicts, and counts the pixels away from any
/// edge whose depth is not exact.
struct EdgeFlips {
  double measured = 0, predicted = 0;
  long interior = 0, interior_not_exact = 0;
};
EdgeFlips lateralEdgeFlips(int width, int height, double f) {
  const World w = planeWorld(
      3.0,
      "  - {id: 2, class: box, primitive: box, size: [0.2, 1.0, 1.0], position: [1.6, 0, 0]}\n");
  const RayScene scene(w);
  TSensorParams p;
  p.dropouts = false;
  p.disparity_subpixel = 0;
  p.axial_sigma0_m = p.axial_sigma_quad = p.axial_sigma_angle = 0;
  p.width = width;
  p.height = height;
  p.fx = p.fy = f;
  p.cx = (width - 1) / 2.0;
  p.cy = (height - 1) / 2.0;
  TSensorParams exact = p;
  exact.noise = false;
  const Eigen::Isometry3d T_world_cam = cameraPoseFromHeading(Eigen::Vector3d::Zero(), 15.0, 0.0);
  const RgbdFrame truth = RgbdSensor(scene, exact).render(T_world_cam);
  const DepthModelParams model = p.depthModel();
  EdgeFlips out;
  for (int seed = 1; seed <= 24; ++seed) {
    const RgbdFrame fr = RgbdSensor(scene, p).render(T_world_cam, std::uint64_t(seed));
    // Rows well inside the box's height, so that vertical offsets stay on the same surfaces.
    for (int y = height / 2 - height / 10; y <= height / 2 + height / 10; ++y)
      for (int x = 0; x < width; ++x) {
        const float zt = truth.depth_m(x, y);
        int k = 1;  // column distance to the nearest pixel of the other surface
        while (k < width && !((x - k >= 0 && std::abs(truth.depth_m(x - k, y) - zt) > 0.5f) ||
                              (x + k < width && std::abs(truth.depth_m(x + k, y) - zt) > 0.5f)))
          ++k;
        const bool other = std::abs(fr.depth_m(x, y) - zt) > 0.5f;
        if (k > 6) {
          ++out.interior;
          if (std::abs(fr.depth_m(x, y) - zt) > 1e-4f * zt) ++out.interior_not_exact;
          continue;
        }
        out.measured += other ? 1 : 0;
        // The nearest sample column is the other surface when the offset exceeds k - 0.5 px.
        const CameraIntrinsics& K = fr.intrinsics;
        const Eigen::Vector3d ray =
            T_world_cam.linear() * Eigen::Vector3d((x - K.cx) / K.fx, (y - K.cy) / K.fy, 1.0);
        const double theta = std::acos(std::abs(ray.x()) / ray.norm());  // both faces: normal -x
        const double sl = lateralSigmaPx(model, float(theta));
        out.predicted += 0.5 * std::erfc((k - 0.5) / sl / std::sqrt(2.0));
      }
  }
  return out;
}

TEST(RgbdSensor, LateralNoiseMovesDepthEdgesByTheModelsSigmaAndLeavesPlanesExact) {
  // sigma_L is in pixels of the preset (Kinect 640x480, fx 525); a 320x240 render at fx 262.5 has
  // pixels twice as wide, so the same angular noise is half the pixels: fewer pixels flip at each
  // edge, as many as the Gaussian with the scaled sigma predicts.
  for (const auto& [w, h, f] : {std::tuple{640, 480, 525.0}, std::tuple{320, 240, 262.5}}) {
    const EdgeFlips e = lateralEdgeFlips(w, h, f);
    ASSERT_GT(e.predicted, 100.0) << w << "x" << h;
    std::printf("%dx%d: %.0f pixels flipped, %.0f predicted; %ld interior\n", w, h, e.measured,
                e.predicted, e.interior);
    // The flips are Bernoulli draws: 250-1400 of them have a standard error of 3-6%, so 15% is
    // 2.5-5 standard errors; unscaled sigma_L at 320x240 flips 5x the prediction, none without it.
    EXPECT_NEAR(e.measured / e.predicted, 1.0, 0.15)
        << w << "x" << h << ": " << e.measured << " pixels flipped, " << e.predicted
        << " predicted";
    // Away from the edges the lateral offset leaves the wall and the box face exact.
    EXPECT_GT(e.interior, 1000);
    EXPECT_EQ(e.interior_not_exact, 0) << w << "x" << h;
  }
}

TEST(RgbdSensor, GrazingAnglesAreMissing) {
  // A floor seen from 0.5 m with a horizontal camera: rows near the horizon meet it at grazing
  // angles. Incidence theta = atan(1 / s) for the ray slope s = (v - cy) / fy in the centre column.
  const World w = loadWorldFromString(
      "objects:\n  - {id: 1, class: floor, primitive: box, size: [60, 60, 0.2], position: [0, 0, "
      "-0.1]}\n",
      "floor");
  const RayScene scene(w);
  TSensorParams p = exactParams();
  p.dropouts = true;
  p.max_depth_m = 50;
  const RgbdSensor sensor(scene, p);
  const RgbdFrame f = sensor.render(cameraPoseFromHeading(Eigen::Vector3d(0, 0, 0.5), 0.0, 0.0));
  const CameraIntrinsics& K = f.intrinsics;
  const int x = int(K.cx + 0.5);
  int checked_valid = 0, checked_missing = 0;
  for (int y = int(K.cy) + 2; y < f.height(); ++y) {
    const double s = (y - K.cy) / K.fy;
    const Eigen::Vector3d d((x - K.cx) / K.fx, s, 1.0);
    const double theta = std::acos(s / d.norm()) * 180 / M_PI;
    if (theta > 80.5) {
      EXPECT_EQ(f.depth_m(x, y), 0.f) << "row " << y << " theta " << theta;
      ++checked_missing;
    } else if (theta < 79.5) {
      EXPECT_NEAR(f.depth_m(x, y), 0.5 / s, 1e-3 * (0.5 / s)) << "row " << y << " theta " << theta;
      ++checked_valid;
    }
  }
  EXPECT_GT(checked_missing, 10);
  EXPECT_GT(checked_valid, 100);
}

TEST(RgbdSensor, ProjectorShadowBesideForegroundEdges) {
  // A 0.3 m wide pole 1.5 m in front of a wall 3 m away. The projector 7.5 cm to the right of the
  // camera cannot light a band of the wall left of the pole, fx b (1/1.5 - 1/3) = 13.1 px wide.
  const World w = planeWorld(
      3.0,
      "  - {id: 2, class: none, primitive: box, size: [0.2, 0.3, 4.0], position: [1.6, 0, 0]}\n");
  const RayScene scene(w);
  TSensorParams p = exactParams();
  p.dropouts = true;
  for (double offset : {0.075, -0.075}) {
    p.projector_offset_m = offset;
    const RgbdFrame f = RgbdSensor(scene, p).render(kCamAtOrigin);
    const int y = 240;
    // Pole columns in this row.
    int left = -1, right = -1;
    for (int x = 0; x < f.width(); ++x)
      if (f.gt_instance(x, y) == 2) {
        if (left < 0) left = x;
        right = x;
      }
    ASSERT_GT(left, 0);
    int missing_left = 0, missing_right = 0;
    for (int x = left - 1; x >= 0 && f.depth_m(x, y) == 0.f; --x) ++missing_left;
    for (int x = right + 1; x < f.width() && f.depth_m(x, y) == 0.f; ++x) ++missing_right;
    const double expected = 525.0 * 0.075 * (1.0 / 1.5 - 1.0 / 3.0);
    const int shadow = offset > 0 ? missing_left : missing_right;
    const int other = offset > 0 ? missing_right : missing_left;
    EXPECT_NEAR(shadow, expected, 1.5) << "offset " << offset;
    EXPECT_EQ(other, 0) << "offset " << offset;
    // The pole itself is lit.
    for (int x = left; x <= right; ++x) EXPECT_NEAR(f.depth_m(x, y), 1.5, 1e-4);
  }
}

TEST(RgbdSensor, InstanceAndClassImagesMatchTheGeometry) {
  // Box face 0.6 m wide and 0.4 m high, 2 m in front of the camera, facing it: it projects to a
  // 157.5 x 105 px rectangle; pixel centres inside it differ from its area by at most w + h.
  const World w = planeWorld(
      4.0,
      "  - {id: 2, class: cup, primitive: box, size: [0.2, 0.6, 0.4], position: [2.1, 0.05, "
      "0.03]}\n"
      "  - {id: 3, class: none, primitive: sphere, radius: 0.1, position: [1.5, -0.6, 0.0]}\n");
  const RayScene scene(w);
  const RgbdFrame f = RgbdSensor(scene, exactParams()).render(kCamAtOrigin);
  const double wpx = 525.0 * 0.6 / 2.0, hpx = 525.0 * 0.4 / 2.0;
  long box = 0, sphere = 0;
  for (int y = 0; y < f.height(); ++y)
    for (int x = 0; x < f.width(); ++x) {
      const int id = f.gt_instance(x, y);
      box += id == 2;
      sphere += id == 3;
      const int expected_class = id == 1   ? classIdFromName("wall")
                                 : id == 2 ? classIdFromName("cup")
                                           : 0;
      ASSERT_EQ(f.gt_class(x, y), expected_class) << x << "," << y;
    }
  EXPECT_NEAR(double(box), wpx * hpx, wpx + hpx);
  // A sphere (half-angle beta, sin beta = r / D) seen alpha off the optical axis projects to an
  // ellipse of area pi f^2 sin^2(beta) cos(beta) / (cos^2(alpha) - sin^2(beta))^(3/2). The
  // tessellated sphere is slightly smaller than the true one.
  const double D = std::hypot(1.5, 0.6), sb = 0.1 / D, cb = std::sqrt(1 - sb * sb), ca = 1.5 / D;
  const double ellipse = M_PI * 525.0 * 525.0 * sb * sb * cb / std::pow(ca * ca - sb * sb, 1.5);
  EXPECT_NEAR(double(sphere), ellipse, 0.03 * ellipse);
  EXPECT_LT(double(sphere), ellipse);
}

TEST(RgbdSensor, DeterministicBySeedWhateverTheThreadCount) {
  const World w = loadWorld("office");
  const RayScene scene(w);
  const RgbdSensor sensor(scene, TSensorParams());
  const Eigen::Isometry3d T =
      cameraPoseLookingAt(Eigen::Vector3d(6.5, 4.5, 1.6), Eigen::Vector3d(2, 1, 0.8));
  const int threads = omp_get_max_threads();
  omp_set_num_threads(1);
  const RgbdFrame a = sensor.render(T, 42, 5);
  omp_set_num_threads(std::max(2, threads));
  const RgbdFrame b = sensor.render(T, 42, 5);
  const RgbdFrame c = sensor.render(T, 43, 5);
  const RgbdFrame d = sensor.render(T, 42, 6);
  omp_set_num_threads(threads);
  EXPECT_TRUE(sameImage(a.depth_m, b.depth_m));
  EXPECT_FALSE(sameImage(a.depth_m, c.depth_m));
  EXPECT_FALSE(sameImage(a.depth_m, d.depth_m));
  for (int y = 0; y < a.height(); ++y) {
    ASSERT_EQ(std::memcmp(a.colour.row(y), b.colour.row(y), sizeof(Bgr8) * a.width()), 0);
    ASSERT_EQ(std::memcmp(a.gt_instance.row(y), b.gt_instance.row(y), 2 * a.width()), 0);
  }
  EXPECT_EQ(RgbdSensor::frameKey(42, 5), RgbdSensor::frameKey(42, 5));
  EXPECT_NE(RgbdSensor::frameKey(42, 5), RgbdSensor::frameKey(42, 6));
}

TEST(RgbdSensor, ColourIsTexturedAndShaded) {
  const World w = loadWorldFromString(
      "light: {direction: [0, 0, -1], ambient: 0.2, diffuse: 0.8}\n"
      "objects:\n"
      "  - {id: 1, class: floor, primitive: box, size: [20, 20, 0.2], position: [0, 0, -0.1], "
      "colour: [200, 200, 200],\n"
      "     texture: {pattern: checker, colour2: [50, 50, 50], period_m: 0.25}}\n"
      "  - {id: 2, class: wall, primitive: box, size: [0.2, 20, 20], position: [3.1, 0, 0], "
      "colour: [200, 200, 200]}\n",
      "tex");
  const RayScene scene(w);
  const RgbdFrame f =
      RgbdSensor(scene, exactParams()).render(cameraPoseFromHeading({0, 0, 1.0}, 0.0, -20.0));
  int bright = 0, dark = 0;
  for (int y = 0; y < f.height(); ++y)
    for (int x = 0; x < f.width(); ++x)
      if (f.gt_instance(x, y) == 1) {
        // Floor faces the light: albedo * (0.2 + 0.8) = albedo.
        const int g = f.colour(x, y).g;
        bright += g == 200;
        dark += g == 50;
      }
  EXPECT_GT(bright, 1000);
  EXPECT_GT(dark, 1000);
  // The wall is lit edge-on: ambient only, 0.2 * 200 = 40.
  EXPECT_EQ(f.colour(320, 40).g, 40);
  EXPECT_EQ(f.gt_instance(320, 40), 2);
}

TEST(SimParams, StrictIniLoadingOfTheThreeSections) {
  mrpt::config::CConfigFileMemory ini;
  ini.write("sim_sensor", "camera", "kinect_v2_depth");
  ini.write("sim_sensor", "noise", "false");
  ini.write("sim_robot", "camera_height_m", "0.8");
  ini.write("sim_detector", "detectable_classes", "cup,conference_phone");
  TSensorParams s;
  rasm::loadParamsStrict(ini, "sim_sensor", s, "test.ini");
  EXPECT_EQ(s.intrinsics().width, 512);
  EXPECT_FALSE(s.noise);
  EXPECT_TRUE(s.dropouts);  // untouched keys keep their defaults
  TRobotParams r;
  rasm::loadParamsStrict(ini, "sim_robot", r, "test.ini");
  EXPECT_DOUBLE_EQ(r.camera_height_m, 0.8);
  TDetectorParams d;
  rasm::loadParamsStrict(ini, "sim_detector", d, "test.ini");
  EXPECT_EQ(d.detectableClassIds().size(), 2u);
  // Unknown keys and bad values name the file, section and key.
  ini.write("sim_sensor", "noize", "false");
  try {
    TSensorParams bad;
    rasm::loadParamsStrict(ini, "sim_sensor", bad, "test.ini");
    FAIL();
  } catch (const rasm::InputError& e) {
    EXPECT_NE(std::string(e.what()).find("test.ini [sim_sensor] noize"), std::string::npos)
        << e.what();
  }
  mrpt::config::CConfigFileMemory ini2;
  ini2.write("sim_sensor", "camera", "kinect_v9");
  TSensorParams bad;
  EXPECT_THROW(rasm::loadParamsStrict(ini2, "sim_sensor", bad, "test.ini"), rasm::InputError);
  // Defaults survive a save / strict load round trip.
  mrpt::config::CConfigFileMemory saved;
  TSensorParams def;
  def.saveToConfigFile(saved, "sim_sensor");
  TSensorParams back;
  back.noise = false;
  rasm::loadParamsStrict(saved, "sim_sensor", back, "saved");
  EXPECT_TRUE(back.noise);
  EXPECT_DOUBLE_EQ(back.axial_sigma_quad, 0.0019);
}
