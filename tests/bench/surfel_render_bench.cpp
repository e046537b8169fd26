// Benchmark of the surfel map renderer (II-A splatting, II-D 4x point index map) at 640x480 on a
// synthetic room map of ~1M surfels (floor, ceiling, 4 walls, a few boxes sampled on a regular
// grid), the camera seeing ~300k of them. Reports milliseconds per render (median of repeats),
// the culling counts, bytes per surfel and the peak resident memory per million surfels.
//   bench_surfel_render [--threads 2] [--repeats 20] [--spacing_cm 1.5] [--cuda off]
// Prints one JSON line: {"bench":"surfel_render",...}.
#include <omp.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <ctime>
#include <fstream>
#include <string>
#include <vector>

#include "rasm/compute/Device.h"
#include "rasm/surfel_map/SurfelRenderer.h"

using namespace rasm;
using namespace rasm::maps;
using Clock = std::chrono::steady_clock;

namespace {

double msSince(Clock::time_point t0) {
  return std::chrono::duration<double, std::milli>(Clock::now() - t0).count();
}
/// Process CPU time (all threads), ms: with --threads 1 it is the single-core cost even when the
/// machine is shared (wall time then includes waiting for a core).
double cpuMs() {
  return 1000.0 * double(std::clock()) / CLOCKS_PER_SEC;
}

double median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  return v.empty() ? 0.0 : v[v.size() / 2];
}

/// Peak resident set size (VmHWM) in bytes.
double peakRssBytes() {
  std::ifstream f("/proc/self/status");
  std::string line;
  while (std::getline(f, line))
    if (line.rfind("VmHWM:", 0) == 0) return std::stod(line.substr(6)) * 1024.0;
  return 0.0;
}

/// Axis-aligned rectangle sampled every `s` metres (fixed axis `axis` at `c`).
void addRect(SurfelStore& store, int axis, float c, float a0, float a1, float b0, float b1,
             const Vec3f& n, float s, Bgr8 col) {
  const int u = (axis + 1) % 3, v = (axis + 2) % 3;
  const int first = store.allocate(int((a1 - a0) / s + 1) * int((b1 - b0) / s + 1));
  const SurfelArrays arr = store.arrays();
  int i = first;
  for (int ia = 0; ia <= int((a1 - a0) / s) && i < arr.size; ++ia)
    for (int ib = 0; ib <= int((b1 - b0) / s) && i < arr.size; ++ib, ++i) {
      Vec3f p;
      p[axis] = c;
      p[u] = a0 + ia * s;
      p[v] = b0 + ib * s;
      arr.pos_conf[i] = Vec4f(p.x(), p.y(), p.z(), 20.0f);
      arr.normal_radius[i] = Vec4f(n.x(), n.y(), n.z(), 0.75f * s);
      arr.colour_flags[i] = packColour(col, kSurfelStable);
      arr.basis[i] = Vec3f::UnitX();
      arr.segment[i] = 1 + axis;
    }
}

}  // namespace

