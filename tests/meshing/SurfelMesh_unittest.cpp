// The mesh of a surfel map (SurfelMesh.h) against the surfaces the surfels were placed on: a
// floor (z = 0, red) and a wall (x = 2, blue) of 2 x 2 m, 1 cm surfels every 1 cm, seen by a
// camera that turns across the corner. Tolerances from the TSDF's geometry: a vertex of marching
// cubes lies on the zero crossing interpolated between two cell centres, within a cell
// (voxel_m) of the surface the renders show.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>

#include "rasm/core/Error.h"
#include "rasm/meshing/SurfelMesh.h"
#include "rasm/surfel_map/MapExport.h"

using namespace rasm;

namespace {

maps::SurfelStore floorAndWall() {
  maps::SurfelStore store;
  for (int i = 0; i < 200; ++i)
    for (int j = 0; j < 200; ++j) {
      maps::Surfel s;
      s.radius = 0.008f;
      s.confidence = 10.0f;
      s.stable = true;
      s.position = Vec3f(0.005f + 0.01f * i, -1.0f + 0.01f * j, 0.0f);  // floor, x in [0, 2]
      s.normal = Vec3f::UnitZ();
      s.basis = Vec3f::UnitX();
      s.colour = Bgr8{0, 0, 255};  // red (B, G, R)
      store.append(s);
      s.position = Vec3f(2.0f, -1.0f + 0.01f * j, 0.005f + 0.01f * i);  // wall, z in [0, 2]
      s.normal = -Vec3f::UnitX();
      s.basis = Vec3f::UnitY();
      s.colour = Bgr8{255, 0, 0};  // blue
      store.append(s);
    }
  store.rebuildIndex();
  return store;
}

/// A camera 1.2 m up at x = 0.3, looking along +x and 35 degrees down, turned by yaw about z.
Eigen::Isometry3d camera(double yaw) {
  const Eigen::Matrix3d optical_in_body = (Eigen::Matrix3d() << 0, 0, 1, -1, 0, 0, 0, -1, 0)
                                              .finished();  // optical z = body x, x = -y, y = -z
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.linear() = Eigen::AngleAxisd(yaw, Eigen::Vector3d::UnitZ()).toRotationMatrix() *
               Eigen::AngleAxisd(35.0 * M_PI / 180.0, Eigen::Vector3d::UnitY()).toRotationMatrix() *
               optical_in_body;
  T.translation() = Eigen::Vector3d(0.3, 0.0, 1.2);
  return T;
}

std::vector<Eigen::Isometry3d> sweep() {
  std::vector<Eigen::Isometry3d> poses;
  for (int k = -10; k <= 10; ++k) poses.push_back(camera(k * 2.0 * M_PI / 180.0));
  return poses;
}

const CameraIntrinsics kK(262.5, 262.5, 159.5, 119.5, 320, 240);

}  // namespace

TEST(SurfelMesh, VerticesLieOnTheSurfacesTheSurfelsShowInTheirColour) {
  const maps::SurfelStore store = floorAndWall();
  meshing::TMeshParams params;
  const meshing::SurfelMesh mesh = meshing::SurfelMesh::build(store, sweep(), kK, params);
  EXPECT_EQ(mesh.views(), 21);
  ASSERT_GT(mesh.triangles(), 1000u);
  const auto v = mesh.vertexPositions();
  const auto c = mesh.vertexColours();
  ASSERT_EQ(v.size(), c.size());
  std::size_t on_floor = 0, on_wall = 0, off = 0, wrong_colour = 0;
  double floor_min_x = 1e9, floor_max_x = -1e9;
  for (std::size_t i = 0; i < v.size(); ++i) {
    const double d_floor = std::abs(v[i].z()), d_wall = std::abs(v[i].x() - 2.0);
    if (std::min(d_floor, d_wall) > params.voxel_m) {
      ++off;
      continue;
    }
    const bool floor = d_floor < d_wall;
    (floor ? on_floor : on_wall) += 1;
    if (floor)
      floor_min_x = std::min(floor_min_x, v[i].x()), floor_max_x = std::max(floor_max_x, v[i].x());
    // The corner's cells mix both colours; elsewhere a vertex has its surface's colour.
    if (std::min(d_floor, d_wall) < 0.5 * params.voxel_m && std::max(d_floor, d_wall) > 0.1) {
      const bool red = c[i].x() > 0.8 && c[i].z()<0.2, blue = c[i].z()> 0.8 && c[i].x() < 0.2;
      if (floor ? !red : !blue) ++wrong_colour;
    }
  }
  std::printf(
      "mesh: %zu vertices, %zu triangles; on the floor %zu (x %.2f..%.2f), on the wall %zu, "
      "off %zu, wrong colour %zu\n",
      v.size(), mesh.triangles(), on_floor, floor_min_x, floor_max_x, on_wall, off, wrong_colour);
  EXPECT_EQ(off, 0u) << "vertices farther than a cell from both surfaces";
  EXPECT_GT(on_floor, 1000u);
  EXPECT_GT(on_wall, 1000u);
  EXPECT_LE(wrong_colour, v.size() / 100);
  // The floor is meshed where the camera saw it: from ~0.5 m ahead (the 35-degree pitch and the
  // 49-degree vertical field of view) to the wall.
  EXPECT_LT(floor_min_x, 1.2);
  EXPECT_GT(floor_max_x, 1.9);
}

