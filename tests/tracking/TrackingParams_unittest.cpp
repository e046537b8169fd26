// [tracking] INI section: defaults, strict loading, range checks.
#include <gtest/gtest.h>
#include <mrpt/config/CConfigFileMemory.h>

#include "rasm/core/Error.h"
#include "rasm/core/Params.h"
#include "rasm/tracking/TrackingParams.h"

using namespace rasm;
using namespace rasm::tracking;

namespace {
TTrackingParams load(const std::string& ini) {
  mrpt::config::CConfigFileMemory cfg(ini);
  TTrackingParams p;
  loadParamsStrict(cfg, "tracking", p, "test.ini");
  return p;
}
std::string errorOf(const std::string& ini) {
  try {
    load(ini);
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}
}  // namespace

TEST(TrackingParams, DefaultsAreKinectFusionSchedule) {
  const TTrackingParams p;
  EXPECT_EQ(p.numLevels(), 3);
  EXPECT_EQ(p.iterations[0], 10);
  EXPECT_EQ(p.iterations[1], 5);
  EXPECT_EQ(p.iterations[2], 4);
  EXPECT_EQ(p.motion_model, MotionModel::ConstantVelocity);
  EXPECT_NO_THROW(p.validate());
}

TEST(TrackingParams, LoadsAndRoundTrips) {
  const TTrackingParams p = load(
      "[tracking]\nnum_levels = 2\niterations_level0 = 7\nmax_dist_m_level1 = 0.2\n"
      "motion_model = previous_pose\nhuber_delta_m = 0.01\nlevel0_pixel_stride = 1\nuse_cuda = "
      "false\n");
  EXPECT_EQ(p.num_levels, 2);
  EXPECT_EQ(p.iterations[0], 7);
  EXPECT_EQ(p.iterations[1], 5);  // default kept
  EXPECT_DOUBLE_EQ(p.max_dist_m[1], 0.2);
  EXPECT_EQ(p.motion_model, MotionModel::PreviousPose);
  EXPECT_DOUBLE_EQ(p.huber_delta_m, 0.01);
  EXPECT_EQ(p.level0_pixel_stride, 1);

  mrpt::config::CConfigFileMemory saved;
  p.saveToConfigFile(saved, "tracking");
  TTrackingParams q;
  loadParamsStrict(saved, "tracking", q, "saved");
  EXPECT_EQ(q.num_levels, 2);
  EXPECT_EQ(q.iterations[0], 7);
  EXPECT_EQ(q.motion_model, MotionModel::PreviousPose);
  EXPECT_DOUBLE_EQ(q.max_dist_m[1], 0.2);
}

TEST(TrackingParams, LoadsWeightingAndPhotometricKeys) {
  const TTrackingParams p = load(
      "[tracking]\ndepth_noise_weighting = false\nmodel_min_confidence = 7\nconfidence_full = 12\n"
      "photometric_weight = 0.01\nphotometric_huber = 0.02\nphotometric_min_gradient = 0.005\n");
  EXPECT_FALSE(p.depth_noise_weighting);
  EXPECT_DOUBLE_EQ(p.model_min_confidence, 7.0);
  EXPECT_DOUBLE_EQ(p.confidence_full, 12.0);
  EXPECT_DOUBLE_EQ(p.photometric_weight, 0.01);
  EXPECT_DOUBLE_EQ(p.photometric_huber, 0.02);
  EXPECT_DOUBLE_EQ(p.photometric_min_gradient, 0.005);
  mrpt::config::CConfigFileMemory saved;
  p.saveToConfigFile(saved, "tracking");
  TTrackingParams q;
  loadParamsStrict(saved, "tracking", q, "saved");
  EXPECT_FALSE(q.depth_noise_weighting);
  EXPECT_DOUBLE_EQ(q.model_min_confidence, 7.0);
  EXPECT_DOUBLE_EQ(q.photometric_weight, 0.01);

  const std::string e = errorOf("[tracking]\nphotometric_weight = -1\n");
  EXPECT_NE(e.find("photometric_weight"), std::string::npos) << e;
}

TEST(TrackingParams, RejectsBadKeysAndValues) {
  std::string e = errorOf("[tracking]\niterations = 10 5 4\n");
  EXPECT_NE(e.find("iterations"), std::string::npos) << e;
  EXPECT_NE(e.find("test.ini"), std::string::npos) << e;
  e = errorOf("[tracking]\nmotion_model = kalman\n");
  EXPECT_NE(e.find("motion_model"), std::string::npos) << e;
  e = errorOf("[tracking]\nnum_levels = 4\n");
  EXPECT_NE(e.find("num_levels"), std::string::npos) << e;
  e = errorOf("[tracking]\niterations_level0 = 0\n");
  EXPECT_NE(e.find("iterations_level0"), std::string::npos) << e;
  e = errorOf("[tracking]\nmax_normal_angle_deg_level0 = 200\n");
  EXPECT_NE(e.find("max_normal_angle_deg_level0"), std::string::npos) << e;
}
