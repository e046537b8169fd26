#pragma once
// The live 3-D view of a run (`rasm run --view`, [view] enabled): MRPT's CDisplayWindow3D shows
// the map as it grows, the camera's path and the camera, from snapshots of the map taken on a
// thread of its own every period_s (Mapper::snapshotThinnedInto: every k-th surfel up to
// max_points, copied straight from the map; the mapping thread waits only when a copy outlasts
// its read phase); over it what the run does, as `rasm view` shows it after the run (RunScene.h):
// "trajectory", "camera", "candidate_views" (an exploring run's last plan and its goals) and
// "objects" (the boxes and "class probability" labels of the objects objects.json would list
// now). The camera follows the map as it grows until the user moves it. Keys: 1 colour,
// 2 segments, 3 classes (the next snapshot is drawn that way), p paths. Closing the window ends
// the view, not the run.
// Headless (no DISPLAY) it refuses to start with an InputError naming [view] enabled. Tested
// under Xvfb (tests/scripts/test_live_view.sh: the window, grabbed with xwd, is not blank; MRPT's
// own window capture reads black under Xvfb's software GL).

#include <mrpt/config/CLoadableOptions.h>

#include <atomic>
#include <chrono>
#include <memory>
#include <mutex>
#include <string>
#include <thread>

#include "rasm/core/CameraIntrinsics.h"
#include "rasm/io/Trajectory.h"
#include "rasm/pipeline/FrameContext.h"
#include "rasm/pipeline/Mapper.h"
#include "rasm/run/RunScene.h"

namespace mrpt::opengl {
class COpenGLScene;
}

namespace rasm::run {

/// [view]
struct TViewParams : mrpt::config::CLoadableOptions {
  bool enabled = false;   ///< open the live window (rasm run --view)
  double period_s = 0.5;  ///< a new snapshot this often (s)
  /// Surfels drawn at most (every k-th beyond), as points of point_size pixels. Under Xvfb the
  /// window is drawn by Mesa's software renderer on the mapping's cores, at a cost that grows with
  /// the points: 300 k slowed the mapping by 21-22%, 100 k by 7-8% (docs/viewing.md "Cost").
  int max_points = 100000;
  double point_size = 3.0;
  std::string colouring = "colour";  ///< colour | segments | classes (keys 1-3 switch it)
  int width = 1024, height = 768;    ///< window size (pixels)

  void loadFromConfigFile(const mrpt::config::CConfigFileBase& c, const std::string& s) override;
  void saveToConfigFile(mrpt::config::CConfigFileBase& c, const std::string& s) const override;
};

class LiveView {
 public:
  /// InputError naming [view] enabled when there is no display (DISPLAY unset): MappingRun
  /// calls it when it loads its configuration, before anything is written.
  static void requireDisplay();
  /// Opens the window and starts the thread (requireDisplay first).
  LiveView(const pipeline::Mapper& mapper, const TViewParams& params);
  /// Stops the thread and draws the map as the run left it (the window closes with the object).
  ~LiveView();
  LiveView(const LiveView&) = delete;
  LiveView& operator=(const LiveView&) = delete;

  /// A frame's result (mapping thread): its pose joins the drawn path.
  void addFrame(const pipeline::FrameResult& r, const CameraIntrinsics& K);
  /// Whether the overlay is due for an update (period_s since the last one): the mapping thread
  /// asks before it collects the views and objects.
  bool overlayDue() const;
  /// The exploring run's views (candidates of the last plan, goals) and the objects to draw over
  /// the map from the next snapshot on (mapping thread).
  void setOverlay(std::vector<autonomy::SceneView> views, std::vector<ObjectBox> objects);
  /// Snapshots drawn so far.
  int updates() const { return m_updates.load(); }

 private:
  struct Window;
  void loop();
  void drawOnce(bool first);
  void frameCamera(mrpt::opengl::COpenGLScene& scene, const Eigen::AlignedBox3d& box, bool first);

  const pipeline::Mapper& m_mapper;
  TViewParams m_params;
  std::unique_ptr<Window> m_window;
  mutable std::mutex m_mutex;  ///< guards m_path, m_K, m_views, m_objects and m_overlay_t
  io::Trajectory m_path;
  CameraIntrinsics m_K;
  std::vector<autonomy::SceneView> m_views;
  std::vector<ObjectBox> m_objects;
  std::chrono::steady_clock::time_point m_overlay_t;
  pipeline::MapSnapshot m_snapshot;  ///< the view thread's, reused from snapshot to snapshot
  std::string m_last_drawn;          ///< what the last snapshot drew (the run's log at the end)
  std::atomic<bool> m_stop{false};
  std::atomic<int> m_updates{0};
  std::thread m_thread;
};

}  // namespace rasm::run
