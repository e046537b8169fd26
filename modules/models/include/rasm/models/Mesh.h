#pragma once
// Triangle meshes: primitives, files loaded through assimp (OBJ, PLY, STL, ...) and OBJ output
// for the procedural models. The simulator's worlds are made of them and the zero-shot
// classifier renders its templates from them (classification/TemplateBank.h). Units are metres.

#include <Eigen/Geometry>
#include <string>
#include <vector>

namespace rasm::models {

struct TriangleMesh {
  std::vector<Eigen::Vector3f> vertices;
  std::vector<Eigen::Vector3i> triangles;  ///< vertex indices

  bool empty() const { return triangles.empty(); }
  /// Appends `other` moved by `T` (p' = T * p).
  void append(const TriangleMesh& other, const Eigen::Affine3f& T = Eigen::Affine3f::Identity());
  /// Axis-aligned bounds (min, max); both zero for an empty mesh.
  Eigen::AlignedBox3f bounds() const;
  /// Sum of triangle areas (m^2).
  double surfaceArea() const;
};

/// Box of edge lengths `size` centred at the origin (12 triangles).
TriangleMesh makeBox(const Eigen::Vector3f& size);
/// Closed cylinder of `radius`, axis z, centred at the origin (height along z).
TriangleMesh makeCylinder(float radius, float height, int segments = 32);
/// UV sphere centred at the origin.
TriangleMesh makeSphere(float radius, int rings = 16, int segments = 32);
/// Surface of revolution about z of a profile of (r, z) points; points with r == 0 become poles.
TriangleMesh makeLathe(const std::vector<Eigen::Vector2f>& profile_rz, int segments);
/// Prism: a simple polygon in the xy plane (counter-clockwise) extruded from z0 to z1, capped.
TriangleMesh makeExtrusion(const std::vector<Eigen::Vector2f>& polygon_xy, float z0, float z1);

/// Loads every mesh of a file through assimp (triangulated, node transforms applied).
/// Throws InputError naming `path` (and `what`, e.g. "world office.yaml objects[3].mesh") when
/// the file is missing, unreadable or holds no triangles, and for every file in a build without
/// the simulator (-DRASM_WITH_SIM=OFF), which has no assimp.
TriangleMesh loadMesh(const std::string& path, const std::string& what = "mesh");

/// Writes a Wavefront OBJ (vertices with 4 decimals, 1-based faces) with `comment` lines first.
void saveObj(const TriangleMesh& mesh, const std::string& path, const std::string& comment = {});

}  // namespace rasm::models
