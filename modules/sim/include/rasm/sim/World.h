#pragma once
// A simulated world: static geometry (floor, walls, doors, furniture) and objects, each with an
// instance id, a class, a triangle mesh in its own frame, scale, pose and a material. Worlds are
// read from human-editable YAML files (schema and example: docs/sim.md). World frame: metres,
// z up, floor at z = 0 (the convention of MRPT's planar robots).

#include <Eigen/Geometry>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "rasm/models/Mesh.h"

namespace rasm::sim {

/// Procedural surface pattern, evaluated on the surface point in the object's frame (metres,
/// after scaling), so the colour is not uniform and photometric cues exist.
enum class Pattern { Solid, Checker, Stripes, Noise };

struct Material {
  Eigen::Vector3f colour_rgb{0.7f, 0.7f, 0.7f};  ///< RGB, file value / 255
  Eigen::Vector3f colour2_rgb{0.4f, 0.4f,
                              0.4f};  ///< second colour of the pattern (default 0.6 x colour)
  Pattern pattern = Pattern::Solid;
  float period_m = 0.1f;  ///< checker cell / stripe period / noise feature size
  int stripe_axis = 0;    ///< 0 = x, 1 = y, 2 = z (object frame)
};

struct WorldObject {
  std::uint16_t instance_id = 0;  ///< unique, >= 1 (0 is "nothing" in gt_instance)
  std::uint16_t class_id = 0;     ///< rasm::sim class id (SimClasses.h); 0 = unknown
  std::string name;               ///< optional human label ("desk_1")
  bool is_static = false;         ///< listed under `static:` (structure and furniture)
  std::string mesh_source;        ///< "box", "cylinder", "sphere" or the mesh file path
  models::TriangleMesh mesh;      ///< in the object frame, scale NOT applied
  Eigen::Vector3f scale{1.f, 1.f, 1.f};
  Eigen::Isometry3d T_world_object = Eigen::Isometry3d::Identity();
  Material material;

  /// Object-to-world affine map including scale: T_world_object * diag(scale).
  Eigen::Affine3f worldFromObjectScaled() const;
  /// The mesh in world coordinates.
  models::TriangleMesh worldMesh() const;
};

struct Light {
  Eigen::Vector3f direction_world{0.3f, 0.2f,
                                  -1.0f};  ///< direction light travels (normalized on load)
  float ambient = 0.35f;
  float diffuse = 0.65f;
};

struct World {
  std::string name;    ///< file stem or "inline"
  std::string source;  ///< file path (for messages)
  Light light;
  Eigen::Vector3f background_rgb{0.f, 0.f, 0.f};  ///< colour of rays that hit nothing
  std::vector<WorldObject> objects;               ///< static first, then objects, in file order

  /// Index into `objects` of an instance id, or -1.
  int indexOfInstance(std::uint16_t instance_id) const;
  /// World-space bounds of all geometry.
  Eigen::AlignedBox3f bounds() const;
};

/// Folder of the shipped worlds, models and trajectories: $RASM_SIM_DATA_DIR when set, else
/// <prefix>/share/rasm/sim beside an installed binary (<prefix>/bin), else the source folder
/// modules/sim compiled in as RASM_SIM_DATA_DIR.
std::string simDataDir();

/// "office" -> <simDataDir>/worlds/office.yaml when that exists; anything else is a path.
/// Throws InputError listing the shipped worlds when neither exists.
std::string resolveWorldPath(const std::string& name_or_path);
/// Names of the shipped worlds (stems of <simDataDir>/worlds/*.yaml), sorted.
std::vector<std::string> shippedWorlds();

/// Loads a world by shipped name or path. Mesh paths are relative to the world file's folder,
/// then <simDataDir>/models. Throws InputError "<file>:<line>: <key path>: <problem>".
World loadWorld(const std::string& name_or_path);
/// Parses YAML text; `source` names it in errors, `base_dir` resolves relative mesh paths.
World loadWorldFromString(const std::string& yaml, const std::string& source,
                          const std::string& base_dir = {});

}  // namespace rasm::sim
