#include "rasm/pipeline/LiveView.h"

#include <mrpt/config/CConfigFileBase.h>
#include <mrpt/gui/CDisplayWindow3D.h>
#include <mrpt/opengl/CGridPlaneXY.h>
#include <mrpt/opengl/COpenGLScene.h>
#include <mrpt/opengl/CSetOfObjects.h>

#include <chrono>
#include <cstdlib>

#include "rasm/core/Error.h"
#include "rasm/core/Log.h"
#include "rasm/pipeline/Mapper.h"
#include "rasm/pipeline/RunScene.h"

namespace rasm::pipeline {

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
  MRPT_LOAD_CONFIG_VAR(colouring, string, c, s);
  MRPT_LOAD_CONFIG_VAR(width, int, c, s);
  MRPT_LOAD_CONFIG_VAR(height, int, c, s);
  if (!(period_s >= 0.05 && period_s <= 60))
    throwInputError("[" + s + "] period_s", "expected 0.05 to 60 s");
  if (max_points < 1000) throwInputError("[" + s + "] max_points", "expected >= 1000");
  if (width < 64 || height < 64 || width > 8192 || height > 8192)
    throwInputError("[" + s + "] width / height", "expected 64 to 8192 pixels");
  (void)colouringOf(colouring);
}

void TViewParams::saveToConfigFile(mrpt::config::CConfigFileBase& c, const std::string& s) const {
  MRPT_SAVE_CONFIG_VAR(enabled, c, s);
  MRPT_SAVE_CONFIG_VAR(period_s, c, s);
  MRPT_SAVE_CONFIG_VAR(max_points, c, s);
  MRPT_SAVE_CONFIG_VAR(colouring, c, s);
  MRPT_SAVE_CONFIG_VAR(width, c, s);
  MRPT_SAVE_CONFIG_VAR(height, c, s);
}

struct LiveView::Window {
  mrpt::gui::CDisplayWindow3D win;
  maps::SurfelColouring colouring;
  Window(int w, int h, maps::SurfelColouring c) : win("rasm run: live view", w, h), colouring(c) {}
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
}

void LiveView::addFrame(const FrameResult& r, const CameraIntrinsics& K) {
  std::lock_guard<std::mutex> lock(m_mutex);
  m_path.push_back({r.timestamp_s, r.T_world_cam});
  m_K = K;
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

void LiveView::drawOnce(bool first) {
  const std::shared_ptr<const MapSnapshot> snap = m_mapper.snapshot();
  maps::SurfelStore thinned;
  const maps::SurfelStore* store = &snap->store;
  if (snap->store.size() > m_params.max_points) {
    const int stride = (snap->store.size() + m_params.max_points - 1) / m_params.max_points;
    thinned.copyThinnedFrom(snap->store, stride, 1.0f);
    store = &thinned;
  }
  RunOverlay overlay;
  {
    std::lock_guard<std::mutex> lock(m_mutex);
    overlay.estimate = m_path;
    overlay.K = m_K;
  }
  maps::SurfelVisualOptions vis;
  vis.colouring = m_window->colouring;
  auto scene = mrpt::opengl::COpenGLScene::Create();
  scene->insert(mrpt::opengl::CGridPlaneXY::Create(-10, 10, -10, 10, 0, 1));
  auto layer = mrpt::opengl::CSetOfObjects::Create();
  maps::surfelsToOpenGL(*store, vis, *layer);
  scene->insert(layer);
  addRunOverlay(*scene, overlay);
  if (first) pointCameraAt(*scene, sceneBounds(*store, overlay));
  mrpt::gui::CDisplayWindow3D& win = m_window->win;
  if (first) {
    const mrpt::opengl::CCamera cam = scene->getViewport("main")->getCamera();
    win.setCameraPointingToPoint(cam.getPointingAtX(), cam.getPointingAtY(), cam.getPointingAtZ());
    win.setCameraZoom(cam.getZoomDistance());
    win.setCameraAzimuthDeg(cam.getAzimuthDegrees());
    win.setCameraElevationDeg(cam.getElevationDegrees());
  }
  win.get3DSceneAndLock() = scene;
  win.unlockAccess3DScene();
  win.forceRepaint();
  ++m_updates;
}

}  // namespace rasm::pipeline
