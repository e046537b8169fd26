// CSurfelMap::insertObservation(CObservation3DRangeScan): fusion at a given pose without tracking,
// through a CMultiMetricMap created from INI (the fusion module registers the inserter).

#include <gtest/gtest.h>
#include <mrpt/config/CConfigFileMemory.h>
#include <mrpt/maps/CMultiMetricMap.h>
#include <mrpt/obs/CObservation3DRangeScan.h>
#include <mrpt/obs/CRawlog.h>
#include <mrpt/poses/CPose3D.h>

#include <cmath>
#include <filesystem>

#include "SyntheticScene.h"
#include "rasm/core/Error.h"
#include "rasm/core/SE3.h"
#include "rasm/surfel_map/CSurfelMap.h"

using namespace rasm;

namespace {

mrpt::obs::CObservation3DRangeScan observationOf(const RgbdFrame& f) {
  mrpt::obs::CObservation3DRangeScan obs;
  obs.sensorLabel = "RGBD";
  obs.timestamp = mrpt::Clock::fromDouble(f.timestamp_s);
  obs.hasRangeImage = true;
  obs.range_is_depth = true;
  obs.rangeUnits = 0.001f;
  obs.rangeImage.resize(f.height(), f.width());
  for (int y = 0; y < f.height(); ++y)
    for (int x = 0; x < f.width(); ++x)
      obs.rangeImage(y, x) = std::uint16_t(std::lround(f.depth_m(x, y) * 1000.0f));
  obs.hasIntensityImage = true;
  obs.intensityImage = mrpt::img::CImage(f.width(), f.height(), mrpt::img::CH_RGB);
  for (int y = 0; y < f.height(); ++y)
    for (int x = 0; x < f.width(); ++x) {
      std::uint8_t* p = obs.intensityImage.ptr<std::uint8_t>(x, y);
      p[0] = f.colour(x, y).b;
      p[1] = f.colour(x, y).g;
      p[2] = f.colour(x, y).r;
    }
  f.intrinsics.toTCamera(obs.cameraParams);
  obs.cameraParamsIntensity = obs.cameraParams;
  obs.sensorPose = mrpt::poses::CPose3D();  // sensor at the robot origin
  return obs;
}

}  // namespace

TEST(CSurfelMapInsertion, ObservationFusedAtTheGivenPose) {
  const std::string ini = R"(
[MAP]
surfelMap_count = 1
[MAP_surfelMap_00_creationOpts]
n_classes = 2
[MAP_surfelMap_00_insertOpts]
max_depth_m = 6.0
stable_confidence = 3
)";
  mrpt::config::CConfigFileMemory cfg(ini);
  mrpt::maps::TSetOfMetricMapInitializers inits;
  inits.loadFromConfigFile(cfg, "MAP");
  mrpt::maps::CMultiMetricMap mm(inits);
  auto map = mm.mapByClass<maps::CSurfelMap>();
  ASSERT_TRUE(map);

  // Camera 0.5 m to the side and 0.2 m up, looking at the wall along world +z (optical frame).
  Eigen::Isometry3d T_world_cam = Eigen::Isometry3d::Identity();
  T_world_cam.translation() = Eigen::Vector3d(0.5, -0.2, 0.0);
  const CameraIntrinsics K(131.25, 131.25, 79.5, 59.5, 160, 120);
  fusiontest::Scene scene;
  const fusiontest::SyntheticFrame sf = fusiontest::renderScene(scene, K, T_world_cam, 50.0);
  const auto obs = observationOf(sf.frame);
  const mrpt::poses::CPose3D robot = mrptSensorPoseFromOptical(T_world_cam);
  for (int k = 0; k < 4; ++k) ASSERT_TRUE(mm.insertObservation(obs, robot));

  const maps::SurfelArrays a = map->arrays();
  ASSERT_GT(a.size, K.width * K.height / 2);
  int stable = 0;
  for (int i = 0; i < a.size; ++i) {
    ASSERT_NEAR(a.position(i).z(), 3.0f, 1e-3f);  // the wall, in the world frame
    ASSERT_NEAR(a.normal(i).z(), -1.0f, 1e-3f);
    stable += a.stable(i);
  }
  EXPECT_GT(stable, 0);  // stable_confidence = 3 from the INI took effect after 4 frames
  // The map is centred on the camera's x/y offset.
  Eigen::Vector3f mean = Eigen::Vector3f::Zero();
  for (int i = 0; i < a.size; ++i) mean += a.position(i);
  mean /= float(a.size);
  EXPECT_NEAR(mean.x(), 0.5f, 0.05f);
  EXPECT_NEAR(mean.y(), -0.2f, 0.05f);
}

