// Cost of mesh.ply (meshing/SurfelMesh.h) on a run's final map: reads a run folder's
// map.surfelmap and trajectory.txt, builds the mesh with the [mesh] defaults and prints one JSON
// line: surfels, views fused, vertices, triangles, build and write ms (median of `reps`). The
// camera is the embedded default's (Kinect v1 preset, 640x480, f = 525 px) unless given; also the
// process's peak RSS before and after (the TSDF's memory while it is built).
//   bench_mesh RUN_FOLDER [fx fy cx cy width height] [--reps N] [--voxel M]
#include <mrpt/io/CFileGZInputStream.h>
#include <mrpt/serialization/CArchive.h>
#include <sys/resource.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <string>
#include <vector>

#include "rasm/io/Trajectory.h"
#include "rasm/meshing/SurfelMesh.h"
#include "rasm/surfel_map/CSurfelMap.h"

using namespace rasm;

int main(int argc, char** argv) {
  std::vector<std::string> args(argv + 1, argv + argc);
  int reps = 3;
  meshing::TMeshParams params;
  for (std::size_t i = 0; i + 1 < args.size();)
    if (args[i] == "--reps" || args[i] == "--voxel") {
      if (args[i] == "--reps") reps = std::max(1, std::stoi(args[i + 1]));
      if (args[i] == "--voxel") params.voxel_m = std::stod(args[i + 1]);
      if (args[i] == "--voxel") params.truncation_m = 3.0 * params.voxel_m;
      args.erase(args.begin() + long(i), args.begin() + long(i) + 2);
    } else {
      ++i;
    }
  const auto peak_mb = [] {
    rusage u{};
    getrusage(RUSAGE_SELF, &u);
    return double(u.ru_maxrss) / 1024.0;
  };
  if (args.size() != 1 && args.size() != 7) {
    std::fprintf(
        stderr, "usage: bench_mesh RUN_FOLDER [fx fy cx cy width height] [--reps N] [--voxel M]\n");
    return 2;
  }
  const std::string dir = args[0];
  CameraIntrinsics K(525.0, 525.0, 319.5, 239.5, 640, 480);
  if (args.size() == 7)
    K = CameraIntrinsics(std::stod(args[1]), std::stod(args[2]), std::stod(args[3]),
                         std::stod(args[4]), std::stoi(args[5]), std::stoi(args[6]));
  maps::CSurfelMap map;
  {
    mrpt::io::CFileGZInputStream f(dir + "/map.surfelmap");
    auto a = mrpt::serialization::archiveFrom(f);
    a >> map;
  }
  std::vector<Eigen::Isometry3d> poses;
  for (const auto& p : io::readTumTrajectory(dir + "/trajectory.txt"))
    poses.push_back(p.T_world_cam);
  const auto ms = [](auto t0) {
    return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
  };
  const double peak_before_mb = peak_mb();
  std::vector<double> build_ms, write_ms;
  meshing::SurfelMesh mesh;
  const std::string out = (std::filesystem::temp_directory_path() / "bench_mesh.ply").string();
  for (int r = 0; r < reps; ++r) {
    auto t0 = std::chrono::steady_clock::now();
    mesh = meshing::SurfelMesh::build(map.store(), poses, K, params);
    build_ms.push_back(ms(t0));
    t0 = std::chrono::steady_clock::now();
    mesh.writePly(out);
    write_ms.push_back(ms(t0));
  }
  std::filesystem::remove(out);
  std::sort(build_ms.begin(), build_ms.end());
  std::sort(write_ms.begin(), write_ms.end());
  const double total = build_ms[build_ms.size() / 2] + write_ms[write_ms.size() / 2];
  std::printf(
      "{\"bench\":\"mesh\",\"surfels\":%d,\"poses\":%zu,\"views\":%d,\"vertices\":%zu,"
      "\"triangles\":%zu,\"voxel_m\":%.3f,\"build_ms\":%.0f,\"write_ms\":%.0f,"
      "\"total_ms\":%.0f,\"target_ms\":10000,\"met\":%s,\"peak_rss_before_mb\":%.0f,"
      "\"peak_rss_after_mb\":%.0f}\n",
      map.store().size(), poses.size(), mesh.views(), mesh.vertices(), mesh.triangles(),
      params.voxel_m, build_ms[build_ms.size() / 2], write_ms[write_ms.size() / 2], total,
      total <= 10000 ? "true" : "false", peak_before_mb, peak_mb());
  return 0;
}
