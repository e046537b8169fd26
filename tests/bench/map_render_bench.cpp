// Benchmark of the per-frame projections of a saved map (a `rasm run` output) at a pose of its
// trajectory: the II-C tracking model (splats of the surfels with confidence >= min_conf, vertex
// and normal maps, as pipeline::Mapper renders it) and fusion's II-D 4x candidate lists, repeated
// on the same map so that A/B comparisons of the renderer do not depend on a whole run.
//   bench_map_render --map DIR/map.surfelmap --poses DIR/trajectory.txt [--pose_index -1]
//                    [--width 640 --height 480 --fx 585 --fy 585 --cx 320 --cy 240]
//                    [--min_conf 3] [--max_depth 6] [--repeats 20] [--threads 2]
// Prints one JSON line: {"bench":"map_render",...} with median wall and process-CPU ms per call
// and the render counts (members tested, surfels drawn).
#include <omp.h>
#include <time.h>

#include <mrpt/io/CFileGZInputStream.h>
#include <mrpt/serialization/CArchive.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <stdexcept>
#include <string>
#include <vector>

#include "rasm/io/Trajectory.h"
#include "rasm/surfel_map/CSurfelMap.h"
#include "rasm/surfel_map/SurfelRenderer.h"
#include "rasm/surfel_map/kernels/RenderKernels.h"

using namespace rasm;
using Clock = std::chrono::steady_clock;

namespace {
double cpuMs() {
  timespec ts;
  clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &ts);
  return 1e3 * double(ts.tv_sec) + 1e-6 * double(ts.tv_nsec);
}
double median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  return v.empty() ? 0.0 : v[v.size() / 2];
}
}  // namespace

