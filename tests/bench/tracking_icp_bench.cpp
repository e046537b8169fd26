// Benchmark of the II-C tracker: milliseconds per IcpTracker::align() call at 640x480 (3 levels,
// default iterations), the model being the previous frame's maps in the world frame (what the
// Mapper's render provides). Frames come from an analytic room scene along a smooth camera path
// (noise-free: few iterations), or with --tum from a sequence folder read by io::openFrameSource
// (TUM-format or 7-Scenes; real depth noise: more iterations before the increments fall below
// the convergence limits).
//   bench_tracking_icp [--threads 2] [--frames 30] [--repeats 5] [--stride 2] [--noise_mm 0]
//                      [--cuda off] [--tum <TUM-format or 7-Scenes folder>]
// Prints one JSON line: {"bench":"tracking_icp","ms_per_track_median":...,...}. The frame
// pyramid (buildFramePyramid, core) is timed separately: the Mapper builds it once per frame for
// every stage.
#include <omp.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <numeric>
#include <string>
#include <vector>

#include "rasm/core/FrameProcessing.h"
#include "rasm/core/SE3.h"
#include "rasm/io/FrameSource.h"
#include "rasm/tracking/IcpTracker.h"
#include "tracking/SyntheticScene.h"

using namespace rasm;
using Clock = std::chrono::steady_clock;

static double msSince(Clock::time_point t0) {
  return std::chrono::duration<double, std::milli>(Clock::now() - t0).count();
}

/// Depth and ground truth of a sequence folder (TUM-format or 7-Scenes) through the product's
/// reader (io::openFrameSource, as `rasm run`); K from the source. False when unreadable.
static bool loadSequence(const std::string& dir, CameraIntrinsics& K,
                         std::vector<Image<float>>& depth, std::vector<Eigen::Isometry3d>& gt) {
  try {
    const std::unique_ptr<io::FrameSource> src = io::openFrameSource(dir);
    while (std::optional<RgbdFrame> f = src->next()) {
      if (!f->gt_T_world_cam) continue;
      K = f->intrinsics;
      depth.push_back(std::move(f->depth_m));
      gt.push_back(*f->gt_T_world_cam);
    }
  } catch (const std::exception& e) {
    std::fprintf(stderr, "%s\n", e.what());
    return false;
  }
  return !depth.empty();
}

int main(int argc, char** argv) {
  int threads = 2, frames = 30, repeats = 5, stride = 2;
  double noise_mm = 0.0;
  bool use_cuda = false;
  std::string tum;
  for (int i = 1; i + 1 < argc; i += 2) {
    const std::string k = argv[i], v = argv[i + 1];
    if (k == "--threads")
      threads = std::stoi(v);
    else if (k == "--frames")
      frames = std::stoi(v);
    else if (k == "--repeats")
      repeats = std::stoi(v);
    else if (k == "--stride")
      stride = std::stoi(v);
    else if (k == "--noise_mm")
      noise_mm = std::stod(v);
    else if (k == "--cuda")
      use_cuda = v == "on";
    else if (k == "--tum")
      tum = v;
    else {
      std::fprintf(stderr, "unknown option %s\n", k.c_str());
      return 2;
    }
  }
  omp_set_num_threads(threads);
  CameraIntrinsics K = CameraIntrinsics::preset("kinect_v1");
  std::vector<Eigen::Isometry3d> gt;
  std::vector<Image<float>> depth;
  if (!tum.empty()) {
    if (!loadSequence(tum, K, depth, gt)) {
      std::fprintf(stderr, "cannot read a sequence with ground truth in %s\n", tum.c_str());
      return 1;
    }
  } else {
    // Camera path: 1 cm and 0.5 deg per frame (a robot at 0.3 m/s, 30 Hz).
    const test::Scene scene = test::Scene::room();
    gt.push_back(test::lookAt({0.3, -1.5, 1.3}, {-0.2, 0.8, 0.5}));
    for (int i = 1; i <= frames; ++i)
      gt.push_back(gt.back() * test::motion({0.01, 0.0, 0.004}, {0.1, 1, 0}, 0.5));
    for (std::size_t i = 0; i < gt.size(); ++i)
      depth.push_back(scene.render(K, gt[i], noise_mm * 1e-3, unsigned(i + 1)));
  }
  std::vector<std::vector<FrameLevel>> pyr(gt.size());
  std::vector<double> pyr_ms;
  for (int r = 0; r < repeats; ++r)
    for (std::size_t i = 0; i < gt.size(); ++i) {
      const auto t0 = Clock::now();
      buildFramePyramid(depth[i], K, 3, pyr[i]);
      pyr_ms.push_back(msSince(t0));
    }
  std::vector<test::WorldMaps> model;
  for (std::size_t i = 0; i < gt.size(); ++i) model.emplace_back(pyr[i][0], gt[i]);

  tracking::TTrackingParams P;
  P.level0_pixel_stride = stride;
  P.use_cuda = use_cuda;
  tracking::IcpTracker tracker(P);
  std::vector<double> ms;
  double iterations = 0, err_t = 0, err_r = 0;
  int ok = 0, calls = 0;
  for (int r = 0; r < repeats; ++r)
    for (std::size_t i = 1; i < gt.size(); ++i) {
      tracking::ModelMaps m;
      m.vertex_world = model[i - 1].vertex.view();
      m.normal_world = model[i - 1].normal.view();
      m.K = K;
      m.T_world_model = gt[i - 1];
      const auto t0 = Clock::now();
      const tracking::TrackingResult res = tracker.align(pyr[i], m, gt[i - 1]);
      ms.push_back(msSince(t0));
      ++calls;
      ok += res.ok;
      iterations += res.iterations;
      err_t = std::max(err_t, translationDistance(gt[i], res.T_world_cam));
      err_r = std::max(err_r, rotationAngle(gt[i], res.T_world_cam));
    }
  auto median = [](std::vector<double> v) {
    std::sort(v.begin(), v.end());
    return v[v.size() / 2];
  };
  std::printf(
      "{\"bench\":\"tracking_icp\",\"data\":\"%s\",\"width\":%d,\"height\":%d,\"threads\":%d,"
      "\"levels\":%d,"
      "\"iterations\":[%d,%d,%d],\"level0_pixel_stride\":%d,\"noise_mm\":%.2f,\"cuda\":%s,"
      "\"calls\":%d,"
      "\"ms_per_track_median\":%.3f,\"ms_per_track_mean\":%.3f,\"ms_per_track_min\":%.3f,"
      "\"ms_frame_pyramid_median\":%.3f,\"iterations_mean\":%.2f,\"ok_fraction\":%.3f,"
      "\"max_error_mm\":%.3f,\"max_error_deg\":%.4f}\n",
      tum.empty() ? "synthetic_room" : "tum", K.width, K.height, threads, P.num_levels,
      P.iterations[0], P.iterations[1], P.iterations[2], stride, noise_mm,
      use_cuda ? "true" : "false", calls, median(ms),
      std::accumulate(ms.begin(), ms.end(), 0.0) / ms.size(),
      *std::min_element(ms.begin(), ms.end()), median(pyr_ms), iterations / calls,
      double(ok) / calls, err_t * 1e3, err_r * 180.0 / M_PI);
  return 0;
}
