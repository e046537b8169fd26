#include "rasm/run/LiveView.h"

#include <mrpt/config/CConfigFileBase.h>
#include <mrpt/gui/CDisplayWindow3D.h>
#include <mrpt/opengl/CGridPlaneXY.h>
#include <mrpt/opengl/COpenGLScene.h>
#include <mrpt/opengl/CSetOfObjects.h>

#include <chrono>
#include <cmath>
#include <cstdlib>
#include <vector>

#include "rasm/core/Error.h"
#include "rasm/core/Log.h"
#include "rasm/pipeline/Mapper.h"
#include "rasm/run/RunScene.h"

namespace rasm::run {

using autonomy::SceneView;
using pipeline::FrameResult;
using pipeline::Mapper;
using pipeline::MapSnapshot;

namespace {

maps::SurfelColouring colouringOf(const std::string& name) {
  if (name == "colour") return maps::SurfelColouring::Rgb;
  if (name == "segments") return maps::SurfelColouring::Segment;
  if (name == "classes") return maps::SurfelColouring::Class;
  throwInputError("[view] colouring", "is '" + name + "'; expected colour, segments or classes");
}

}  // namespace

void TViewParams::loadFromConfigFile(const mrpt::config::CConfigFileBase& c, const std::string& s) {
  MRPT_LOAD_CONFIG_VAR(enabled, bool, c, s);
  MRPT_LOAD_CONFIG_VAR(period_s, double, c, s);
  MRPT_LOAD_CONFIG_VAR(max_points, int, c, s);
  MRPT_LOAD_CONFIG_VAR(point_size, double, c, s);
  MRPT_LOAD_CONFIG_VAR(colouring, string, c, s);
  MRPT_LOAD_CONFIG_VAR(width, int, c, s);
  MRPT_LOAD_CONFIG_VAR(height, int, c, s);
  if (!(period_s >= 0.05 && period_s <= 60))
    throwInputError("[" + s + "] period_s", "expected 0.05 to 60 s");
  if (max_points < 1000) throwInputError("[" + s + "] max_points", "expected >= 1000");
  if (!(point_size >= 1.0 && point_size <= 20.0))
    throwInputError("[" + s + "] point_size", "expected 1 to 20 pixels");
  if (width < 64 || height < 64 || width > 8192 || height > 8192)
    throwInputError("[" + s + "] width / height", "expected 64 to 8192 pixels");
  (void)colouringOf(colouring);
}

void TViewParams::saveToConfigFile(mrpt::config::CConfigFileBase& c, const std::string& s) const {
  MRPT_SAVE_CONFIG_VAR(enabled, c, s);
  MRPT_SAVE_CONFIG_VAR(period_s, c, s);
  MRPT_SAVE_CONFIG_VAR(max_points, c, s);
  MRPT_SAVE_CONFIG_VAR(point_size, c, s);
  MRPT_SAVE_CONFIG_VAR(colouring, c, s);
  MRPT_SAVE_CONFIG_VAR(width, c, s);
  MRPT_SAVE_CONFIG_VAR(height, c, s);
}

namespace {

/// MRPT 2.5's CDisplayWindow3D cannot be destroyed safely while wx may still paint it: its
/// destructor returns once the wx window has handled its close event, but wx deletes the
/// window's canvas only later (on idle), and a paint in between (a repaint this view asked for,
/// an expose) renders through the canvas's raw pointer to the freed CDisplayWindow3D. Valgrind
/// shows OnPreRender -> get3DSceneAndLock on freed memory and a shared_ptr released twice; under
/// load the run aborted with "double free or corruption" after its last frame. So the window is
/// closed here (the protected destroyWxWindow, as the destructor would) and the object is kept
/// until the process ends, its scene emptied (keepUntilExit).
class ClosableWindow3D : public mrpt::gui::CDisplayWindow3D {
 public:
  using CDisplayWindow3D::CDisplayWindow3D;
  void closeWindow() { destroyWxWindow(); }
};

/// Keeps closed windows reachable until the process ends (never destroyed, see above).
void keepUntilExit(ClosableWindow3D* win) {
  static std::mutex mutex;
  static auto* kept = new std::vector<ClosableWindow3D*>();
  std::lock_guard<std::mutex> lock(mutex);
  kept->push_back(win);
}

}  // namespace

struct LiveView::Window {
  ClosableWindow3D& win;  ///< closed and kept by ~Window, never destroyed (ClosableWindow3D)
  maps::SurfelColouring colouring;
  /// The camera frameCamera last set (pointing-at x, y, z; zoom; azimuth, elevation in deg).
  struct Camera {
    float x = 0, y = 0, z = 0, zoom = 0, azimuth_deg = 0, elevation_deg = 0;
    bool sameAs(const Camera& o) const {
      const auto near = [](float a, float b) {
        return std::abs(a - b) <= 1e-3f * (1 + std::abs(b));
      };
      return near(x, o.x) && near(y, o.y) && near(z, o.z) && near(zoom, o.zoom) &&
             near(azimuth_deg, o.azimuth_deg) && near(elevation_deg, o.elevation_deg);
    }
  } camera_set;
  Eigen::AlignedBox3d framed;  ///< the map's box the camera was last pointed at
  bool user_moved_camera = false;
  Window(int w, int h, maps::SurfelColouring c)
      : win(*new ClosableWindow3D("rasm run: live view", w, h)), colouring(c) {}
  ~Window() {
    win.closeWindow();
    win.get3DSceneAndLock() = mrpt::opengl::COpenGLScene::Create();  // the map's memory goes
    win.unlockAccess3DScene();
    keepUntilExit(&win);
  }
  Window(const Window&) = delete;
  Window& operator=(const Window&) = delete;
};

void LiveView::requireDisplay() {
  const char* display = std::getenv("DISPLAY");
  if (!display || !*display)
    throwInputError("[view] enabled",
                    "needs a display (DISPLAY is not set): run without --view, look at the run "
                    "afterwards with rasm view FOLDER, or run under xvfb-run");
}

LiveView::LiveView(const Mapper& mapper, const TViewParams& params)
    : m_mapper(mapper), m_params(params) {
  requireDisplay();
  m_window = std::make_unique<Window>(params.width, params.height, colouringOf(params.colouring));
  m_window->win.addTextMessage(5, 5, "1 colour  2 segments  3 classes  p paths", 0);
  m_thread = std::thread([this] { loop(); });
}

LiveView::~LiveView() {
  m_stop = true;
  if (m_thread.joinable()) m_thread.join();
  try {
    // The map as the run left it, unless the user closed the window.
    if (m_window->win.isOpen()) drawOnce(m_updates == 0);
  } catch (const std::exception& e) {
    log::warning(std::string("live view: ") + e.what());
  }
  log::debug("live view: " + std::to_string(m_updates.load()) + " snapshots drawn; the last " +
             m_last_drawn);
}

void LiveView::addFrame(const FrameResult& r, const CameraIntrinsics& K) {
  std::lock_guard<std::mutex> lock(m_mutex);
  m_path.push_back({r.timestamp_s, r.T_world_cam});
  m_K = K;
}

bool LiveView::overlayDue() const {
  std::lock_guard<std::mutex> lock(m_mutex);
  return std::chrono::steady_clock::now() - m_overlay_t >=
         std::chrono::milliseconds(int(m_params.period_s * 1000));
}

void LiveView::setOverlay(std::vector<SceneView> views, std::vector<ObjectBox> objects) {
  std::lock_guard<std::mutex> lock(m_mutex);
  m_views = std::move(views);
  m_objects = std::move(objects);
  m_overlay_t = std::chrono::steady_clock::now();
}

void LiveView::loop() {
  auto next = std::chrono::steady_clock::now();
  while (!m_stop) {
    if (!m_window->win.isOpen()) return;  // closed by the user: the run goes on
    if (m_window->win.keyHit()) {
      const int key = m_window->win.getPushedKey();
      if (key == '1') m_window->colouring = maps::SurfelColouring::Rgb;
      if (key == '2') m_window->colouring = maps::SurfelColouring::Segment;
      if (key == '3') m_window->colouring = maps::SurfelColouring::Class;
      if (key == 'p' || key == 'P') {
        auto& scene = m_window->win.get3DSceneAndLock();
        for (const char* name : {"trajectory", "groundtruth"})
          if (auto o = scene->getByName(name)) o->setVisibility(!o->isVisible());
        m_window->win.unlockAccess3DScene();
        m_window->win.forceRepaint();
      }
    }
    if (std::chrono::steady_clock::now() >= next) {
      drawOnce(m_updates == 0);
      next = std::chrono::steady_clock::now() +
             std::chrono::milliseconds(int(m_params.period_s * 1000));
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(30));
  }
}

/// The window's camera follows the map: it is pointed at the whole map (pointCameraAt) on the
/// first snapshot and again whenever the map has grown out of the box it framed, until the user
/// moves the camera (the window's camera is then no longer the one set here).
void LiveView::frameCamera(mrpt::opengl::COpenGLScene& scene, const Eigen::AlignedBox3d& box,
                           bool first) {
  mrpt::gui::CDisplayWindow3D& win = m_window->win;
  if (!first && m_window->user_moved_camera) return;
  if (!first) {
    float x = 0, y = 0, z = 0;
    win.getCameraPointingToPoint(x, y, z);
    const Window::Camera now{
        x, y, z, win.getCameraZoom(), win.getCameraAzimuthDeg(), win.getCameraElevationDeg()};
    if (!now.sameAs(m_window->camera_set)) {
      m_window->user_moved_camera = true;
      return;
    }
    // Grown: a corner of the map more than 20% of the framed box's size outside it.
    const Eigen::Vector3d margin = 0.2 * m_window->framed.sizes();
    Eigen::AlignedBox3d grown = m_window->framed;
    grown.extend(m_window->framed.min() - margin).extend(m_window->framed.max() + margin);
    if (box.isEmpty() || grown.contains(box)) return;
  }
  pointCameraAt(scene, box);
  const mrpt::opengl::CCamera cam = scene.getViewport("main")->getCamera();
  m_window->camera_set = {cam.getPointingAtX(),    cam.getPointingAtY(),
                          cam.getPointingAtZ(),    cam.getZoomDistance(),
                          cam.getAzimuthDegrees(), cam.getElevationDegrees()};
  m_window->framed = box;
  win.setCameraPointingToPoint(cam.getPointingAtX(), cam.getPointingAtY(), cam.getPointingAtZ());
  win.setCameraZoom(cam.getZoomDistance());
  win.setCameraAzimuthDeg(cam.getAzimuthDegrees());
  win.setCameraElevationDeg(cam.getElevationDegrees());
}

void LiveView::drawOnce(bool first) {
  m_mapper.snapshotThinnedInto(m_snapshot, m_params.max_points);
  const maps::SurfelStore* store = &m_snapshot.store;
  RunOverlay overlay;
  {
    std::lock_guard<std::mutex> lock(m_mutex);
    overlay.estimate = m_path;
    overlay.K = m_K;
    overlay.views = m_views;
    overlay.objects = m_objects;
  }
  int goals = 0;
  for (const SceneView& v : overlay.views) goals += v.goal;
  m_last_drawn = std::to_string(store->size()) + " surfels, " +
                 std::to_string(overlay.views.size()) + " views (" + std::to_string(goals) +
                 " goals), " + std::to_string(overlay.objects.size()) + " objects";
  maps::SurfelVisualOptions vis;
  vis.colouring = m_window->colouring;
  vis.point_size = float(m_params.point_size);
  auto scene = mrpt::opengl::COpenGLScene::Create();
  scene->insert(mrpt::opengl::CGridPlaneXY::Create(-10, 10, -10, 10, 0, 1));
  auto layer = mrpt::opengl::CSetOfObjects::Create();
  maps::surfelsToOpenGL(*store, vis, *layer);
  scene->insert(layer);
  addRunOverlay(*scene, overlay);
  frameCamera(*scene, sceneBounds(*store, overlay), first);
  mrpt::gui::CDisplayWindow3D& win = m_window->win;
  win.get3DSceneAndLock() = scene;
  win.unlockAccess3DScene();
  win.forceRepaint();
  ++m_updates;
}

}  // namespace rasm::run
