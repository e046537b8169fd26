// What people open of a run (issue 19, 3-4): the 3-D scenes carry the paths, the last camera and
// the exploration's candidate views and start on the map; annotated.rawlog carries the path as
// odometry (RawLogViewer draws it) with the tracking status; the plots; the plotter itself.
#include <gtest/gtest.h>
#include <mrpt/io/CFileGZInputStream.h>
#include <mrpt/obs/CObservation3DRangeScan.h>
#include <mrpt/obs/CObservationComment.h>
#include <mrpt/obs/CObservationOdometry.h>
#include <mrpt/opengl/CArrow.h>
#include <mrpt/opengl/CBox.h>
#include <mrpt/opengl/COpenGLScene.h>
#include <mrpt/opengl/CSetOfLines.h>
#include <mrpt/opengl/CSetOfObjects.h>
#include <mrpt/opengl/CText.h>
#include <mrpt/serialization/CArchive.h>

#include <filesystem>
#include <fstream>
#include <opencv2/imgcodecs.hpp>

#include "rasm/core/Error.h"
#include "rasm/core/SE3.h"
#include "rasm/run/LinePlot.h"
#include "rasm/run/MappingRun.h"
#include "rasm/run/RunPlots.h"
#include "rasm/run/RunScene.h"
#include "run/RunTestFiles.h"

namespace fs = std::filesystem;
using namespace rasm;
using namespace rasm::pipeline;
using namespace rasm::autonomy;
using namespace rasm::run;
using namespace rasm::run::testing;

namespace {
int countColour(const cv::Mat& img, const cv::Vec3b& bgr) {
  int n = 0;
  for (int y = 0; y < img.rows; ++y)
    for (int x = 0; x < img.cols; ++x) n += img.at<cv::Vec3b>(y, x) == bgr;
  return n;
}

/// Pixels whose channel `c` (0 blue, 1 green, 2 red) exceeds both others by 60 (anti-aliased
/// lines blend into the white).
int countDominant(const cv::Mat& img, int c) {
  int n = 0;
  for (int y = 0; y < img.rows; ++y)
    for (int x = 0; x < img.cols; ++x) {
      const cv::Vec3b p = img.at<cv::Vec3b>(y, x);
      n += p[c] > p[(c + 1) % 3] + 60 && p[c] > p[(c + 2) % 3] + 60;
    }
  return n;
}

io::Trajectory straightPath(int n, double step_m) {
  io::Trajectory t;
  for (int i = 0; i < n; ++i) {
    Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
    T.translation() = Eigen::Vector3d(step_m * i, 0.5, 0.3);
    t.push_back({0.1 * i, T});
  }
  return t;
}
}  // namespace

TEST(LinePlot, DrawsEachSeriesInItsColourInsideTheFrame) {
  PlotSeries up{"up", {0, 1, 2}, {0, 1, 2}, cv::Scalar(255, 0, 0), 2};
  PlotSeries flat{"flat", {0, 2}, {1, 1}, cv::Scalar(0, 0, 255), 1};
  PlotSeries legend_only{"flat", {}, {}, cv::Scalar(0, 0, 255), 1};
  PlotAxes axes;
  axes.y_min = 0;
  axes.y_max = 2;
  const cv::Mat img = linePlot(axes, {up, flat}, 400, 300);
  ASSERT_EQ(img.cols, 400);
  ASSERT_EQ(img.rows, 300);
  const int legend = countDominant(linePlot(axes, {up, legend_only}, 400, 300), 2);
  // The diagonal is drawn in blue, the flat line in red across the plot (~320 px).
  EXPECT_GT(countDominant(img, 0), 400);
  EXPECT_GT(countDominant(img, 2), legend + 250);
  // Above y_max it is clipped: only its legend entry stays.
  flat.y = {5, 5};
  EXPECT_EQ(countDominant(linePlot(axes, {up, flat}, 400, 300), 2), legend);
}

TEST(LinePlot, EqualAspectKeepsMetresSquare) {
  // A 4 m x 1 m rectangle in a square image: with equal scales its drawn height is a quarter
  // of its drawn width.
  PlotSeries box{"", {0, 4, 4, 0, 0}, {0, 0, 1, 1, 0}, cv::Scalar(0, 200, 0), 1};
  PlotAxes axes;
  axes.equal_aspect = true;
  const cv::Mat img = linePlot(axes, {box}, 500, 500);
  int x0 = img.cols, x1 = -1, y0 = img.rows, y1 = -1;
  for (int y = 0; y < img.rows; ++y)
    for (int x = 0; x < img.cols; ++x)
      if (img.at<cv::Vec3b>(y, x)[1] > img.at<cv::Vec3b>(y, x)[0] + 60)
        x0 = std::min(x0, x), x1 = std::max(x1, x), y0 = std::min(y0, y), y1 = std::max(y1, y);
  ASSERT_GT(x1, x0);
  EXPECT_NEAR(double(y1 - y0) / double(x1 - x0), 0.25, 0.02);
}

