// Benchmark of surfel fusion (II-B, II-D) at 640x480 on analytic frames (a back wall at 3 m and
// boxes, exact depth) along a slow camera path (2 mm and 0.2 deg per frame): the first frame
// initialises ~300k surfels, the later ones mostly associate and update. Optionally the map is
// pre-filled with extra surfels out of view (--extra_surfels) to show that the cost does not grow
// with the map size beyond the O(N) pruning scan.
//   bench_fusion [--threads 2] [--frames 30] [--extra_surfels 700000] [--labels on] [--view_bins
//   on]
//                [--carve on] [--cuda off]
// Prints one JSON line: {"bench":"fusion",...}.
#include <omp.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <ctime>
#include <string>
#include <vector>

#include "fusion/SyntheticScene.h"
#include "rasm/compute/Device.h"
#include "rasm/fusion/SurfelFusion.h"

using namespace rasm;
using Clock = std::chrono::steady_clock;

namespace {
double msSince(Clock::time_point t0) {
  return std::chrono::duration<double, std::milli>(Clock::now() - t0).count();
}
/// Process CPU time (all threads), ms (see surfel_render_bench.cpp).
double cpuMs() {
  return 1000.0 * double(std::clock()) / CLOCKS_PER_SEC;
}
double median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  return v.empty() ? 0.0 : v[v.size() / 2];
}
}  // namespace

int main(int argc, char** argv) {
  int threads = 2, frames = 30, extra = 700000;
  bool labels = true, use_cuda = false, view_bins = true, carve = true;
  for (int i = 1; i + 1 < argc; i += 2) {
    const std::string k = argv[i], v = argv[i + 1];
    if (k == "--threads")
      threads = std::stoi(v);
    else if (k == "--frames")
      frames = std::stoi(v);
    else if (k == "--extra_surfels")
      extra = std::stoi(v);
    else if (k == "--labels")
      labels = v == "on";
    else if (k == "--view_bins")
      view_bins = v == "on";
    else if (k == "--carve")
      carve = v == "on";
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
  const CameraIntrinsics K = CameraIntrinsics::preset("kinect_v1");
  fusiontest::Scene scene;
  scene.wall_z = 3.0;
  scene.boxes.push_back(
      {Eigen::Vector3d(-0.6, -0.3, 1.6), Eigen::Vector3d(0.0, 0.4, 2.0), Bgr8{0, 0, 220}});
  scene.boxes.push_back(
      {Eigen::Vector3d(0.3, 0.2, 2.2), Eigen::Vector3d(0.9, 0.9, 2.6), Bgr8{0, 220, 0}});

  std::vector<fusiontest::SyntheticFrame> seq;
  for (int k = 0; k <= frames; ++k) {
    Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
    T.translation() = Eigen::Vector3d(0.002 * k, 0.001 * k, 0.0);
    T.linear() = Eigen::AngleAxisd(0.0035 * k, Eigen::Vector3d::UnitY()).toRotationMatrix();
    seq.push_back(fusiontest::renderScene(scene, K, T, 100.0 + k / 30.0));
  }
  Image<std::uint32_t> label_img(K.width, K.height);
  for (int y = 0; y < K.height; ++y)
    for (int x = 0; x < K.width; ++x) label_img(x, y) = 1 + (x / 80) + 8 * (y / 80);

  maps::SurfelStoreOptions layout;
  layout.n_classes = 20;
  maps::SurfelStore map(layout);
  // Out-of-view surfels (behind the camera): they make the map large without being in view.
  if (extra > 0) {
    const int first = map.allocate(extra);
    const maps::SurfelArrays a = map.arrays();
    for (int i = 0; i < extra; ++i) {
      const int j = first + i;
      a.pos_conf[j] = Vec4f(-5.0f + 0.01f * (i % 1000), -2.0f + 0.01f * ((i / 1000) % 400),
                            -2.0f - 0.01f * (i / 400000), 20.0f);
      a.normal_radius[j] = Vec4f(0, 0, 1, 0.007f);
      a.colour_flags[j] = maps::packColour(Bgr8{100, 100, 100}, maps::kSurfelStable);
      a.basis[j] = Vec3f::UnitX();
    }
    map.setTimeOrigin(100.0);
    map.indexAppended();
  }

  fusion::TFusionParams params;
  params.update_view_bins = view_bins;
  params.carve_free_space = carve;
  fusion::SurfelFusion fusion(params, use_cuda ? compute::Backend::Cuda : compute::Backend::Cpu);
  std::vector<double> t_steady, t_index, t_update, t_add, t_cleanup, c_steady;
  double t_init = 0.0;
  fusion::FusionStats last;
  for (int k = 0; k <= frames; ++k) {
    const auto in = seq[k].input(labels ? &label_img : nullptr);
    const auto t0 = Clock::now();
    const double c0 = cpuMs();
    last = fusion.fuse(map, in);
    const double ms = msSince(t0), cms = cpuMs() - c0;
    if (k == 0) {
      t_init = ms;
    } else {
      t_steady.push_back(ms);
      c_steady.push_back(cms);
      t_index.push_back(last.ms_index_map);
      t_update.push_back(last.ms_update);
      t_add.push_back(last.ms_add);
      t_cleanup.push_back(last.ms_cleanup);
    }
  }
  std::printf(
      "{\"bench\":\"fusion\",\"threads\":%d,\"backend\":\"%s\",\"width\":%d,\"height\":%d,"
      "\"frames\":%d,"
      "\"labels\":%s,\"ms_first_frame_init\":%.2f,\"ms_per_frame_median\":%.2f,\"ms_per_frame_"
      "max\":%.2f,"
      "\"cpu_ms_per_frame_median\":%.2f,\"ms_index_map\":%.2f,\"ms_update\":%.2f,\"ms_add\":%.2f,"
      "\"ms_cleanup\":%.2f,"
      "\"map_surfels\":%d,\"extra_out_of_view\":%d,\"last_valid\":%d,\"last_associated\":%d,"
      "\"last_fused\":%d,\"last_added\":%d,\"last_surfels_in_view\":%lld}\n",
      threads, use_cuda ? "cuda" : "cpu", K.width, K.height, frames, labels ? "true" : "false",
      t_init, median(t_steady),
      t_steady.empty() ? 0.0 : *std::max_element(t_steady.begin(), t_steady.end()),
      median(c_steady), median(t_index), median(t_update), median(t_add), median(t_cleanup),
      map.size(), extra, last.valid_pixels, last.associated, last.fused, last.added,
      last.render.surfels_drawn);
  return 0;
}
