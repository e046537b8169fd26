#include "rasm/meshing/SurfelMesh.h"

#include <mrpt/config/CConfigFileBase.h>

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
#include <stdexcept>

#include "rasm/core/Error.h"
#include "rasm/core/Params.h"
#include "rasm/surfel_map/MapExport.h"
#include "rasm/surfel_map/SurfelRenderer.h"

namespace rasm::meshing {

void TMeshParams::loadFromConfigFile(const mrpt::config::CConfigFileBase& c, const std::string& s) {
  MRPT_LOAD_CONFIG_VAR(voxel_m, double, c, s);
  MRPT_LOAD_CONFIG_VAR(truncation_m, double, c, s);
  MRPT_LOAD_CONFIG_VAR(max_views, int, c, s);
  MRPT_LOAD_CONFIG_VAR(width, int, c, s);
  MRPT_LOAD_CONFIG_VAR(height, int, c, s);
  MRPT_LOAD_CONFIG_VAR(max_depth_m, double, c, s);
  validate(s);
}

void TMeshParams::validate(const std::string& s) const {
  requireInRange(voxel_m, 0.002, 0.5, s, "voxel_m");
  requireInRange(truncation_m, voxel_m, 1.0, s, "truncation_m");  // at least one cell
  requireInRange(max_views, 1, 100000, s, "max_views");
  requireInRange(width, 16, 4096, s, "width");
  requireInRange(height, 16, 4096, s, "height");
  // Beyond the renders' 0.1 m near plane (build): a bound of 0.1 itself renders nothing.
  requireInRange(max_depth_m, std::nextafter(0.1, 1.0), 20.0, s, "max_depth_m");
}

void TMeshParams::saveToConfigFile(mrpt::config::CConfigFileBase& c, const std::string& s) const {
  MRPT_SAVE_CONFIG_VAR(voxel_m, c, s);
  MRPT_SAVE_CONFIG_VAR(truncation_m, c, s);
  MRPT_SAVE_CONFIG_VAR(max_views, c, s);
  MRPT_SAVE_CONFIG_VAR(width, c, s);
  MRPT_SAVE_CONFIG_VAR(height, c, s);
  MRPT_SAVE_CONFIG_VAR(max_depth_m, c, s);
}

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

SurfelMesh SurfelMesh::build(const maps::SurfelStore& map,
                             const std::vector<Eigen::Isometry3d>& T_world_cam,
                             const CameraIntrinsics& K, const TMeshParams& params) {
  if (K.width <= 0 || K.height <= 0 || !(K.fx > 0) || !(K.fy > 0))
    throwInputError("mesh camera", "intrinsics " + K.toString() + " are not valid");
  params.validate();

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
  SurfelMesh out;
  for (const std::size_t i : evenlySpaced(T_world_cam.size(), std::size_t(params.max_views))) {
    renderer.render(map, T_world_cam[i], Kr, opt, r);
    bool any = false;
    for (int y = 0; y < r.depth_m.height() && !any; ++y)
      for (int x = 0; x < r.depth_m.width() && !any; ++x) any = r.depth_m(x, y) > 0.0f;
    if (!any) continue;
    volume.Integrate(*toRgbd(r, params.max_depth_m), intrinsic, T_world_cam[i].inverse().matrix());
    ++out.m_views;
  }
  out.m_mesh = volume.ExtractTriangleMesh();
  out.m_mesh->ComputeVertexNormals();
  return out;
}

std::size_t SurfelMesh::vertices() const {
  return m_mesh ? m_mesh->vertices_.size() : 0;
}
std::size_t SurfelMesh::triangles() const {
  return m_mesh ? m_mesh->triangles_.size() : 0;
}

void SurfelMesh::colourByClass(const maps::SurfelStore& map) {
  if (!m_mesh || m_mesh->vertices_.empty()) return;
  const maps::SurfelArrays a = map.arrays();
  open3d::geometry::PointCloud surfels;
  std::vector<int> index;
  for (int i = 0; i < a.size; ++i)
    if (a.alive(i)) {
      surfels.points_.push_back(a.position(i).cast<double>());
      index.push_back(i);
    }
  m_mesh->vertex_colors_.assign(m_mesh->vertices_.size(), Eigen::Vector3d::Constant(0.5));
  if (index.empty()) return;
  const open3d::geometry::KDTreeFlann tree(surfels);
  std::vector<int> nearest(1);
  std::vector<double> d2(1);
  for (std::size_t v = 0; v < m_mesh->vertices_.size(); ++v) {
    if (tree.SearchKNN(m_mesh->vertices_[v], 1, nearest, d2) < 1) continue;
    const Bgr8 c = maps::classColour(maps::bestClass(a, index[std::size_t(nearest[0])]));
    m_mesh->vertex_colors_[v] = Eigen::Vector3d(c.r, c.g, c.b) / 255.0;
  }
}

void SurfelMesh::writePly(const std::string& path) const {
  // (WriteTriangleMeshToPLY, not WriteTriangleMesh: the format is PLY whatever the name ends in,
  // e.g. the ".part" of OutputFolder's atomic writes)
  if (triangles() == 0)  // (Open3D writes no PLY of an empty mesh)
    throw std::runtime_error("the mesh " + path + " has no triangle to write");
  if (!open3d::io::WriteTriangleMeshToPLY(path, *m_mesh, false, false, true, true, false, false))
    throw std::runtime_error("could not write the mesh " + path);
}

std::vector<Eigen::Vector3d> SurfelMesh::vertexPositions() const {
  return m_mesh ? m_mesh->vertices_ : std::vector<Eigen::Vector3d>{};
}

std::vector<Eigen::Vector3d> SurfelMesh::vertexColours() const {
  return m_mesh ? m_mesh->vertex_colors_ : std::vector<Eigen::Vector3d>{};
}

}  // namespace rasm::meshing
