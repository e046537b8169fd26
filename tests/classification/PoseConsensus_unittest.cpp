// The zero-shot pose consistency across views (PoseConsensus.h): the orientation a template
// viewpoint implies, the agreement modulo symmetry, and which detections it lets through.

#include "rasm/classification/PoseConsensus.h"

#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <cmath>

using namespace rasm::classification;

namespace {

constexpr double kDeg = M_PI / 180.0;

/// An upright camera (optical frame: x right, y down, z forward; no roll, world z up) at
/// `position` looking at `target`, turned by `look_offset_deg` to the left so that the target is
/// off the image centre.
Eigen::Matrix3d uprightCamera(const Eigen::Vector3d& position, const Eigen::Vector3d& target,
                              double look_offset_deg) {
  const Eigen::Vector3d to = target - position;
  const Eigen::Vector3d forward =
      Eigen::AngleAxisd(look_offset_deg * kDeg, Eigen::Vector3d::UnitZ()) * to.normalized();
  const Eigen::Vector3d x = forward.cross(Eigen::Vector3d::UnitZ()).normalized();
  Eigen::Matrix3d R;
  R.col(0) = x;
  R.col(1) = forward.cross(x);
  R.col(2) = forward;
  return R;
}

/// The template viewpoint a camera at `camera` has of a model at `model` with orientation
/// R_world_model: the direction to the camera in the model frame, as azimuth / elevation, rounded
/// to the bank's 5 degree grid when `grid`.
PoseHint viewpoint(const Eigen::Matrix3d& R_world_model, const Eigen::Vector3d& model,
                   const Eigen::Vector3d& camera, bool grid) {
  const Eigen::Vector3d d = R_world_model.transpose() * (camera - model).normalized();
  PoseHint p;
  p.valid = true;
  p.azimuth_deg = float(std::atan2(d.y(), d.x()) / kDeg);
  p.elevation_deg = float(std::asin(d.z()) / kDeg);
  if (grid) {
    p.azimuth_deg = 5.f * std::round(p.azimuth_deg / 5.f);
    p.elevation_deg = 5.f * std::round(p.elevation_deg / 5.f);
  }
  return p;
}

struct View {
  Eigen::Matrix3d R_world_cam;
  Eigen::Vector3d ray_cam;
};

/// A camera 0.5 m above a model at the origin, `distance_m` away at bearing `bearing_deg`,
/// looking at it with the model `look_offset_deg` off the image centre.
View viewFrom(double bearing_deg, double distance_m = 2.0, double look_offset_deg = 10.0) {
  const Eigen::Vector3d model(0, 0, 0);
  const Eigen::Vector3d camera(distance_m * std::cos(bearing_deg * kDeg),
                               distance_m * std::sin(bearing_deg * kDeg), 0.5);
  View v;
  v.R_world_cam = uprightCamera(camera, model, look_offset_deg);
  v.ray_cam = v.R_world_cam.transpose() * (model - camera);
  return v;
}

Eigen::Vector3d cameraAt(double bearing_deg, double distance_m = 2.0) {
  return {distance_m * std::cos(bearing_deg * kDeg), distance_m * std::sin(bearing_deg * kDeg),
          0.5};
}

PoseObservation observation(const PoseHint& pose, const View& v, std::size_t frame,
                            std::uint32_t segment, int class_id) {
  PoseObservation o;
  o.R_world_model = impliedModelRotation(pose, v.R_world_cam, v.ray_cam);
  o.sight_world = (v.R_world_cam * v.ray_cam).normalized();
  o.azimuth_period_deg = pose.azimuth_period_deg;
  o.frame = frame;
  o.evidence = {{segment, class_id, 0.7f, 1.f}};
  return o;
}

}  // namespace