TEST(LinePlot, TicksAreRoundAndFew) {
  EXPECT_EQ(niceTicks(0, 240, 6), (std::vector<double>{0, 50, 100, 150, 200}));
  EXPECT_EQ(niceTicks(0, 1, 5), (std::vector<double>{0, 0.5, 1}));
  EXPECT_EQ(niceTicks(-3.2, 7.9, 10), (std::vector<double>{-2, 0, 2, 4, 6}));
  EXPECT_EQ(niceTicks(0, 1, 11).size(), 11u) << "0.1 apart";
  EXPECT_TRUE(niceTicks(1, 1, 5).empty());
}

TEST(RunPlots, TimingPlotStacksTheStagesUpToTheTotal) {
  // Stages a (10 ms) and b (5 ms, of which its part b_part 3 ms), total 20 ms: three layers
  // 10, 5 and the rest 5 ms high, the part not stacked again; a column that is no timer is not
  // drawn.
  std::string csv = "index,timestamp_s,tracked,icp_iterations,ms_a,ms_b,ms_b_part,ms_total\n";
  for (int i = 0; i < 50; ++i)
    csv += std::to_string(i) + ",0.0,1," + (i == 1 ? "x" : "3") + ",10,5,3,20\n";
  const CsvColumns c = parseCsvColumns(csv);
  ASSERT_EQ(c.rows, 50u);
  EXPECT_TRUE(std::isnan(c.values.at("icp_iterations")[1])) << "'x' is no number";
  const cv::Mat img = timingPlot(c, {"a", "b"});
  ASSERT_FALSE(img.empty());
  EXPECT_EQ(img.cols, 900);
  const auto light = [](const cv::Scalar& s) {  // a band's fill: halfway to white
    cv::Vec3b v;
    for (int k = 0; k < 3; ++k) v[k] = cv::saturate_cast<uchar>(0.5 * (s[k] + 255));
    return v;
  };
  const int a = countColour(img, light({200, 80, 0})), b = countColour(img, light({0, 0, 200}));
  const int rest = countColour(img, light({190, 190, 190}));
  ASSERT_GT(b, 1000);
  EXPECT_NEAR(double(a) / b, 2.0, 0.15) << "10 ms over 5 ms";
  EXPECT_NEAR(double(rest) / b, 1.0, 0.1) << "20 - 10 - 5 ms";
  EXPECT_GT(countColour(img, cv::Vec3b(0, 0, 0)), 1500) << "the total, thick black, and the frame";
  EXPECT_TRUE(timingPlot(parseCsvColumns("index,tracked\n0,1\n"), {"a"}).empty());
}

TEST(RunPlots, ObjectsPlotFollowsTheObjectList) {
  // 1 object for 20 frames, then 3, then 5; one detection fused every 4th frame.
  std::string csv = "index,tracked,cls_fused,objects\n";
  for (int i = 0; i < 60; ++i)
    csv += std::to_string(i) + ",1," + (i % 4 == 0 ? "1" : "0") + "," +
           (i < 20   ? "0"
            : i < 40 ? "3"
                     : "5") +
           "\n";
  const cv::Mat img = objectsPlot(parseCsvColumns(csv));
  ASSERT_EQ(img.rows, 2 * 240);
  // The objects line (2 px, BGR 160, 60, 0) inside the top panel (below its legend): its highest
  // pixels (5 objects) lie right of its lowest (1 object), the steps at frames 20 and 40.
  int top_y = 1 << 30, bottom_y = -1, top_x = 0, bottom_x = 0;
  for (int y = 45; y < 240; ++y)
    for (int x = 60; x < 860; ++x)
      if (img.at<cv::Vec3b>(y, x) == cv::Vec3b(160, 60, 0)) {
        if (y < top_y) top_y = y, top_x = x;
        if (y > bottom_y) bottom_y = y, bottom_x = x;
      }
  ASSERT_GE(bottom_y, 0) << "no objects line";
  EXPECT_GT(bottom_y - top_y, 80) << "1 to 5 of 5.5 objects spans most of the panel";
  EXPECT_GT(top_x, bottom_x);
  EXPECT_GT(countColour(img, cv::Vec3b(0, 120, 0)), 300) << "the detections fused line";
  EXPECT_TRUE(objectsPlot(parseCsvColumns("index,tracked\n0,1\n")).empty()) << "no column";
  EXPECT_TRUE(objectsPlot(parseCsvColumns("")).empty());
}

