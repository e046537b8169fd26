// `rasm view <run folder>`: a run's map (map.surfelmap, reloaded) with its camera paths, last
// camera and the exploration's candidate views as arrows (RunScene.h), in MRPT's 3-D window when
// a display exists (keys switch colour / segments / classes), else rendered offscreen to a PNG
// (mrpt::opengl::CFBORender, EGL: no X server needed).
#include <mrpt/gui/CDisplayWindow3D.h>
#include <mrpt/img/CImage.h>
#include <mrpt/io/CFileGZInputStream.h>
#include <mrpt/opengl/CFBORender.h>
#include <mrpt/opengl/CGridPlaneXY.h>
#include <mrpt/opengl/COpenGLScene.h>
#include <mrpt/opengl/CSetOfObjects.h>
#include <mrpt/serialization/CArchive.h>

#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <thread>

#include "Command.h"
#include "rasm/core/AtomicFile.h"
#include "rasm/core/Error.h"
#include "rasm/run/RunScene.h"
#include "rasm/surfel_map/CSurfelMap.h"

namespace {

namespace fs = std::filesystem;
using rasm::maps::SurfelColouring;

const rasm::app::CommandDecl kDecl{
    "view",
    "a run's map, paths and candidate views in a 3-D window, or offscreen to a PNG",
    {{"run folder", "the output folder of a `rasm run` (its map.surfelmap)"}},
    {{"colour", "rgb|segments|classes", "the surfels' colouring (default rgb)"},
     {"color", "rgb|segments|classes", "the same as --colour"},
     {"png", "out.png", "render offscreen to this PNG (without a display: view.png)"},
     {"size", "WIDTHxHEIGHT", "pixels, 16-8192 each (default 1280x960)"},
     {"no-views", "", "leave out the exploration's candidate views"}},
    "Shows the run's map (map.surfelmap) with the estimated camera path (orange), the ground\n"
    "truth (green), the last camera (white frustum) and the exploration's candidate views\n"
    "(arrows coloured by information gain, blue low .. red high, grey unreachable; goals driven\n"
    "to in magenta).\n"
    "With a display (DISPLAY set) and no --png: MRPT's 3-D window; keys 1 colour, 2 segments,\n"
    "3 classes, v views, p paths, q or Esc quits; the mouse turns (left), zooms (wheel) and pans\n"
    "(right). Without a display, or with --png: renders offscreen to out.png (default view.png),\n"
    "--size pixels (default 1280x960).\n"};

const char* const kLayers[] = {"colour", "segments", "classes"};

struct ViewArgs {
  std::string run, png;
  SurfelColouring colouring = SurfelColouring::Rgb;
  int width = 1280, height = 960;
  bool views = true;
};

ViewArgs viewArgsOf(const rasm::app::ParsedArgs& args) {
  ViewArgs v;
  v.run = args.positional("run folder");
  v.png = args.value("png");
  v.views = !args.has("no-views");
  for (const auto& [option, c] : args.given()) {
    if (option != "colour" && option != "color") continue;
    if (c == "rgb" || c == "colour")
      v.colouring = SurfelColouring::Rgb;
    else if (c == "segments")
      v.colouring = SurfelColouring::Segment;
    else if (c == "classes")
      v.colouring = SurfelColouring::Class;
    else
      throw rasm::InputError("--colour '" + c + "': expected rgb, segments or classes");
  }
  if (args.has("size")) {
    const std::string s = args.value("size");
    if (std::sscanf(s.c_str(), "%dx%d", &v.width, &v.height) != 2 || v.width < 16 ||
        v.height < 16 || v.width > 8192 || v.height > 8192)
      throw rasm::InputError("--size '" + s + "': expected WIDTHxHEIGHT, 16-8192 pixels each");
  }
  if (!fs::is_directory(v.run)) rasm::throwInputError(v.run, "is not a folder (a run folder)");
  return v;
}

std::unique_ptr<rasm::maps::CSurfelMap> loadMap(const std::string& run) {
  const std::string path = (fs::path(run) / "map.surfelmap").string();
  if (!fs::exists(path))
    rasm::throwInputError(path, "not found (rasm run writes it with [output] save_map = true)");
  auto map = std::make_unique<rasm::maps::CSurfelMap>();
  try {
    mrpt::io::CFileGZInputStream in(path);
    mrpt::serialization::archiveFrom(in) >> *map;
  } catch (const std::exception& e) {
    rasm::throwInputError(path, std::string("cannot be read as a rasm surfel map: ") + e.what());
  }
  return map;
}

/// The map in its three colourings (one visible), the grid and the run's overlay.
mrpt::opengl::COpenGLScene::Ptr viewScene(const rasm::maps::CSurfelMap& map,
                                          const rasm::run::RunOverlay& overlay,
                                          SurfelColouring shown) {
  auto scene = mrpt::opengl::COpenGLScene::Create();
  scene->insert(mrpt::opengl::CGridPlaneXY::Create(-10, 10, -10, 10, 0, 1));
  const SurfelColouring colourings[] = {SurfelColouring::Rgb, SurfelColouring::Segment,
                                        SurfelColouring::Class};
  for (int k = 0; k < 3; ++k) {
    rasm::maps::SurfelVisualOptions vis = map.renderingOptions.visual;
    vis.colouring = colourings[k];
    auto layer = mrpt::opengl::CSetOfObjects::Create();
    layer->setName(kLayers[k]);
    rasm::maps::surfelsToOpenGL(map.store(), vis, *layer);
    layer->setVisibility(colourings[k] == shown);
    scene->insert(layer);
  }
  rasm::run::addRunOverlay(*scene, overlay);
  rasm::run::pointCameraAt(*scene, rasm::run::sceneBounds(map.store(), overlay));
  return scene;
}

void renderPng(const mrpt::opengl::COpenGLScene& scene, const ViewArgs& v) {
  const std::string path = v.png.empty() ? "view.png" : v.png;
  mrpt::opengl::CFBORender render(v.width, v.height);
  // CFBORender renders from a camera of its own, not the viewport's: hand it the scene's.
  render.setCamera(scene, scene.getViewport("main")->getCamera());
  mrpt::img::CImage img;
  render.render_RGB(scene, img);
  try {  // MRPT picks the format by the extension
    rasm::writeThroughTemporary(
        path, [&](const std::string& temp) { return img.saveToFile(temp); }, ".part.png");
  } catch (const std::runtime_error& e) {
    rasm::throwInputError(path, std::string("cannot be written: ") + e.what());
  }
  std::printf("wrote %s (%dx%d)\n", path.c_str(), v.width, v.height);
}

void showWindow(const mrpt::opengl::COpenGLScene::Ptr& scene, const ViewArgs& v) {
  mrpt::gui::CDisplayWindow3D win("rasm view: " + v.run, v.width, v.height);
  const mrpt::opengl::CCamera cam = scene->getViewport("main")->getCamera();
  win.get3DSceneAndLock() = scene;
  win.unlockAccess3DScene();
  win.setCameraPointingToPoint(cam.getPointingAtX(), cam.getPointingAtY(), cam.getPointingAtZ());
  win.setCameraZoom(cam.getZoomDistance());
  win.setCameraAzimuthDeg(cam.getAzimuthDegrees());
  win.setCameraElevationDeg(cam.getElevationDegrees());
  win.addTextMessage(5, 5, "1 colour  2 segments  3 classes  v views  p paths  q quit", 0);
  win.repaint();
  auto toggle = [&](const char* name) {
    if (auto o = scene->getByName(name)) o->setVisibility(!o->isVisible());
  };
  while (win.isOpen()) {
    if (win.keyHit()) {
      const int key = win.getPushedKey();
      if (key == 'q' || key == 'Q' || key == 27) break;
      win.get3DSceneAndLock();
      if (key >= '1' && key <= '3')
        for (int k = 0; k < 3; ++k)
          if (auto o = scene->getByName(kLayers[k])) o->setVisibility(k == key - '1');
      if (key == 'v' || key == 'V') toggle("candidate_views");
      if (key == 'p' || key == 'P') toggle("trajectory"), toggle("groundtruth");
      win.unlockAccess3DScene();
      win.repaint();
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(30));
  }
}

int view(const rasm::app::ParsedArgs& args) {
  const ViewArgs v = viewArgsOf(args);
  const auto map = loadMap(v.run);
  rasm::run::RunOverlay overlay = rasm::run::readRunOverlay(v.run);
  if (!v.views) overlay.views.clear();
  const auto scene = viewScene(*map, overlay, v.colouring);
  const char* display = std::getenv("DISPLAY");
  if (!v.png.empty() || !display || !*display)
    renderPng(*scene, v);
  else
    showWindow(scene, v);
  return 0;
}

const rasm::app::Registrar reg{kDecl, &view};

}  // namespace