TEST(SurfelMesh, ClassColoursComeFromTheNearestSurfelAndThePlyOpens) {
  maps::SurfelStoreOptions opt;
  opt.n_classes = 4;
  maps::SurfelStore store(opt);
  const maps::SurfelStore plain = floorAndWall();
  for (int i = 0; i < plain.size(); ++i) store.append(plain.get(i));
  std::vector<int> wall;
  for (int i = 0; i < store.size(); ++i)
    if (store.get(i).position.x() > 1.99f) wall.push_back(i);
  store.addClassEvidence(wall, 3, 0.9f);
  store.rebuildIndex();
  meshing::SurfelMesh mesh = meshing::SurfelMesh::build(store, sweep(), kK);
  mesh.colourByClass(store);
  const maps::SurfelArrays a = store.arrays();
  const Bgr8 wall_colour = maps::classColour(maps::bestClass(a, wall.front()));
  const Bgr8 floor_colour = maps::classColour(maps::bestClass(a, 0));
  const auto v = mesh.vertexPositions();
  const auto c = mesh.vertexColours();
  std::size_t checked = 0;
  for (std::size_t i = 0; i < v.size(); ++i) {
    if (std::abs(v[i].x() - 2.0) > 0.2 && std::abs(v[i].z()) > 0.2) continue;  // near neither
    const bool on_wall = std::abs(v[i].x() - 2.0) < std::abs(v[i].z());
    if (std::abs(v[i].x() - 2.0) < 0.1 && std::abs(v[i].z()) < 0.1) continue;  // the corner
    const Bgr8 want = on_wall ? wall_colour : floor_colour;
    EXPECT_NEAR(c[i].x(), want.r / 255.0, 1e-6);
    EXPECT_NEAR(c[i].z(), want.b / 255.0, 1e-6);
    ++checked;
  }
  EXPECT_GT(checked, 1000u);

  const std::string path =
      (std::filesystem::temp_directory_path() / "rasm_mesh_test.ply.part").string();
  mesh.writePly(path);  // PLY whatever the name ends in (OutputFolder writes to ".part")
  std::ifstream in(path, std::ios::binary);
  std::string magic, format;
  std::getline(in, magic);
  std::getline(in, format);
  EXPECT_EQ(magic, "ply");
  EXPECT_NE(format.find("binary"), std::string::npos) << format;
  std::string header, line;
  while (std::getline(in, line) && line != "end_header") header += line + "\n";
  EXPECT_NE(header.find("element vertex " + std::to_string(mesh.vertices())), std::string::npos)
      << header;
  EXPECT_NE(header.find("element face " + std::to_string(mesh.triangles())), std::string::npos)
      << header;
  EXPECT_NE(header.find("property uchar red"), std::string::npos) << header;
  in.close();
  std::filesystem::remove(path);
}

TEST(SurfelMesh, NothingInViewGivesAnEmptyMeshAndBadParamsAreNamed) {
  const maps::SurfelStore store = floorAndWall();
  Eigen::Isometry3d away = camera(M_PI);  // looking at -x: nothing there
  away.translation().x() = -1.0;
  const meshing::SurfelMesh mesh = meshing::SurfelMesh::build(store, {away}, kK);
  EXPECT_EQ(mesh.views(), 0);
  EXPECT_EQ(mesh.triangles(), 0u);
  EXPECT_THROW(mesh.writePly((std::filesystem::temp_directory_path() / "rasm_empty.ply").string()),
               std::runtime_error);
  meshing::TMeshParams bad;
  bad.truncation_m = 0.001;  // less than a cell
  try {
    (void)meshing::SurfelMesh::build(store, sweep(), kK, bad);
    FAIL() << "accepted a truncation below one cell";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("[mesh] truncation_m"), std::string::npos) << e.what();
  }
}