TEST(RunPlots, TrajectoryPlotMarksLostFrames) {
  const io::Trajectory est = straightPath(20, 0.1);
  const CsvColumns frames = parseCsvColumns(
      "index,tracked\n0,1\n1,1\n2,1\n3,1\n4,1\n5,0\n6,0\n7,1\n8,1\n9,1\n10,1\n11,1\n12,1\n"
      "13,1\n14,1\n15,1\n16,1\n17,1\n18,1\n19,1\n");
  const cv::Mat with_lost = trajectoryPlot(est, {}, frames);
  const cv::Mat none_lost = trajectoryPlot(est, {}, parseCsvColumns(""));
  // The lost frames are red dots (BGR 0, 0, 220) beyond the legend entry.
  EXPECT_GT(countDominant(with_lost, 2), countDominant(none_lost, 2) + 10);
}

TEST(RunPlots, TrackingPlotShadesLostFramesInEveryPanel) {
  // 41 frames, x 0-40; the ground truth 10 cm beside the estimate.
  const io::Trajectory est = straightPath(41, 0.1);
  io::Trajectory gt = est;
  for (io::StampedPose& p : gt) p.T_world_cam.translation().y() += 0.1;
  const auto csv = [](std::initializer_list<int> lost) {
    std::string text = "index,tracked,inlier_fraction,check_agreement,rms_m\n";
    for (int i = 0; i <= 40; ++i) {
      const bool l = std::find(lost.begin(), lost.end(), i) != lost.end();
      text += std::to_string(i) + (l ? ",0" : ",1") + ",0.8,0.95,0.004\n";
    }
    return parseCsvColumns(text);
  };
  const cv::Mat with_gt = trackingPlot(csv({10, 11}), est, gt);
  EXPECT_EQ(with_gt.rows, 3 * 240) << "fraction, residual and world-frame error panels";
  EXPECT_EQ(trackingPlot(csv({10, 11}), est, {}).rows, 2 * 240);
  EXPECT_TRUE(trackingPlot(parseCsvColumns(""), est, gt).empty());
  // The band: light red (halfway from BGR 150, 150, 255 to white), as wide as the lost frames.
  const cv::Vec3b band(cv::saturate_cast<uchar>(202.5), cv::saturate_cast<uchar>(202.5), 255);
  const int two = countColour(with_gt, band),
            four = countColour(trackingPlot(csv({10, 11, 30, 31}), est, gt), band);
  EXPECT_EQ(countColour(trackingPlot(csv({}), est, gt), band), 0);
  ASSERT_GT(two, 3 * 500) << "a band in each of the 3 panels";
  EXPECT_NEAR(double(four) / two, 2.0, 0.2);
}

TEST(RunScene, ViewsSurviveJsonAndABadEntryIsNamed) {
  SceneView a;
  a.position = {1, 2, 0.5};
  a.direction = {0, 1, 0};
  a.gain = 0.7;
  SceneView b = a;
  b.reachable = false;
  b.goal = true;
  const auto back = sceneViewsFromJson(sceneViewsJson({a, b}), "x");
  ASSERT_EQ(back.size(), 2u);
  EXPECT_EQ(back[0].position, a.position);
  EXPECT_EQ(back[0].direction, a.direction);
  EXPECT_DOUBLE_EQ(back[0].gain, 0.7);
  EXPECT_TRUE(back[0].reachable);
  EXPECT_FALSE(back[1].reachable);
  EXPECT_TRUE(back[1].goal);
  try {
    sceneViewsFromJson(nlohmann::json::parse(R"([{"position": [1, 2], "direction": [0, 0, 1]}])"),
                       "exploration.json candidate_views");
    FAIL() << "a 2-vector position accepted";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("exploration.json candidate_views[0].position"),
              std::string::npos)
        << e.what();
  }
}

