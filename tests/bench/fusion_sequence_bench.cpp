// Benchmark of the per-frame map work of the Mapper on a real RGB-D sequence at known poses:
// the tracking model render (stable surfels, vertex + normal, at the previous pose; re-rendered
// with all surfels when the stable model covers < 30% of the valid pixels, as Mapper.cpp does)
// and SurfelFusion::fuse at the current pose. The frames are preprocessed like the Mapper's
// defaults (bilateral filter, vertex map 0.3-4 m, normals) outside the timed region. Poses are the
// source's ground truth, or a TUM trajectory (e.g. the trajectory.txt of a `rasm run`).
//   bench_fusion_sequence --source DIR [--poses trajectory.txt] [--frames 300] [--threads 2]
//                         [--csv per_frame.csv] [--ranges 20-50,250-300] [--repeat_render 0]
//                         [--repeat_sorted 0]
//                         [--merge 1]   (0: [fusion] merge_redundant = false, for A/B)
//                         [--resort F]  ([fusion] resort_unsorted_fraction, 1 = never)
// Prints one JSON line: {"bench":"fusion_sequence",...} with per-stage wall and process-CPU
// means over every range (frame indices of the run, end exclusive). Wall time is what a frame
// costs on an idle machine only; on a shared one, compare CPU time.
#include <omp.h>
#include <time.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "rasm/core/FrameProcessing.h"
#include "rasm/fusion/SurfelFusion.h"
#include "rasm/io/FrameSource.h"
#include "rasm/io/Trajectory.h"
#include "rasm/surfel_map/SurfelRenderer.h"

using namespace rasm;
using Clock = std::chrono::steady_clock;

namespace {
double msSince(Clock::time_point t0) {
  return std::chrono::duration<double, std::milli>(Clock::now() - t0).count();
}
/// Process CPU time (all threads), ms.
double cpuMs() {
  timespec ts;
  clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &ts);
  return 1e3 * double(ts.tv_sec) + 1e-6 * double(ts.tv_nsec);
}

struct FrameRow {
  int frame = 0;
  int map_size = 0;
  long long in_view = 0;
  long long model_tested = 0, model_drawn = 0;  ///< tracking render: members visited, drawn
  bool render_all = false;
  double render_ms = 0, render_cpu = 0, fuse_ms = 0, fuse_cpu = 0;
  double index_ms = 0, update_ms = 0, add_ms = 0, cleanup_ms = 0;
  double resort_ms = 0;  ///< SurfelStore::sortByBlock before this frame (0 when none)
};

int countValid(const Image<Vec3f>& v) {
  int n = 0;
  for (int y = 0; y < v.height(); ++y)
    for (int x = 0; x < v.width(); ++x) n += v(x, y).x() == v(x, y).x() ? 1 : 0;
  return n;
}
}  // namespace