int main(int argc, char** argv) {
  std::string map_path, poses_path;
  int pose_index = -1, repeats = 20, threads = 2, width = 640, height = 480;
  double fx = 585, fy = 585, cx = 320, cy = 240, min_conf = 3, max_depth = 6;
  for (int i = 1; i + 1 < argc; i += 2) {
    const std::string k = argv[i], v = argv[i + 1];
    if (k == "--map")
      map_path = v;
    else if (k == "--poses")
      poses_path = v;
    else if (k == "--pose_index")
      pose_index = std::stoi(v);
    else if (k == "--repeats")
      repeats = std::stoi(v);
    else if (k == "--threads")
      threads = std::stoi(v);
    else if (k == "--width")
      width = std::stoi(v);
    else if (k == "--height")
      height = std::stoi(v);
    else if (k == "--fx")
      fx = std::stod(v);
    else if (k == "--fy")
      fy = std::stod(v);
    else if (k == "--cx")
      cx = std::stod(v);
    else if (k == "--cy")
      cy = std::stod(v);
    else if (k == "--min_conf")
      min_conf = std::stod(v);
    else if (k == "--max_depth")
      max_depth = std::stod(v);
    else {
      std::fprintf(stderr, "unknown option %s\n", k.c_str());
      return 2;
    }
  }
  if (map_path.empty() || poses_path.empty()) {
    std::fprintf(stderr, "--map FILE and --poses FILE are required\n");
    return 2;
  }
  omp_set_num_threads(threads);
  maps::CSurfelMap map;
  io::Trajectory poses;
  try {
    mrpt::io::CFileGZInputStream f;
    if (!f.open(map_path)) throw std::runtime_error("cannot open " + map_path);
    auto a = mrpt::serialization::archiveFrom(f);
    a >> map;
    poses = io::readTumTrajectory(poses_path);
  } catch (const std::exception& e) {
    std::fprintf(stderr,
                 "bench_map_render: %s (expected --map a rasm run's map.surfelmap, "
                 "--poses its trajectory.txt)\n",
                 e.what());
    return 2;
  }
  if (poses.empty()) {
    std::fprintf(stderr, "%s holds no pose\n", poses_path.c_str());
    return 2;
  }
  const int pi =
      pose_index < 0 ? int(poses.size()) - 1 : std::min(pose_index, int(poses.size()) - 1);
  const Eigen::Isometry3d T = poses[pi].T_world_cam;
  CameraIntrinsics K;
  K.fx = fx;
  K.fy = fy;
  K.cx = cx;
  K.cy = cy;
  K.width = width;
  K.height = height;

  maps::SurfelRenderer renderer;
  maps::RenderOptions model_opt;  // as pipeline::Mapper
  model_opt.min_depth_m = 0.3f;
  model_opt.max_depth_m = float(max_depth);
  model_opt.stable_only = min_conf <= 0;
  model_opt.min_confidence = float(min_conf);
  model_opt.outputs = maps::kRenderVertex | maps::kRenderNormal;
  maps::RenderOptions cand_opt;  // as SurfelFusion
  cand_opt.min_depth_m = 0.3f;
  cand_opt.max_depth_m = 4.0f * 1.01f + 0.03f;
  cand_opt.splat = false;

  maps::RenderedMaps model;
  maps::PointCandidates4x cand;
  maps::RenderStats model_stats, cand_stats;
  std::vector<double> model_ms, model_cpu, cand_ms, cand_cpu;
  for (int r = 0; r < repeats + 1; ++r) {
    auto t0 = Clock::now();
    double c0 = cpuMs();
    renderer.render(map.store(), T, K, model_opt, model, &model_stats);
    if (r > 0) {
      model_ms.push_back(std::chrono::duration<double, std::milli>(Clock::now() - t0).count());
      model_cpu.push_back(cpuMs() - c0);
    }
    t0 = Clock::now();
    c0 = cpuMs();
    renderer.renderCandidates4x(map.store(), T, K, cand_opt, cand, &cand_stats);
    if (r > 0) {
      cand_ms.push_back(std::chrono::duration<double, std::milli>(Clock::now() - t0).count());
      cand_cpu.push_back(cpuMs() - c0);
    }
  }
  long long below_min_conf = 0;
  {
    const maps::SurfelArrays a = map.store().arrays();
    for (int i = 0; i < map.size(); ++i) below_min_conf += a.pos_conf[i].w() < min_conf ? 1 : 0;
  }
  // Footprint sizes of the model's splats (bounding boxes in pixels, 3 = 3 or more).
  long long fp[4][4] = {};
  // Footprints that lose the depth test at their own centre pixel, by how far they lie behind
  // the winner there: < 5 mm, < 2 cm, < 5 cm, < 20 cm, farther (same surface .. occluded).
  long long behind[5] = {};
  long long box_pixels = 0, larger_pixels = 0;  // pixels the depth test visits (bounding boxes)
  {
    Image<std::uint64_t> scratch(width, height);
    const maps::kernels::SplatKernel k{map.store().arrays(),
                                       nullptr,
                                       RigidF::fromMatrix(T.inverse().matrix().cast<float>()),
                                       K.plain(),
                                       model_opt.min_depth_m,
                                       model_opt.max_depth_m,
                                       model_opt.max_splat_radius_px,
                                       scratch.view()};
    const maps::SurfelArrays a = map.store().arrays();
    for (int i = 0; i < map.size(); ++i) {
      if (a.pos_conf[i].w() < model_opt.min_confidence) continue;
      const Vec3f pc = k.T_cam_world.apply(a.position(i));
      if (!(pc.z() > 0.0f)) continue;
      const float u = k.K.fx * pc.x() / pc.z() + k.K.cx, v = k.K.fy * pc.y() / pc.z() + k.K.cy;
      const float m = model_opt.max_splat_radius_px;
      if (u < -0.5f - m || v < -0.5f - m || u > width - 0.5f + m || v > height - 0.5f + m) continue;
      maps::kernels::SplatFootprint f;
      if (!k.footprintAt(i, pc, u, v, f)) continue;
      ++fp[std::min(f.x1 - f.x0 + 1, 3)][std::min(f.y1 - f.y0 + 1, 3)];
      if (f.uc >= 0 && f.vc >= 0 && f.uc < width && f.vc < height) {
        const int wi = model.index(f.uc, f.vc);
        if (wi >= 0 && wi != i) {
          const float dz = pc.z() - k.T_cam_world.apply(model.vertex_world(f.uc, f.vc)).z();
          ++behind[dz < 0.005f ? 0 : dz < 0.02f ? 1 : dz < 0.05f ? 2 : dz < 0.2f ? 3 : 4];
        }
      }
      box_pixels += (long long)(f.x1 - f.x0 + 1) * (f.y1 - f.y0 + 1);
      if (f.x1 - f.x0 + 1 > 2 || f.y1 - f.y0 + 1 > 2)
        larger_pixels += (long long)(f.x1 - f.x0 + 1) * (f.y1 - f.y0 + 1);
    }
  }
  long long model_valid = 0;
  // Surfels that win at least one pixel of the model: drawn minus this is the overdraw that
  // depth-tested and lost everywhere (occluded or covered by neighbours).
  long long model_winners = 0;
  {
    std::vector<std::uint8_t> wins(std::size_t(map.size()), 0);
    for (int y = 0; y < height; ++y)
      for (int x = 0; x < width; ++x) {
        const int i = model.index(x, y);
        if (i < 0) continue;
        ++model_valid;
        model_winners += wins[std::size_t(i)] ? 0 : 1;
        wins[std::size_t(i)] = 1;
      }
  }
  // FNV-1a of the model's index, vertex and normal maps: equal hashes = bit-identical renders
  // (for A/B of renderer changes that must not change the output).
  std::uint64_t hash = 1469598103934665603ull;
  const auto mix = [&](const void* p, std::size_t n) {
    const unsigned char* b = static_cast<const unsigned char*>(p);
    for (std::size_t k = 0; k < n; ++k) hash = (hash ^ b[k]) * 1099511628211ull;
  };
  for (int y = 0; y < height; ++y) {
    mix(model.index.row(y), sizeof(std::int32_t) * width);
    mix(model.vertex_world.row(y), sizeof(Vec3f) * width);
    mix(model.normal_world.row(y), sizeof(Vec3f) * width);
  }
  std::printf(
      "{\"bench\":\"map_render\",\"surfels\":%d,\"pose_index\":%d,\"threads\":%d,"
      "\"model_ms\":%.3f,\"model_cpu_ms\":%.3f,\"model_tested\":%lld,\"model_drawn\":%lld,"
      "\"model_valid_pixels\":%lld,\"model_winning_surfels\":%lld,\"candidates_ms\":%.3f,"
      "\"candidates_cpu_ms\":%.3f,"
      "\"candidates_in_view\":%lld,\"surfels_below_min_conf\":%lld,"
      "\"footprints_1x1\":%lld,\"footprints_2x1\":%lld,\"footprints_1x2\":%lld,"
      "\"footprints_2x2\":%lld,\"footprints_larger\":%lld,\"footprint_box_pixels\":%lld,"
      "\"footprint_box_pixels_larger\":%lld,\"centre_losers_behind_5mm_2cm_5cm_20cm_more\":"
      "[%lld,%lld,%lld,%lld,%lld],\"model_hash\":\"%016llx\"}\n",
      map.size(), pi, threads, median(model_ms), median(model_cpu), model_stats.surfels_tested,
      model_stats.surfels_drawn, model_valid, model_winners, median(cand_ms), median(cand_cpu),
      cand_stats.surfels_drawn, below_min_conf, fp[1][1], fp[2][1], fp[1][2], fp[2][2],
      fp[3][1] + fp[3][2] + fp[3][3] + fp[1][3] + fp[2][3], box_pixels, larger_pixels, behind[0],
      behind[1], behind[2], behind[3], behind[4], (unsigned long long)hash);
  return 0;
}