TEST(CSurfelMapInsertion, LikelihoodPeaksAtTheTruePose) {
  const CameraIntrinsics K(131.25, 131.25, 79.5, 59.5, 160, 120);
  fusiontest::Scene scene;
  scene.boxes.push_back(
      {Eigen::Vector3d(-0.4, -0.3, 1.8), Eigen::Vector3d(0.3, 0.3, 2.2), Bgr8{0, 0, 200}});
  const auto sf = fusiontest::renderScene(scene, K, Eigen::Isometry3d::Identity(), 0.0);
  const auto obs = observationOf(sf.frame);
  maps::CSurfelMap map;
  const mrpt::poses::CPose3D truth = mrptSensorPoseFromOptical(Eigen::Isometry3d::Identity());
  ASSERT_TRUE(map.insertObservation(obs, truth));
  ASSERT_TRUE(map.canComputeObservationLikelihood(obs));
  const double ll_true = map.computeObservationLikelihood(obs, truth);
  for (const Eigen::Vector3d& off :
       {Eigen::Vector3d(0, 0, 0.1), Eigen::Vector3d(0.1, 0, 0), Eigen::Vector3d(0, 0.05, 0)}) {
    Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
    T.translation() = off;
    EXPECT_GT(ll_true, map.computeObservationLikelihood(obs, mrptSensorPoseFromOptical(T)))
        << off.transpose();
  }
}

TEST(CSurfelMapInsertion, BadFusionKeyInInsertOptionsIsReported) {
  mrpt::config::CConfigFileMemory cfg(
      "[MAP]\nsurfelMap_count = 1\n[MAP_surfelMap_00_insertOpts]\nmax_dept_m = 4\n");
  mrpt::maps::TSetOfMetricMapInitializers inits;
  inits.loadFromConfigFile(cfg, "MAP");
  mrpt::maps::CMultiMetricMap mm(inits);
  const CameraIntrinsics K(65.6, 65.6, 39.5, 29.5, 80, 60);
  const auto sf =
      fusiontest::renderScene(fusiontest::Scene(), K, Eigen::Isometry3d::Identity(), 0.0);
  try {
    mm.insertObservation(observationOf(sf.frame));
    FAIL() << "expected an InputError for the misspelt key";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("max_dept_m"), std::string::npos) << e.what();
  }
}

TEST(CSurfelMapInsertion, RealKinectFrameFromMrptDataset) {
  const std::string path = RASM_MRPT_TEST_RAWLOG;
  if (!std::filesystem::exists(path))
    GTEST_SKIP() << path << " not installed (package mrpt-common)";
  mrpt::obs::CRawlog rawlog;
  ASSERT_TRUE(rawlog.loadFromRawLogFile(path));
  mrpt::obs::CObservation3DRangeScan::Ptr obs;
  for (std::size_t i = 0; i < rawlog.size() && !obs; ++i)
    if (rawlog.getType(i) == mrpt::obs::CRawlog::etObservation)
      obs =
          std::dynamic_pointer_cast<mrpt::obs::CObservation3DRangeScan>(rawlog.getAsObservation(i));
  ASSERT_TRUE(obs);
  maps::CSurfelMap map;
  ASSERT_TRUE(map.insertObservation(*obs));
  const maps::SurfelArrays a = map.arrays();
  EXPECT_GT(a.size, 100000);  // most of the 640x480 pixels
  // Depth of this frame is 1.62-2.56 m (MRPT-NOTES); the sensor is at the origin with MRPT's
  // sensor frame (+x forward), so surfels lie 1.6-2.6 m ahead along world +x.
  int in_range = 0;
  for (int i = 0; i < a.size; ++i)
    in_range += a.position(i).x() > 1.55f && a.position(i).x() < 2.65f;
  EXPECT_GT(in_range, 0.99 * a.size);
  // Registered colour: not all black.
  int coloured = 0;
  for (int i = 0; i < a.size; ++i) coloured += (a.colour(i).r + a.colour(i).g + a.colour(i).b) > 0;
  EXPECT_GT(coloured, a.size / 2);
}