int main(int argc, char** argv) {
  int threads = 2, max_frames = 300, repeat_render = 0, merge = 1, repeat_sorted = 0;
  float resort = -1.0f;
  std::string source_path, poses_path, csv_path, ranges_arg = "20-50,250-300";
  for (int i = 1; i + 1 < argc; i += 2) {
    const std::string k = argv[i], v = argv[i + 1];
    if (k == "--threads")
      threads = std::stoi(v);
    else if (k == "--frames")
      max_frames = std::stoi(v);
    else if (k == "--source")
      source_path = v;
    else if (k == "--poses")
      poses_path = v;
    else if (k == "--csv")
      csv_path = v;
    else if (k == "--ranges")
      ranges_arg = v;
    else if (k == "--repeat_render")
      repeat_render = std::stoi(v);
    else if (k == "--repeat_sorted")
      repeat_sorted = std::stoi(v);
    else if (k == "--merge")
      merge = std::stoi(v);
    else if (k == "--resort")
      resort = std::stof(v);
    else {
      std::fprintf(stderr, "unknown option %s\n", k.c_str());
      return 2;
    }
  }
  if (source_path.empty()) {
    std::fprintf(stderr, "--source DIR is required\n");
    return 2;
  }
  omp_set_num_threads(threads);
  std::vector<std::pair<int, int>> ranges;
  {
    std::stringstream ss(ranges_arg);
    std::string r;
    while (std::getline(ss, r, ',')) {
      const auto dash = r.find('-');
      if (dash != std::string::npos)
        ranges.emplace_back(std::stoi(r.substr(0, dash)), std::stoi(r.substr(dash + 1)));
    }
  }

  auto source = io::openFrameSource(source_path);
  io::Trajectory poses;
  if (!poses_path.empty()) poses = io::readTumTrajectory(poses_path);

  maps::SurfelStore map;
  fusion::TFusionParams fusion_params;
  fusion_params.merge_redundant = merge != 0;
  if (resort >= 0.0f) fusion_params.resort_unsorted_fraction = resort;
  fusion::SurfelFusion fusion(fusion_params);
  maps::SurfelRenderer renderer;
  maps::RenderedMaps model;
  Image<float> filtered;
  Image<Vec3f> vertex, normal;
  std::vector<FrameRow> rows;
  Eigen::Isometry3d T_prev = Eigen::Isometry3d::Identity();
  CameraIntrinsics K_last;
  int frame = 0;
  while (frame < max_frames) {
    std::optional<RgbdFrame> f = source->next();
    if (!f) break;
    std::optional<Eigen::Isometry3d> T;
    if (!poses.empty())
      T = io::interpolatePose(poses, f->timestamp_s);
    else if (f->gt_T_world_cam)
      T = *f->gt_T_world_cam;
    if (!T) continue;
    bilateralFilterDepth(f->depth_m, filtered, 2, 4.5f, 0.03f);
    VertexMapOptions vo;
    vo.min_depth_m = 0.3f;
    vo.max_depth_m = 4.0f;
    computeVertexMap(filtered, f->intrinsics, vertex, vo);
    computeNormalMap(vertex, normal, 0.05f);

    FrameRow row;
    row.frame = frame;
    if (frame > 0) {
      const auto t0 = Clock::now();
      const double c0 = cpuMs();
      maps::RenderOptions ro;
      ro.min_depth_m = 0.3f;
      ro.max_depth_m = 6.0f;
      ro.stable_only = true;
      ro.outputs = maps::kRenderVertex | maps::kRenderNormal;
      maps::RenderStats rs;
      renderer.render(map, T_prev, f->intrinsics, ro, model, &rs);
      if (countValid(model.normal_world) < 0.3 * countValid(normal)) {
        ro.stable_only = false;
        renderer.render(map, T_prev, f->intrinsics, ro, model, &rs);
        row.render_all = true;
      }
      row.render_ms = msSince(t0);
      row.model_tested = rs.surfels_tested;
      row.model_drawn = rs.surfels_drawn;
      row.render_cpu = cpuMs() - c0;
    }
    fusion::FusionInput in = fusion::makeFusionInput(*f, vertex, normal, *T);
    const auto t0 = Clock::now();
    const double c0 = cpuMs();
    const fusion::FusionStats st = fusion.fuse(map, in);
    row.fuse_ms = msSince(t0);
    row.fuse_cpu = cpuMs() - c0;
    row.index_ms = st.ms_index_map;
    row.update_ms = st.ms_update;
    row.add_ms = st.ms_add;
    row.cleanup_ms = st.ms_cleanup;
    row.resort_ms = st.resorted ? st.ms_resort : 0.0;
    row.map_size = st.map_size;
    row.in_view = st.render.surfels_drawn;
    rows.push_back(row);
    T_prev = *T;
    K_last = f->intrinsics;
    ++frame;
  }

  // The tracking render of the final map at the last pose, repeated (a fixed workload for A/B).
  // The tracking render (stable surfels) and the 4x candidate lists of fusion, of the final map
  // at the last pose, repeated: a fixed workload for A/B. With --repeat_sorted 1 the store is then
  // sorted by block (SurfelStore::sortByBlock) and both are repeated again.
  std::string repeats;
  maps::PointCandidates4x candidates;
  auto repeat = [&](const char* label) {
    std::vector<double> rep_ms, rep_cpu, cand_ms, all_ms;
    for (int k = 0; k < repeat_render && !rows.empty(); ++k) {
      maps::RenderOptions ro;
      ro.min_depth_m = 0.3f;
      ro.max_depth_m = 6.0f;
      ro.stable_only = true;
      ro.outputs = maps::kRenderVertex | maps::kRenderNormal;
      auto t0 = Clock::now();
      const double c0 = cpuMs();
      renderer.render(map, T_prev, K_last, ro, model);
      rep_ms.push_back(msSince(t0));
      rep_cpu.push_back(cpuMs() - c0);
      ro.stable_only = false;
      t0 = Clock::now();
      renderer.render(map, T_prev, K_last, ro, model);
      all_ms.push_back(msSince(t0));
      maps::RenderOptions r4;
      r4.min_depth_m = 0.3f;
      r4.max_depth_m = 4.0f;
      t0 = Clock::now();
      renderer.renderCandidates4x(map, T_prev, K_last, r4, candidates);
      cand_ms.push_back(msSince(t0));
    }
    if (rep_ms.empty()) return;
    std::sort(rep_ms.begin(), rep_ms.end());
    std::sort(rep_cpu.begin(), rep_cpu.end());
    std::sort(cand_ms.begin(), cand_ms.end());
    std::sort(all_ms.begin(), all_ms.end());
    char buf[256];
    std::snprintf(buf, sizeof buf,
                  ",\"%s\":{\"n\":%zu,\"min_ms\":%.2f,\"median_ms\":%.2f,"
                  "\"min_cpu_ms\":%.2f,\"all_surfels_min_ms\":%.2f,\"candidates4x_min_ms\":%.2f}",
                  label, rep_ms.size(), rep_ms.front(), rep_ms[rep_ms.size() / 2], rep_cpu.front(),
                  all_ms.front(), cand_ms.front());
    repeats += buf;
  };
  repeat("repeat_render");
  if (repeat_sorted) {
    const double unsorted = map.unsortedFraction();
    const auto t0 = Clock::now();
    map.sortByBlock();
    char buf[128];
    std::snprintf(buf, sizeof buf, ",\"sort_by_block\":{\"unsorted_fraction\":%.3f,\"ms\":%.2f}",
                  unsorted, msSince(t0));
    repeats += buf;
    repeat("repeat_render_sorted");
  }

  if (!csv_path.empty()) {
    std::ofstream csv(csv_path);
    csv << "frame,map_size,in_view,render_all,render_ms,render_cpu_ms,fuse_ms,fuse_cpu_ms,"
           "index_ms,update_ms,add_ms,cleanup_ms,model_tested,model_drawn,resort_ms\n";
    for (const FrameRow& r : rows)
      csv << r.frame << ',' << r.map_size << ',' << r.in_view << ',' << int(r.render_all) << ','
          << r.render_ms << ',' << r.render_cpu << ',' << r.fuse_ms << ',' << r.fuse_cpu << ','
          << r.index_ms << ',' << r.update_ms << ',' << r.add_ms << ',' << r.cleanup_ms << ','
          << r.model_tested << ',' << r.model_drawn << ',' << r.resort_ms << '\n';
  }
  ranges.emplace_back(1, int(rows.size()));  // every frame after the first
  std::string out = "{\"bench\":\"fusion_sequence\",\"threads\":" + std::to_string(threads) +
                    ",\"frames\":" + std::to_string(rows.size()) +
                    ",\"final_surfels\":" + std::to_string(map.size());
  out += repeats;
  out += ",\"ranges\":[";
  for (std::size_t k = 0; k < ranges.size(); ++k) {
    const int a = std::max(1, ranges[k].first), b = std::min(int(rows.size()), ranges[k].second);
    FrameRow m;
    double map_size = 0, in_view = 0;
    const int n = std::max(0, b - a);
    for (int j = a; j < b; ++j) {
      const FrameRow& r = rows[j];
      m.render_ms += r.render_ms / n;
      m.render_cpu += r.render_cpu / n;
      m.fuse_ms += r.fuse_ms / n;
      m.fuse_cpu += r.fuse_cpu / n;
      m.index_ms += r.index_ms / n;
      m.update_ms += r.update_ms / n;
      m.add_ms += r.add_ms / n;
      m.cleanup_ms += r.cleanup_ms / n;
      map_size += double(r.map_size) / n;
      in_view += double(r.in_view) / n;
    }
    char buf[512];
    std::snprintf(buf, sizeof buf,
                  "%s{\"from\":%d,\"to\":%d,\"mean_map_size\":%.0f,\"mean_in_view\":%.0f,"
                  "\"render_ms\":%.2f,\"render_cpu_ms\":%.2f,\"fuse_ms\":%.2f,\"fuse_cpu_ms\":%.2f,"
                  "\"index_map_ms\":%.2f,\"update_ms\":%.2f,\"add_ms\":%.2f,\"cleanup_ms\":%.2f}",
                  k ? "," : "", a, b, map_size, in_view, m.render_ms, m.render_cpu, m.fuse_ms,
                  m.fuse_cpu, m.index_ms, m.update_ms, m.add_ms, m.cleanup_ms);
    out += buf;
  }
  out += "]}";
  std::printf("%s\n", out.c_str());
  return 0;
}
