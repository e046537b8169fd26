#include "rasm/run/RunScene.h"

#include <mrpt/img/color_maps.h>
#include <mrpt/opengl/CArrow.h>
#include <mrpt/opengl/CBox.h>
#include <mrpt/opengl/CFrustum.h>
#include <mrpt/opengl/COpenGLScene.h>
#include <mrpt/opengl/CSetOfLines.h>
#include <mrpt/opengl/CSetOfObjects.h>
#include <mrpt/opengl/CText.h>
#include <mrpt/opengl/stock_objects.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>

#include "rasm/core/Error.h"
#include "rasm/core/SE3.h"

namespace rasm::run {

using autonomy::SceneView;
using autonomy::sceneViewsFromJson;

namespace fs = std::filesystem;

namespace {
mrpt::opengl::CSetOfLines::Ptr lineStrip(const io::Trajectory& path, const char* name,
                                         std::uint8_t r, std::uint8_t g, std::uint8_t b) {
  auto lines = mrpt::opengl::CSetOfLines::Create();
  lines->setName(name);
  lines->setColor_u8(r, g, b);
  lines->setLineWidth(3.0f);
  lines->setVerticesPointSize(4.0f);  // wide lines are not drawn everywhere: points at the poses
  for (std::size_t i = 1; i < path.size(); ++i) {
    const Eigen::Vector3d a = path[i - 1].T_world_cam.translation();
    const Eigen::Vector3d c = path[i].T_world_cam.translation();
    lines->appendLine(a.x(), a.y(), a.z(), c.x(), c.y(), c.z());
  }
  return lines;
}

/// The last camera: a wireframe frustum with its field of view (0.05-0.4 m) and small axes.
mrpt::opengl::CSetOfObjects::Ptr cameraObject(const Eigen::Isometry3d& T_world_cam,
                                              const CameraIntrinsics& K) {
  auto cam = mrpt::opengl::CSetOfObjects::Create();
  cam->setName("camera");
  const float hfov = float(2.0 * std::atan2(0.5 * K.width, K.fx) * 180.0 / M_PI);
  const float vfov = float(2.0 * std::atan2(0.5 * K.height, K.fy) * 180.0 / M_PI);
  auto frustum = mrpt::opengl::CFrustum::Create(0.05f, 0.4f, hfov, vfov, 2.0f, true, false);
  frustum->setColor_u8(255, 255, 255);
  cam->insert(frustum);
  cam->insert(mrpt::opengl::stock_objects::CornerXYZSimple(0.15f, 2.0f));
  cam->setPose(mrptSensorPoseFromOptical(T_world_cam));  // MRPT's sensor frame: +X forward
  return cam;
}

mrpt::opengl::CSetOfObjects::Ptr viewArrows(const std::vector<SceneView>& views) {
  auto arrows = mrpt::opengl::CSetOfObjects::Create();
  arrows->setName("candidate_views");
  double lo = INFINITY, hi = -INFINITY;
  for (const SceneView& v : views)
    if (!v.goal && v.reachable) lo = std::min(lo, v.gain), hi = std::max(hi, v.gain);
  for (const SceneView& v : views) {
    const float len = v.goal ? 0.45f : 0.3f;
    const Eigen::Vector3f a = v.position.cast<float>();
    const Eigen::Vector3f b = a + len * v.direction.normalized().cast<float>();
    auto arrow = mrpt::opengl::CArrow::Create(a.x(), a.y(), a.z(), b.x(), b.y(), b.z(), 0.35f,
                                              v.goal ? 0.02f : 0.012f, v.goal ? 0.05f : 0.035f);
    if (v.goal) {
      arrow->setColor_u8(230, 0, 230);
    } else if (!v.reachable) {
      arrow->setColor_u8(150, 150, 150);
    } else {
      const float t = hi > lo ? float((v.gain - lo) / (hi - lo)) : 1.0f;
      float r = 0, g = 0, bl = 0;
      mrpt::img::colormap(mrpt::img::cmJET, t, r, g, bl);
      arrow->setColor(r, g, bl);
    }
    arrows->insert(arrow);
  }
  return arrows;
}
}  // namespace

namespace {
/// The JSON document at `path`; InputError naming it when it is not JSON.
nlohmann::json readJson(const fs::path& path) {
  std::ifstream f(path);
  try {
    return nlohmann::json::parse(f);
  } catch (const std::exception& e) {
    throwInputError(path.string(), std::string("is not valid JSON: ") + e.what());
  }
}

/// Each object's oriented box (wireframe) and its "class probability" label above it.
mrpt::opengl::CSetOfObjects::Ptr objectBoxesObject(const std::vector<ObjectBox>& objects) {
  auto set = mrpt::opengl::CSetOfObjects::Create();
  set->setName("objects");
  for (const ObjectBox& o : objects) {
    const Bgr8 c = maps::labelColour(o.class_id);
    const Eigen::Vector3d half = 0.5 * o.extents_m;
    auto box =
        mrpt::opengl::CBox::Create(mrpt::math::TPoint3D(-half.x(), -half.y(), -half.z()),
                                   mrpt::math::TPoint3D(half.x(), half.y(), half.z()), true, 2.0f);
    Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
    T.linear() = o.axes_world;
    T.translation() = o.centre_world;
    box->setPose(toCPose3D(T));
    box->setColor_u8(c.r, c.g, c.b);
    set->insert(box);
    char label[96];
    std::snprintf(label, sizeof label, "%s %.2f", o.class_name.c_str(), o.probability);
    auto text = mrpt::opengl::CText::Create(label);
    const Eigen::Vector3d top = o.centre_world + o.axes_world * Eigen::Vector3d(0, 0, half.z());
    text->setLocation(top.x(), top.y(), top.z() + 0.1);
    text->setColor_u8(c.r, c.g, c.b);
    set->insert(text);
  }
  return set;
}
}  // namespace

RunOverlay readRunOverlay(const std::string& dir) {
  RunOverlay o;
  o.estimate = io::readTumTrajectory((fs::path(dir) / "trajectory.txt").string());
  const fs::path gt = fs::path(dir) / "groundtruth.txt";
  if (fs::exists(gt)) o.groundtruth = io::readTumTrajectory(gt.string());
  const fs::path xp = fs::path(dir) / "exploration.json";
  if (fs::exists(xp)) {
    const nlohmann::json j = readJson(xp);
    if (j.contains("candidate_views"))
      o.views = sceneViewsFromJson(j["candidate_views"], xp.string() + " candidate_views");
  }
  const fs::path objects = fs::path(dir) / "objects.json";
  if (fs::exists(objects)) o.objects = objectBoxes(readJson(objects));
  return o;
}

void addRunOverlay(mrpt::opengl::COpenGLScene& scene, const RunOverlay& o) {
  if (o.groundtruth.size() > 1) scene.insert(lineStrip(o.groundtruth, "groundtruth", 0, 170, 0));
  if (o.estimate.size() > 1) scene.insert(lineStrip(o.estimate, "trajectory", 255, 140, 0));
  if (!o.estimate.empty()) scene.insert(cameraObject(o.estimate.back().T_world_cam, o.K));
  if (!o.views.empty()) scene.insert(viewArrows(o.views));
  if (!o.objects.empty()) scene.insert(objectBoxesObject(o.objects));
}

Eigen::AlignedBox3d sceneBounds(const maps::SurfelStore& map, const RunOverlay& o) {
  const maps::SurfelArrays a = map.arrays();
  std::vector<float> c[3];
  for (int i = 0; i < a.size; ++i) {
    if (!a.alive(i)) continue;
    const Vec3f p = a.position(i);
    for (int k = 0; k < 3; ++k) c[k].push_back(p[k]);
  }
  Eigen::AlignedBox3d box;  // empty
  if (!c[0].empty()) {
    Eigen::Vector3d lo, hi;
    for (int k = 0; k < 3; ++k) {
      auto& v = c[k];
      const std::size_t i0 = v.size() / 100, i1 = v.size() - 1 - v.size() / 100;
      std::nth_element(v.begin(), v.begin() + i0, v.end());
      lo[k] = v[i0];
      std::nth_element(v.begin(), v.begin() + i1, v.end());
      hi[k] = v[i1];
    }
    box.extend(lo);
    box.extend(hi);
  }
  for (const io::StampedPose& p : o.estimate) box.extend(p.T_world_cam.translation());
  return box;
}

void pointCameraAt(mrpt::opengl::COpenGLScene& scene, const Eigen::AlignedBox3d& box) {
  if (box.isEmpty()) return;
  const Eigen::Vector3d c = box.center(), e = box.sizes();
  mrpt::opengl::CCamera& cam = scene.getViewport("main")->getCamera();
  cam.setPointingAt(float(c.x()), float(c.y()), float(c.z()));
  // The viewers' perspective field of view is 30 degrees: at 1.7 x the larger horizontal
  // extent the box fills most of the view from 50 degrees above.
  cam.setZoomDistance(float(std::max(1.0, 1.7 * std::max({e.x(), e.y(), 0.5 * e.z()}))));
  cam.setElevationDegrees(50.0f);
  cam.setAzimuthDegrees(-60.0f);
  scene.enableFollowCamera(true);
}

std::shared_ptr<mrpt::opengl::COpenGLScene> runScene(const maps::SurfelStore& map,
                                                     const maps::SurfelVisualOptions& vis,
                                                     const RunOverlay& overlay) {
  auto scene = maps::surfelScene(map, vis);
  addRunOverlay(*scene, overlay);
  pointCameraAt(*scene, sceneBounds(map, overlay));
  return scene;
}

}  // namespace rasm::run
