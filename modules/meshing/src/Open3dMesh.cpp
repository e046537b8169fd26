// The Open3D plugin of SurfelMesh (librasm_meshing_open3d.so, MeshBackend.h): TSDF fusion of the
// map's renders and marching cubes.

#include <open3d/camera/PinholeCameraIntrinsic.h>
#include <open3d/geometry/Image.h>
#include <open3d/geometry/KDTreeFlann.h>
#include <open3d/geometry/PointCloud.h>
#include <open3d/geometry/RGBDImage.h>
#include <open3d/geometry/TriangleMesh.h>
#include <open3d/io/TriangleMeshIO.h>
#include <open3d/pipelines/integration/ScalableTSDFVolume.h>
#include <algorithm>
#include <cmath>
#include <cstring>
#include <memory>
#include <stdexcept>

#include "MeshBackend.h"
#include "rasm/surfel_map/MapExport.h"
#include "rasm/surfel_map/SurfelRenderer.h"

namespace rasm::meshing {

namespace {

/// A render as Open3D's RGB-D image: colour RGB8 (black where nothing was drawn), depth float
/// metres (0 = none).
std::shared_ptr<open3d::geometry::RGBDImage> toRgbd(const maps::RenderedMaps& r,
                                                    double max_depth_m) {
  const int w = r.depth_m.width(), h = r.depth_m.height();
  open3d::geometry::Image colour, depth;
  colour.Prepare(w, h, 3, 1);
  depth.Prepare(w, h, 1, 4);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      const Bgr8 c = r.colour(x, y);
      std::uint8_t* px = colour.PointerAt<std::uint8_t>(x, y, 0);
      px[0] = c.r, px[1] = c.g, px[2] = c.b;
      *depth.PointerAt<float>(x, y) = r.depth_m(x, y);
    }
  return open3d::geometry::RGBDImage::CreateFromColorAndDepth(colour, depth, 1.0, max_depth_m,
                                                              false);
}

/// Up to n indices spread evenly over [0, count).
std::vector<std::size_t> evenlySpaced(std::size_t count, std::size_t n) {
  std::vector<std::size_t> out;
  if (count == 0) return out;
  n = std::min(n, count);
  for (std::size_t k = 0; k < n; ++k) out.push_back(n == 1 ? 0 : k * (count - 1) / (n - 1));
  return out;
}

}  // namespace

/// The mesh in Open3D's type.
class Open3dMesh final : public detail::MeshBackend {
 public:
  std::shared_ptr<open3d::geometry::TriangleMesh> mesh;
  int fused_views = 0;

  std::size_t vertices() const override { return mesh ? mesh->vertices_.size() : 0; }
  std::size_t triangles() const override { return mesh ? mesh->triangles_.size() : 0; }
  int views() const override { return fused_views; }
  void colourByClass(const maps::SurfelStore& map) override;
  void writePly(const std::string& path) const override;
  std::vector<Eigen::Vector3d> vertexPositions() const override {
    return mesh ? mesh->vertices_ : std::vector<Eigen::Vector3d>{};
  }
  std::vector<Eigen::Vector3d> vertexColours() const override {
    return mesh ? mesh->vertex_colors_ : std::vector<Eigen::Vector3d>{};
  }
};

/// SurfelMesh::build on checked arguments (K valid, params validated).
Open3dMesh* build(const maps::SurfelStore& map, const std::vector<Eigen::Isometry3d>& T_world_cam,
                  const CameraIntrinsics& K, const TMeshParams& params) {
  const CameraIntrinsics Kr = K.resized(params.width, params.height);
  const open3d::camera::PinholeCameraIntrinsic intrinsic(Kr.width, Kr.height, Kr.fx, Kr.fy, Kr.cx,
                                                         Kr.cy);
  open3d::pipelines::integration::ScalableTSDFVolume volume(
      params.voxel_m, params.truncation_m,
      open3d::pipelines::integration::TSDFVolumeColorType::RGB8);
  maps::SurfelRenderer renderer;
  maps::RenderOptions opt;
  opt.stable_only = true;
  opt.cull_back_faces = true;
  opt.splat = true;
  opt.min_depth_m = 0.1f;
  opt.max_depth_m = float(params.max_depth_m);
  opt.outputs = maps::kRenderDepth | maps::kRenderColour;
  maps::RenderedMaps r;
  auto out = std::make_unique<Open3dMesh>();
  for (const std::size_t i : evenlySpaced(T_world_cam.size(), std::size_t(params.max_views))) {
    renderer.render(map, T_world_cam[i], Kr, opt, r);
    bool any = false;
    for (int y = 0; y < r.depth_m.height() && !any; ++y)
      for (int x = 0; x < r.depth_m.width() && !any; ++x) any = r.depth_m(x, y) > 0.0f;
    if (!any) continue;
    volume.Integrate(*toRgbd(r, params.max_depth_m), intrinsic, T_world_cam[i].inverse().matrix());
    ++out->fused_views;
  }
  out->mesh = volume.ExtractTriangleMesh();
  out->mesh->ComputeVertexNormals();
  return out.release();
}

void Open3dMesh::colourByClass(const maps::SurfelStore& map) {
  if (!mesh || mesh->vertices_.empty()) return;
  const maps::SurfelArrays a = map.arrays();
  open3d::geometry::PointCloud surfels;
  std::vector<int> index;
  for (int i = 0; i < a.size; ++i)
    if (a.alive(i)) {
      surfels.points_.push_back(a.position(i).cast<double>());
      index.push_back(i);
    }
  mesh->vertex_colors_.assign(mesh->vertices_.size(), Eigen::Vector3d::Constant(0.5));
  if (index.empty()) return;
  const open3d::geometry::KDTreeFlann tree(surfels);
  std::vector<int> nearest(1);
  std::vector<double> d2(1);
  for (std::size_t v = 0; v < mesh->vertices_.size(); ++v) {
    if (tree.SearchKNN(mesh->vertices_[v], 1, nearest, d2) < 1) continue;
    const Bgr8 c = maps::classColour(maps::bestClass(a, index[std::size_t(nearest[0])]));
    mesh->vertex_colors_[v] = Eigen::Vector3d(c.r, c.g, c.b) / 255.0;
  }
}

void Open3dMesh::writePly(const std::string& path) const {
  // (WriteTriangleMeshToPLY, not WriteTriangleMesh: the format is PLY whatever the name ends in,
  // e.g. the ".part" of OutputFolder's atomic writes)
  if (!open3d::io::WriteTriangleMeshToPLY(path, *mesh, false, false, true, true, false, false))
    throw std::runtime_error("could not write the mesh " + path);
}

}  // namespace rasm::meshing

extern "C" rasm::meshing::detail::MeshBackend* rasm_meshing_open3d_build(
    const rasm::maps::SurfelStore& map, const std::vector<Eigen::Isometry3d>& T_world_cam,
    const rasm::CameraIntrinsics& K, const rasm::meshing::TMeshParams& params) {
  return rasm::meshing::build(map, T_world_cam, K, params);
}
