#pragma once
// The seam between librasm_meshing (no Open3D) and the plugin librasm_meshing_open3d.so that
// holds the mesh in Open3D's types. The plugin exports kBuildSymbol, a BuildFn.

#include <Eigen/Geometry>
#include <string>
#include <vector>

#include "rasm/core/CameraIntrinsics.h"
#include "rasm/meshing/SurfelMesh.h"
#include "rasm/surfel_map/SurfelStore.h"

namespace rasm::meshing::detail {

/// One mesh built by the plugin; SurfelMesh forwards to it.
class MeshBackend {
 public:
  virtual ~MeshBackend();
  virtual std::size_t vertices() const = 0;
  virtual std::size_t triangles() const = 0;
  virtual int views() const = 0;
  virtual void colourByClass(const maps::SurfelStore& map) = 0;
  virtual void writePly(const std::string& path) const = 0;
  virtual std::vector<Eigen::Vector3d> vertexPositions() const = 0;
  virtual std::vector<Eigen::Vector3d> vertexColours() const = 0;
};

/// SurfelMesh::build's work on checked arguments; the caller owns the result.
using BuildFn = MeshBackend* (*)(const maps::SurfelStore& map,
                                 const std::vector<Eigen::Isometry3d>& T_world_cam,
                                 const CameraIntrinsics& K, const TMeshParams& params);
inline constexpr const char* kBuildSymbol = "rasm_meshing_open3d_build";
inline constexpr const char* kPluginFile = "librasm_meshing_open3d.so";

}  // namespace rasm::meshing::detail