TEST(PoseConsensus, TheExactViewpointImpliesTheModelsOrientation) {
  const Eigen::Matrix3d R_world_model =
      Eigen::AngleAxisd(40 * kDeg, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  for (const double bearing : {0.0, 75.0, 160.0, 250.0}) {
    const PoseHint p = viewpoint(R_world_model, Eigen::Vector3d::Zero(), cameraAt(bearing), false);
    // At the image centre the camera's up is the model's up seen along the ray: exact.
    const View centred = viewFrom(bearing, 2.0, 0.0);
    const Eigen::Matrix3d R = impliedModelRotation(p, centred.R_world_cam, centred.ray_cam);
    EXPECT_LT(orientationDisagreementDeg(R, R_world_model, 360.0), 1e-6) << bearing;
    // Off the centre of a camera pitched down, the camera's up is rolled about the ray by about
    // offset x sin(pitch) (10 degrees x sin 14 degrees = 2.4; the camera is 0.5 m above, 2 m away).
    const View off = viewFrom(bearing, 2.0, 10.0);
    const double roll_deg = 10.0 * std::sin(std::atan2(0.5, 2.0));
    const Eigen::Matrix3d R_off = impliedModelRotation(p, off.R_world_cam, off.ray_cam);
    EXPECT_LT(orientationDisagreementDeg(R_off, R_world_model, 360.0), 1.1 * roll_deg) << bearing;
  }
}

TEST(PoseConsensus, DisagreementIsTheRotationAngleModuloTheAzimuthPeriod) {
  const Eigen::Matrix3d I = Eigen::Matrix3d::Identity();
  const auto yaw = [](double deg) {
    return Eigen::AngleAxisd(deg * kDeg, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  };
  EXPECT_NEAR(orientationDisagreementDeg(I, yaw(180), 360.0), 180.0, 1e-6);
  EXPECT_NEAR(orientationDisagreementDeg(I, yaw(180), 180.0), 0.0, 1e-6);
  EXPECT_NEAR(orientationDisagreementDeg(I, yaw(130), 120.0), 10.0, 1e-6);
  const Eigen::Matrix3d tilt =
      Eigen::AngleAxisd(25 * kDeg, Eigen::Vector3d::UnitX()).toRotationMatrix();
  EXPECT_NEAR(orientationDisagreementDeg(I, tilt, 90.0), 25.0, 1e-6);  // not about z: stays
}

TEST(PoseConsensus, AnObjectSeenFromTwoViewsIsReleasedAndFalseMatchesAreNot) {
  // A model at yaw 40 degrees, its viewpoints on the bank's 5 degree grid (up to 2.5 degrees off
  // each way), seen from bearings 30 and 60 degrees: they imply one orientation.
  const Eigen::Matrix3d R_true =
      Eigen::AngleAxisd(40 * kDeg, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  PoseConsensus consensus(30.0, 10.0);
  PoseObservation seen_first = observation(
      viewpoint(R_true, Eigen::Vector3d::Zero(), cameraAt(30), true), viewFrom(30), 5, 7, 3);
  seen_first.surfels = {11, 12, 13};  // the segment's surfels when it was seen
  const auto first = consensus.add(7, 3, seen_first);
  EXPECT_FALSE(first.this_one);
  EXPECT_TRUE(first.evidence.empty());
  EXPECT_EQ(consensus.heldDetections(), 1u);
  const auto second =
      consensus.add(7, 3,
                    observation(viewpoint(R_true, Eigen::Vector3d::Zero(), cameraAt(60), true),
                                viewFrom(60), 10, 7, 3));
  EXPECT_TRUE(second.this_one);
  EXPECT_EQ(second.evidence.size(), 1u);  // this one's
  ASSERT_EQ(second.earlier.size(), 1u);   // and the held one, with its frame and surfels
  EXPECT_EQ(second.earlier[0].frame, 5u);
  EXPECT_EQ(second.earlier[0].evidence.size(), 1u);
  EXPECT_EQ(second.earlier[0].surfels, (std::vector<std::int32_t>{11, 12, 13}));
  EXPECT_EQ(consensus.heldDetections(), 0u);
  EXPECT_EQ(consensus.releasedDetections(), 2u);

  // A false match: the same outline matched whatever the view, so the template viewpoint stays
  // (azimuth 90) while the camera moves 30 -> 60 -> 90 degrees around: the implied yaws turn with
  // the camera, 30 and 60 degrees apart. 30 is within the tolerance of 30, but as far apart as
  // the views (more than half of them): not an agreement.
  PoseConsensus strict(30.0, 10.0, 0.5);
  PoseHint fixed;
  fixed.valid = true;
  fixed.azimuth_deg = 90.f;
  fixed.elevation_deg = 15.f;
  for (const double bearing : {30.0, 60.0, 90.0})
    EXPECT_FALSE(strict.add(8, 3, observation(fixed, viewFrom(bearing), 0, 8, 3)).this_one);
  EXPECT_EQ(strict.heldDetections(), 3u);
  EXPECT_EQ(strict.releasedDetections(), 0u);
}

TEST(PoseConsensus, TwoImagesFromOneViewDoNotConfirmEachOther) {
  const Eigen::Matrix3d R_true = Eigen::Matrix3d::Identity();
  PoseConsensus consensus(30.0, 10.0);
  const PoseHint p = viewpoint(R_true, Eigen::Vector3d::Zero(), cameraAt(45), true);
  EXPECT_FALSE(consensus.add(1, 2, observation(p, viewFrom(45), 0, 1, 2)).this_one);
  EXPECT_FALSE(consensus.add(1, 2, observation(p, viewFrom(45), 5, 1, 2)).this_one);
  // ... and a view of another class or another segment does not either.
  const PoseHint q = viewpoint(R_true, Eigen::Vector3d::Zero(), cameraAt(80), true);
  EXPECT_FALSE(consensus.add(1, 4, observation(q, viewFrom(80), 10, 1, 4)).this_one);
  EXPECT_FALSE(consensus.add(9, 2, observation(q, viewFrom(80), 10, 9, 2)).this_one);
  EXPECT_EQ(consensus.heldDetections(), 4u);
}

TEST(PoseConsensus, SymmetricModelsAgreeModuloTheirPeriod) {
  // A model with a 180-degree symmetry matched at the symmetric viewpoint from the second view.
  const Eigen::Matrix3d R_true = Eigen::Matrix3d::Identity();
  PoseHint a = viewpoint(R_true, Eigen::Vector3d::Zero(), cameraAt(20), true);
  PoseHint b = viewpoint(R_true, Eigen::Vector3d::Zero(), cameraAt(70), true);
  b.azimuth_deg += 180.f;
  for (PoseHint* p : {&a, &b}) p->azimuth_period_deg = 180.f;
  PoseConsensus consensus(30.0, 10.0);
  consensus.add(2, 1, observation(a, viewFrom(20), 0, 2, 1));
  EXPECT_TRUE(consensus.add(2, 1, observation(b, viewFrom(70), 5, 2, 1)).this_one);
  // Without the symmetry the same hints are 180 degrees apart.
  for (PoseHint* p : {&a, &b}) p->azimuth_period_deg = 360.f;
  PoseConsensus plain(30.0, 10.0);
  plain.add(2, 1, observation(a, viewFrom(20), 0, 2, 1));
  EXPECT_FALSE(plain.add(2, 1, observation(b, viewFrom(70), 5, 2, 1)).this_one);
}

TEST(PoseConsensus, HeldEvidenceFollowsTheSegmentsItWasOn) {
  const Eigen::Matrix3d R_true = Eigen::Matrix3d::Identity();
  PoseConsensus consensus(30.0, 10.0);
  const PoseHint a = viewpoint(R_true, Eigen::Vector3d::Zero(), cameraAt(0), true);
  const PoseHint b = viewpoint(R_true, Eigen::Vector3d::Zero(), cameraAt(40), true);
  consensus.add(3, 1, observation(a, viewFrom(0), 0, 3, 1));
  consensus.add(6, 9, observation(a, viewFrom(0), 0, 6, 9));
  // Segment 3 merges into 5; segment 6 is gone.
  std::vector<std::uint32_t> table(8);
  for (std::uint32_t l = 0; l < table.size(); ++l) table[l] = l;
  table[3] = 5;
  table[6] = 0;
  consensus.relabel(table);
  EXPECT_EQ(consensus.heldDetections(), 1u);
  const auto released = consensus.add(5, 1, observation(b, viewFrom(40), 5, 5, 1));
  ASSERT_TRUE(released.this_one);
  ASSERT_EQ(released.evidence.size(), 1u);
  ASSERT_EQ(released.earlier.size(), 1u);
  ASSERT_EQ(released.earlier[0].evidence.size(), 1u);
  EXPECT_EQ(released.evidence[0].segment, 5u);
  EXPECT_EQ(released.earlier[0].evidence[0].segment, 5u);  // followed the merge of 3 into 5
}

TEST(PoseConsensus, OnlyTheNewestHeldDetectionsOfASegmentKeepTheirSurfels) {
  const Eigen::Matrix3d R_true = Eigen::Matrix3d::Identity();
  PoseConsensus consensus(30.0, 10.0);
  const PoseHint a = viewpoint(R_true, Eigen::Vector3d::Zero(), cameraAt(0), true);
  for (int k = 0; k < 10; ++k) {  // ten views from one place: all held
    PoseObservation o = observation(a, viewFrom(0), std::size_t(k), 4, 1);
    o.surfels = {k};
    EXPECT_FALSE(consensus.add(4, 1, std::move(o)).this_one);
  }
  const PoseHint b = viewpoint(R_true, Eigen::Vector3d::Zero(), cameraAt(40), true);
  const auto released = consensus.add(4, 1, observation(b, viewFrom(40), 10, 4, 1));
  ASSERT_TRUE(released.this_one);
  ASSERT_EQ(released.earlier.size(), 10u);
  for (const ReleasedDetection& e : released.earlier) {
    // The two oldest gave their surfels up (their evidence goes to the segment); the eight
    // newest kept theirs.
    if (e.frame < 2)
      EXPECT_TRUE(e.surfels.empty()) << e.frame;
    else
      EXPECT_EQ(e.surfels, (std::vector<std::int32_t>{std::int32_t(e.frame)})) << e.frame;
  }
}
