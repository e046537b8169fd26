#pragma once
// A triangle mesh of the surfel map, for MeshLab, Open3D or Blender (mesh.ply, mesh_classes.ply).
//
// How: the map's stable surfels are rendered (SurfelRenderer: splatted depth and colour) at up to
// max_views camera poses spread evenly along the run's path, at width x height with the run's
// camera scaled, and the renders are fused into a truncated signed distance field (Curless and
// Levoy 1996; Open3D's ScalableTSDFVolume, voxel_m cells, truncation_m) from which marching cubes
// extracts the mesh, coloured by the fused RGB. The renders are the map itself seen from where the
// camera was, so the mesh holds what the map holds (denoised by fusion), closed over the splats'
// gaps, and nothing the camera never saw. A vertex's class colour (mesh_classes.ply) is that of
// the nearest surfel (labelColour faded towards the no-class colour as map_classes.ply).
// World frame, metres; binary PLY with vertex normals and colours.
//
// Open3D is loaded only when a mesh is built: the work happens in the plugin
// librasm_meshing_open3d.so beside this library (dlopen), so a run that writes no mesh does not
// pay Open3D's libraries in start-up time and memory (docs/viewing.md "The mesh").

#include <mrpt/config/CLoadableOptions.h>

#include <Eigen/Geometry>
#include <memory>
#include <string>
#include <vector>

#include "rasm/core/CameraIntrinsics.h"
#include "rasm/surfel_map/SurfelStore.h"

namespace rasm::meshing {

namespace detail {
class MeshBackend;  // the mesh held by the Open3D plugin (src/MeshBackend.h)
}

/// [mesh]
struct TMeshParams : mrpt::config::CLoadableOptions {
  /// TSDF cell: the mesh's resolution. Its memory grows as the band of cells around every
  /// surface, ~1/voxel_m^2: on the embedded default's map 2 cm (4 cells of truncation) took
  /// 509 MB more at its peak, 3 cm 220 MB (bench_mesh; docs/viewing.md "The mesh").
  double voxel_m = 0.03;
  /// TSDF truncation: three cells, beyond the rendered map's depth noise (the renders are the
  /// fused map, not raw depth).
  double truncation_m = 0.09;
  int max_views = 200;            ///< renders fused at most (evenly spaced along the path)
  int width = 320, height = 240;  ///< render size (the camera's intrinsics scaled)
  double max_depth_m = 4.0;       ///< farther rendered depth is not fused ([mapper] max_depth_m)

  void loadFromConfigFile(const mrpt::config::CConfigFileBase& c, const std::string& s) override;
  void saveToConfigFile(mrpt::config::CConfigFileBase& c, const std::string& s) const override;
  /// InputError naming [section] and the key of a value out of range.
  void validate(const std::string& section = "mesh") const;
};

class SurfelMesh {
 public:
  /// The mesh of `map` seen from the camera poses T_world_cam (optical frame) with intrinsics K.
  /// Empty (no triangle) when no pose sees a stable surfel. Throws InputError when K is not
  /// valid or params are out of range, std::runtime_error naming the plugin when Open3D's plugin
  /// cannot be loaded.
  static SurfelMesh build(const maps::SurfelStore& map,
                          const std::vector<Eigen::Isometry3d>& T_world_cam,
                          const CameraIntrinsics& K, const TMeshParams& params = {});

  /// Empty when meshes can be built; otherwise why not (Open3D's plugin did not load), to say
  /// before a run's outputs skip the mesh.
  static std::string unavailable();

  std::size_t vertices() const;
  std::size_t triangles() const;
  int views() const;  ///< renders fused

  /// Vertex colours become the class colour of the nearest alive surfel of `map`.
  void colourByClass(const maps::SurfelStore& map);
  /// Binary PLY (vertices with normals and RGB colours, triangles). Throws std::runtime_error
  /// when the mesh has no triangle or the file cannot be written.
  void writePly(const std::string& path) const;

  /// Every vertex as a point (tests).
  std::vector<Eigen::Vector3d> vertexPositions() const;
  std::vector<Eigen::Vector3d> vertexColours() const;  ///< RGB in [0, 1]

 private:
  std::shared_ptr<detail::MeshBackend> m_mesh;
};

}  // namespace rasm::meshing
