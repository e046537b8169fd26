// io::GroundTruthFrameSource: frames without a pose take the trajectory's at their timestamp.
#include <gtest/gtest.h>

#include <cmath>
#include <deque>

#include "rasm/io/GroundTruthFrameSource.h"

using namespace rasm;
using namespace rasm::io;

namespace {

/// Frames at the given timestamps, the first `with_pose` of them carrying a pose of their own.
class StampsSource : public FrameSource {
 public:
  StampsSource(std::deque<double> stamps, int with_pose)
      : m_stamps(std::move(stamps)), m_with_pose(with_pose) {}
  std::optional<RgbdFrame> next() override {
    if (m_stamps.empty()) return std::nullopt;
    RgbdFrame f;
    f.timestamp_s = m_stamps.front();
    m_stamps.pop_front();
    if (m_with_pose-- > 0) f.gt_T_world_cam = Eigen::Isometry3d(Eigen::Translation3d(9, 9, 9));
    return f;
  }
  long long sizeHint() const override { return 7; }
  std::string describe() const override { return "stamps"; }

 private:
  std::deque<double> m_stamps;
  int m_with_pose;
};

StampedPose sample(double t, double x, double yaw) {
  return {t, Eigen::Translation3d(x, 0, 0) * Eigen::AngleAxisd(yaw, Eigen::Vector3d::UnitZ())};
}

}  // namespace

TEST(GroundTruthFrameSource, FramesWithoutAPoseTakeTheTrajectorysAtTheirTime) {
  // Samples out of order (the source sorts them): x = t m, yaw = t rad.
  const Trajectory gt = {sample(0.2, 0.2, 0.2), sample(0.0, 0.0, 0.0), sample(0.1, 0.1, 0.1),
                         sample(0.3, 0.3, 0.3)};
  GroundTruthFrameSource src(
      std::make_unique<StampsSource>(std::deque<double>{0.0, 0.1, 0.15, 0.25, 5.0}, 1), gt,
      0.06);  // samples 0.1 s apart: a wider association
  EXPECT_EQ(src.describe(), "stamps");
  EXPECT_EQ(src.sizeHint(), 7);
  // Its own pose is kept.
  std::optional<RgbdFrame> f = src.next();
  ASSERT_TRUE(f && f->gt_T_world_cam);
  EXPECT_NEAR(f->gt_T_world_cam->translation().x(), 9.0, 1e-12);
  // On a sample: that sample.
  f = src.next();
  ASSERT_TRUE(f && f->gt_T_world_cam);
  EXPECT_NEAR(f->gt_T_world_cam->translation().x(), 0.1, 1e-12);
  // Between samples: linear in position, slerp in rotation (halfway).
  for (const double t : {0.15, 0.25}) {
    f = src.next();
    ASSERT_TRUE(f && f->gt_T_world_cam) << t;
    EXPECT_NEAR(f->gt_T_world_cam->translation().x(), t, 1e-12);
    EXPECT_NEAR(Eigen::AngleAxisd(f->gt_T_world_cam->linear()).angle(), t, 1e-9);
  }
  // Far from every sample: none.
  f = src.next();
  ASSERT_TRUE(f.has_value());
  EXPECT_FALSE(f->gt_T_world_cam.has_value());
  EXPECT_FALSE(src.next().has_value());
  EXPECT_EQ(src.attached(), 3);
  EXPECT_EQ(src.unmatched(), 1);
}