TEST(RunScene, SceneHoldsPathsCameraViewsAndStartsOnTheMap) {
  maps::SurfelStore store;
  // A 4 m x 2 m floor patch centred on (5, 3, 0), far from the origin.
  for (int i = 0; i < 40; ++i)
    for (int j = 0; j < 20; ++j) {
      maps::Surfel s;
      s.position = Vec3f(3.0f + 0.1f * i, 2.0f + 0.1f * j, 0.0f);
      s.radius = 0.05f;
      s.confidence = 5.0f;
      store.append(s);
    }
  RunOverlay o;
  o.estimate = straightPath(10, 0.2);
  o.groundtruth = straightPath(10, 0.21);
  SceneView v;
  v.position = {4, 3, 0.5};
  v.gain = 1.0;
  o.views = {v, v};
  o.views[1].goal = true;
  ObjectBox chair;
  chair.class_name = "chair", chair.class_id = 57, chair.probability = 0.9;
  chair.centre_world = {4.0, 3.0, 0.4};
  chair.axes_world = Eigen::AngleAxisd(0.5, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  chair.extents_m = {0.5, 0.6, 0.8};
  o.objects = {chair};
  const auto scene = runScene(store, {}, o);
  const std::string path = tempDir("scene") + ".3Dscene";
  ASSERT_TRUE(scene->saveToFile(path));
  mrpt::opengl::COpenGLScene back;  // what SceneViewer3D reads
  ASSERT_TRUE(back.loadFromFile(path));
  fs::remove(path);
  auto traj = std::dynamic_pointer_cast<mrpt::opengl::CSetOfLines>(back.getByName("trajectory"));
  ASSERT_TRUE(traj);
  EXPECT_EQ(traj->size(), 9u) << "one segment between each two of the 10 poses";
  EXPECT_TRUE(back.getByName("groundtruth"));
  auto cam = std::dynamic_pointer_cast<mrpt::opengl::CSetOfObjects>(back.getByName("camera"));
  ASSERT_TRUE(cam);
  EXPECT_NEAR(cam->getPose().x, 1.8, 1e-5) << "at the last pose";
  auto views =
      std::dynamic_pointer_cast<mrpt::opengl::CSetOfObjects>(back.getByName("candidate_views"));
  ASSERT_TRUE(views);
  EXPECT_EQ(std::distance(views->begin(), views->end()), 2);
  // The object: its box as a wireframe at its pose (yaw 0.5 rad) and its label 0.1 m above the
  // box's top (0.4 + 0.8 / 2 m), both in the class colour.
  auto objects = std::dynamic_pointer_cast<mrpt::opengl::CSetOfObjects>(back.getByName("objects"));
  ASSERT_TRUE(objects);
  std::shared_ptr<mrpt::opengl::CBox> box;
  std::shared_ptr<mrpt::opengl::CText> label;
  for (const auto& obj : *objects) {
    if (auto b = std::dynamic_pointer_cast<mrpt::opengl::CBox>(obj)) box = b;
    if (auto t = std::dynamic_pointer_cast<mrpt::opengl::CText>(obj)) label = t;
  }
  ASSERT_TRUE(box && label);
  EXPECT_TRUE(box->isWireframe());
  EXPECT_NEAR(box->getPose().x, 4.0, 1e-6);
  EXPECT_NEAR(box->getPose().yaw, 0.5, 1e-6);
  mrpt::math::TPoint3D lo, hi;
  box->getBoxCorners(lo, hi);
  EXPECT_NEAR(hi.z - lo.z, 0.8, 1e-6);
  EXPECT_EQ(label->getString(), "chair 0.90");
  EXPECT_NEAR(label->getPose().z, 0.9, 1e-6);
  const Bgr8 colour = maps::labelColour(57);
  EXPECT_EQ(label->getColor_u8().R, colour.r);
  // The camera looks at the middle of the map and the path (x 0-6.9, y 0.5-3.9), not at (0,0,0).
  EXPECT_TRUE(back.followCamera());
  const mrpt::opengl::CCamera& c = back.getViewport("main")->getCamera();
  EXPECT_NEAR(c.getPointingAtX(), 3.45, 0.06);
  EXPECT_NEAR(c.getPointingAtY(), 2.2, 0.06);
  EXPECT_GT(c.getZoomDistance(), 6.9) << "far enough to see most of the 6.9 m extent";
  EXPECT_LT(c.getZoomDistance(), 20.0);
}

// A short simulated hand-held replay (20 frames with ground truth): the scenes, the annotated
// rawlog's odometry and the plots.
TEST(RunScene, RunWritesScenesRawlogPathAndPlots) {
  const std::string out = tempDir("scene_run");
  RunConfig cfg = RunConfig::fromString("[source]\ntype = rawlog\npath = " RASM_SOURCE_DIR
                                        "/rawlogs/sim_office_handheld_320x240.rawlog\n",
                                        "test");
  cfg.set("output", "dir", out);
  cfg.set("output", "write_rawlog", "true");
  MappingRun run(cfg);
  const RunSummary s = run.run();
  ASSERT_EQ(s.frames, 20u);
  expectCompleteRunFolder(out);
  const io::Trajectory est = io::readTumTrajectory(out + "/trajectory.txt");

  mrpt::opengl::COpenGLScene scene;
  ASSERT_TRUE(scene.loadFromFile(out + "/map.3Dscene"));
  auto traj = std::dynamic_pointer_cast<mrpt::opengl::CSetOfLines>(scene.getByName("trajectory"));
  ASSERT_TRUE(traj);
  EXPECT_EQ(traj->size(), 19u);
  EXPECT_TRUE(scene.getByName("groundtruth")) << "the simulated rawlog has ground truth";
  EXPECT_TRUE(scene.getByName("camera"));
  EXPECT_TRUE(scene.followCamera());
  const mrpt::opengl::CCamera& cam = scene.getViewport("main")->getCamera();
  const maps::PlySurfels ply = maps::readSurfelPly(out + "/map.ply");
  Eigen::AlignedBox3f box;
  for (const Vec3f& p : ply.position) box.extend(p);
  EXPECT_TRUE(box.contains(
      Eigen::Vector3f(cam.getPointingAtX(), cam.getPointingAtY(), cam.getPointingAtZ())))
      << "the camera points into the map";

  // annotated.rawlog: per frame a CObservationOdometry labelled with the status, then the scan;
  // odometry + sensorPose is the estimated camera pose of trajectory.txt.
  mrpt::io::CFileGZInputStream in(out + "/annotated.rawlog");
  auto ar = mrpt::serialization::archiveFrom(in);
  std::optional<mrpt::poses::CPose2D> odo;
  std::size_t frames = 0, comments = 0;
  for (;;) {
    mrpt::serialization::CSerializable::Ptr obj;
    try {
      ar >> obj;
    } catch (const mrpt::serialization::CExceptionEOF&) {
      break;
    }
    if (auto c = std::dynamic_pointer_cast<mrpt::obs::CObservationComment>(obj)) ++comments;
    if (auto o = std::dynamic_pointer_cast<mrpt::obs::CObservationOdometry>(obj)) {
      EXPECT_TRUE(o->sensorLabel == "POSE_TRACKED" || o->sensorLabel == "POSE_LOST" ||
                  o->sensorLabel == "POSE_RELOCALISED")
          << o->sensorLabel;
      odo = o->odometry;
    }
    auto scan = std::dynamic_pointer_cast<mrpt::obs::CObservation3DRangeScan>(obj);
    if (!scan) continue;
    ASSERT_TRUE(odo) << "frame " << frames << " without its odometry before it";
    ASSERT_LT(frames, est.size());
    const Eigen::Isometry3d T =
        opticalFromMrptSensorPose(mrpt::poses::CPose3D(*odo) + scan->sensorPose);
    EXPECT_LT((T.translation() - est[frames].T_world_cam.translation()).norm(), 1e-4);
    EXPECT_LT((T.linear() - est[frames].T_world_cam.linear()).norm(), 1e-4);
    odo.reset();
    ++frames;
  }
  EXPECT_EQ(frames, 20u);
  EXPECT_GE(comments, 1u) << "the header saying the poses are estimates";

  const cv::Mat tp = cv::imread(out + "/plot_trajectory.png");
  const cv::Mat tm = cv::imread(out + "/plot_timing.png");
  EXPECT_EQ(tp.cols, 560);
  EXPECT_EQ(tm.cols, 900);
  // The floor plan: the simulated rawlog's frame is the world's (z up), which the map's
  // horizontal surfaces find (a rawlog says nothing about gravity; the camera looks down).
  const cv::Mat plan = cv::imread(out + "/floorplan.png");
  EXPECT_FALSE(plan.empty());
  std::ifstream svg_file(out + "/floorplan.svg");
  const std::string svg((std::istreambuf_iterator<char>(svg_file)), {});
  EXPECT_NE(svg.find("width=\"" + std::to_string(plan.cols) + "\""), std::string::npos);
  EXPECT_NE(svg.find("up = world +z (no gravity in the data:"), std::string::npos);
  EXPECT_NE(svg.find("horizontal surfaces"), std::string::npos);
  fs::remove_all(out);
}