int main(int argc, char** argv) {
  int threads = 2, repeats = 20;
  float spacing_cm = 1.5f;
  bool use_cuda = false;
  for (int i = 1; i + 1 < argc; i += 2) {
    const std::string k = argv[i], v = argv[i + 1];
    if (k == "--threads")
      threads = std::stoi(v);
    else if (k == "--repeats")
      repeats = std::stoi(v);
    else if (k == "--spacing_cm")
      spacing_cm = std::stof(v);
    else if (k == "--cuda")
      use_cuda = v == "on";
    else {
      std::fprintf(stderr, "unknown option %s\n", k.c_str());
      return 2;
    }
  }
  omp_set_num_threads(threads);
  if (use_cuda && !compute::cudaAvailability().available) {
    std::fprintf(stderr, "CUDA: %s\n", compute::cudaAvailability().reason.c_str());
    return 3;
  }
  const double rss0 = peakRssBytes();

  // Room 8 x 6 x 3 m (x, y, z up) plus three boxes.
  const float s = spacing_cm * 0.01f;
  SurfelStore store;
  const auto t_build = Clock::now();
  addRect(store, 2, 0.0f, -4, 4, -3, 3, {0, 0, 1}, s, {90, 120, 140});    // floor
  addRect(store, 2, 3.0f, -4, 4, -3, 3, {0, 0, -1}, s, {230, 230, 230});  // ceiling
  addRect(store, 0, -4.0f, -3, 3, 0, 3, {1, 0, 0}, s, {200, 180, 160});   // walls
  addRect(store, 0, 4.0f, -3, 3, 0, 3, {-1, 0, 0}, s, {200, 180, 160});
  addRect(store, 1, -3.0f, 0, 3, -4, 4, {0, 1, 0}, s, {160, 200, 180});
  addRect(store, 1, 3.0f, 0, 3, -4, 4, {0, -1, 0}, s, {160, 200, 180});
  for (int b = 0; b < 3; ++b) {
    const float x0 = 0.5f + b, y0 = -1.0f + b * 0.8f;
    addRect(store, 0, x0, y0, y0 + 0.5f, 0.0f, 0.6f, {-1, 0, 0}, s, {40, 40, 200});
    addRect(store, 2, 0.6f, x0, x0 + 0.5f, y0, y0 + 0.5f, {0, 0, 1}, s, {40, 200, 40});
  }
  store.indexAppended();
  const double build_ms = msSince(t_build);

  // Optical camera at (-2.5, 0, 1.2) looking along world +x, 10 deg down.
  const CameraIntrinsics K = CameraIntrinsics::preset("kinect_v1");
  Eigen::Matrix3d R_world_cam;
  R_world_cam << 0, 0, 1, -1, 0, 0, 0, -1, 0;
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.linear() = R_world_cam *
               Eigen::AngleAxisd(-10.0 * M_PI / 180.0, Eigen::Vector3d::UnitX()).toRotationMatrix();
  T.translation() = Eigen::Vector3d(-2.5, 0.0, 1.2);

  SurfelRenderer renderer(use_cuda ? compute::Backend::Cuda : compute::Backend::Cpu);
  RenderedMaps maps;
  IndexMap4x index4x;
  RenderStats st_splat, st_track, st_4x;
  RenderOptions all;
  all.max_depth_m = 10.0f;
  RenderOptions track = all;  // what the tracker asks for: stable, vertex + normal
  track.stable_only = true;
  track.outputs = kRenderVertex | kRenderNormal;
  RenderOptions pts = all;
  pts.splat = false;
  std::vector<double> t_splat, t_track, t_points, t_4x, t_cull, c_splat, c_track, c_4x;
  std::vector<int> visible;
  for (int r = 0; r < repeats + 2; ++r) {  // 2 warm-up renders
    auto t0 = Clock::now();
    double c0 = cpuMs();
    renderer.render(store, T, K, all, maps, &st_splat);
    const double a = msSince(t0), ca = cpuMs() - c0;
    t0 = Clock::now();
    c0 = cpuMs();
    renderer.render(store, T, K, track, maps, &st_track);
    const double b = msSince(t0), cb = cpuMs() - c0;
    t0 = Clock::now();
    renderer.render(store, T, K, pts, maps);
    const double c = msSince(t0);
    t0 = Clock::now();
    c0 = cpuMs();
    renderer.renderIndexMap4x(store, T, K, all, index4x, &st_4x);
    const double d = msSince(t0), cd = cpuMs() - c0;
    t0 = Clock::now();
    renderer.collectVisible(store, T, K, all, all.max_splat_radius_px, visible);
    const double e = msSince(t0);
    if (r < 2) continue;
    t_splat.push_back(a);
    t_track.push_back(b);
    t_points.push_back(c);
    t_4x.push_back(d);
    t_cull.push_back(e);
    c_splat.push_back(ca);
    c_track.push_back(cb);
    c_4x.push_back(cd);
  }
  int covered = 0;
  for (int y = 0; y < K.height; ++y)
    for (int x = 0; x < K.width; ++x) covered += maps.index(x, y) >= 0;

  const double n = store.size();
  const double peak = peakRssBytes();
  std::printf(
      "{\"bench\":\"surfel_render\",\"threads\":%d,\"backend\":\"%s\",\"width\":%d,\"height\":%d,"
      "\"surfels\":%d,\"blocks\":%d,\"blocks_visited\":%d,\"surfels_tested\":%lld,\"surfels_in_"
      "view\":%lld,"
      "\"pixels_covered_points\":%d,\"ms_build_map\":%.1f,\"ms_splat_all_outputs\":%.2f,"
      "\"ms_splat_tracking\":%.2f,\"ms_points\":%.2f,\"ms_index4x\":%.2f,\"ms_cull_collect\":%.2f,"
      "\"cpu_ms_splat_all_outputs\":%.2f,\"cpu_ms_splat_tracking\":%.2f,\"cpu_ms_index4x\":%.2f,"
      "\"bytes_per_surfel_arrays\":%zu,\"bytes_per_surfel_index\":%zu,\"bytes_per_surfel_held\":%."
      "1f,"
      "\"peak_rss_mb\":%.1f,\"peak_rss_mb_per_million_surfels\":%.1f}\n",
      threads, use_cuda ? "cuda" : "cpu", K.width, K.height, store.size(), st_splat.blocks_total,
      st_splat.blocks_visited, st_splat.surfels_tested, st_splat.surfels_drawn, covered, build_ms,
      median(t_splat), median(t_track), median(t_points), median(t_4x), median(t_cull),
      median(c_splat), median(c_track), median(c_4x),
      SurfelStore::bytesPerSurfel(0, store.options().nViewBins()),
      SurfelStore::kIndexBytesPerSurfel, store.memoryBytes() / n, peak / 1048576.0,
      (peak - rss0) / 1048576.0 / (n / 1e6));
  return 0;
}
