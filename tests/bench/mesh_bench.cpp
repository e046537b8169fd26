// Cost of mesh.ply (meshing/SurfelMesh.h) on a run's final map: reads a run folder's
// map.surfelmap and trajectory.txt, builds the mesh with the [mesh] defaults and prints one JSON
// line: surfels, views fused, vertices, triangles, build and write ms (median of `reps`). The
// camera is the embedded default's (Kinect v1 preset, 640x480, f = 525 px) unless given.
//   bench_mesh RUN_FOLDER [fx fy cx cy width height] [--reps N]
#include <mrpt/io/CFileGZInputStream.h>
#include <mrpt/serialization/CArchive.h>

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
  for (std::size_t i = 0; i + 1 < args.size(); ++i)
    if (args[i] == "--reps") {
      reps = std::max(1, std::stoi(args[i + 1]));
      args.erase(args.begin() + long(i), args.begin() + long(i) + 2);
      break;
    }
  if (args.size() != 1 && args.size() != 7) {
    std::fprintf(stderr, "usage: bench_mesh RUN_FOLDER [fx fy cx cy width height] [--reps N]\n");
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
  for (const auto& p : io::readTumTrajectory(dir + "/trajectory.txt")) poses.push_back(p.T_world_cam);
  const auto ms = [](auto t0) {
    return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
  };
  std::vector<double> build_ms, write_ms;
  meshing::SurfelMesh mesh;
  const std::string out = (std::filesystem::temp_directory_path() / "bench_mesh.ply").string();
  for (int r = 0; r < reps; ++r) {
    auto t0 = std::chrono::steady_clock::now();
    mesh = meshing::SurfelMesh::build(map.store(), poses, K);
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
      "\"triangles\":%zu,\"build_ms\":%.0f,\"write_ms\":%.0f,\"total_ms\":%.0f,"
      "\"target_ms\":10000,\"met\":%s}\n",
      map.store().size(), poses.size(), mesh.views(), mesh.vertices(), mesh.triangles(),
      build_ms[build_ms.size() / 2], write_ms[write_ms.size() / 2], total,
      total <= 10000 ? "true" : "false");
  return 0;
}
