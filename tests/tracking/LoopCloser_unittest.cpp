// The loop-closure policy (LoopCloser) on an analytic, textured room: the part of the map made on
// an earlier pass sits displaced by a known drift; the check registers the frame against both
// parts, asks for that correction, confirms it by colour against the old part and closes it on
// the second agreeing check.
#include "rasm/tracking/LoopCloser.h"

#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "rasm/core/FrameProcessing.h"
#include "rasm/core/SE3.h"
#include "tracking/SyntheticScene.h"

using namespace rasm;
using namespace rasm::tracking;
using rasm::test::lookAt;
using rasm::test::motion;
using rasm::test::Scene;

namespace {

const CameraIntrinsics K = CameraIntrinsics::preset("kinect_v1");

/// The map's parts as the tracking stage renders them: every render into the same buffers (the
/// previous part's views then show the new one), the colour dropped when not asked for, as
/// SurfelRenderer does. The inactive part (created_before_s set) is the room moved by `drift`,
/// the active part the room where it is.
class RoomParts : public MapPartSource {
 public:
  struct Render {
    bool inactive, colour;
  };
  RoomParts(const Scene& scene, const Eigen::Isometry3d& drift) : m_scene(scene), m_drift(drift) {}

  MapPart render(const Eigen::Isometry3d& T, bool with_colour,
                 const maps::RenderOptions& filter) override {
    const bool inactive = std::isfinite(filter.created_before_s);
    renders.push_back({inactive, with_colour});
    // A point X of the room moved to D X projects from T as X does from D^-1 T.
    const Eigen::Isometry3d T_seen = inactive ? m_drift.inverse() * T : T;
    std::vector<FrameLevel> pyr;
    buildFramePyramid(m_scene.render(K, T_seen), K, 1, pyr);
    const test::WorldMaps world(pyr[0], T);  // camera frame -> the part's world frame
    m_vertex.resize(K.width, K.height);
    m_normal.resize(K.width, K.height);
    MapPart part;
    for (int y = 0; y < K.height; ++y)
      for (int x = 0; x < K.width; ++x) {
        m_vertex(x, y) = world.vertex(x, y);
        m_normal(x, y) = world.normal(x, y);
        part.valid_pixels += world.normal(x, y).x() == world.normal(x, y).x();
      }
    m_colour = with_colour ? m_scene.renderColour(K, T_seen) : Image<Bgr8>();
    part.model.vertex_world = m_vertex.cview();
    part.model.normal_world = m_normal.cview();
    part.model.K = K;
    part.model.T_world_model = T;
    if (with_colour) part.model.colour = m_colour.cview();
    return part;
  }
  double medianInitTimeOfLastRender() const override { return 2.0; }

  std::vector<Render> renders;

 private:
  const Scene& m_scene;
  Eigen::Isometry3d m_drift;
  Image<Vec3f> m_vertex, m_normal;
  Image<Bgr8> m_colour;
};

Scene texturedRoom() {
  Scene s = Scene::room();
  s.texture = Scene::smoothTexture;
  return s;
}

}  // namespace

TEST(LoopCloser, ADriftedOldMapIsRegisteredConfirmedByColourAndClosed) {
  const Scene scene = texturedRoom();
  const Eigen::Isometry3d T_true = lookAt({0.3, -1.5, 1.3}, {-0.2, 0.8, 0.5});
  // The old pass's map sits 4 cm and 0.8 deg off (5.6 cm at the camera, 1.55 m from the axis):
  // within the drift bound after 4 m of path (5 cm + 5 cm/m, 1 deg + 1 deg/m), above the 2 cm /
  // 0.5 deg of agreement.
  const Eigen::Isometry3d drift = motion({0.03, -0.02, 0.0173}, {0, 0, 1}, 0.8);
  RoomParts parts(scene, drift);

  TLoopClosureParams lp;
  lp.enabled = true;
  lp.check_every_frames = 1;
  lp.inactive_after_s = 5.0;
  ASSERT_EQ(lp.confirmation, "colour");
  ASSERT_EQ(lp.confirmations, 2);
  LoopCloser closer;
  closer.configure(lp, TTrackingParams());
  closer.start(nullptr);
  maps::CSurfelMap map;
  // The trajectory: 4 m along x in 8 s, ending at the frame's pose.
  for (int k = 0; k <= 16; ++k) {
    const Eigen::Isometry3d T = Eigen::Translation3d(-0.25 * (16 - k), 0.0, 0.0) * T_true;
    closer.frameDone(false);
    EXPECT_TRUE(closer.closeIfDue(std::size_t(k), 0.5 * k, T, map).empty());
  }

  RgbdFrame frame;
  frame.intrinsics = K;
  frame.depth_m = scene.render(K, T_true);
  frame.colour = scene.renderColour(K, T_true);
  std::vector<FrameLevel> pyr;
  buildFramePyramid(frame.depth_m, K, TTrackingParams::kMaxLevels, pyr);
  int valid = 0;
  for (int y = 0; y < K.height; ++y)
    for (int x = 0; x < K.width; ++x) valid += pyr[0].normal(x, y).x() == pyr[0].normal(x, y).x();
  Relocaliser reloc;

  const char* expected[] = {"candidate", "closed"};
  for (int c = 0; c < 2; ++c) {
    frame.index = std::size_t(17 + c);
    frame.timestamp_s = 8.5 + 0.5 * c;
    parts.renders.clear();
    const LoopCheck check = closer.check(frame, pyr, T_true, valid, map, parts, reloc);
    EXPECT_TRUE(check.rendered);
    EXPECT_EQ(check.verdict, expected[c]) << "check " << c;
    // (the correction where the camera is: the drift's rotation about the origin moves it too)
    EXPECT_NEAR(check.correction_m, translationDistance(drift * T_true, T_true), 0.005)
        << "check " << c;
    EXPECT_NEAR(check.correction_deg, 0.8, 0.15) << "check " << c;
    // The old part for the geometry, the active part, the old part again with its colour for
    // the confirmation (the first render's views were overwritten by the second).
    ASSERT_EQ(parts.renders.size(), 3u) << "check " << c;
    EXPECT_TRUE(parts.renders[0].inactive && !parts.renders[0].colour);
    EXPECT_TRUE(!parts.renders[1].inactive && !parts.renders[1].colour);
    EXPECT_TRUE(parts.renders[2].inactive && parts.renders[2].colour);
    closer.frameDone(false);
    const TrajectoryCorrection corr =
        closer.closeIfDue(frame.index, frame.timestamp_s, T_true, map);
    EXPECT_EQ(corr.empty(), c == 0) << "check " << c;
    if (!corr.empty()) {  // the camera now sits where the old map says it is
      const Eigen::Isometry3d T_corrected = corr.at(frame.timestamp_s) * T_true;
      EXPECT_LT(translationDistance(T_corrected, drift * T_true), 0.01);
    }
  }
  EXPECT_EQ(closer.checks(), 2u);
  EXPECT_EQ(closer.closed().size(), 1u);
}
