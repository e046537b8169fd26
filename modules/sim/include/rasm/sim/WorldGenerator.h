#pragma once
// Random room worlds for `rasm sim generate` (docs/sim.md "Generated worlds"): one rectangular
// room (floor, four walls, ceiling, a door) in the world YAML schema, furnished from the shipped
// models (modules/sim/models) and primitives the way the shipped worlds are: desks, benches,
// tables, shelves and cabinets against the walls with chairs in front, objects resting on their
// surfaces (monitors, keyboards, laptops, mugs, bottles, books, boxes, unknown clutter),
// free-standing clutter along the walls, wall clocks, whiteboards and radiators, with colours and
// textures drawn from the shipped worlds' materials. Footprints never overlap (axis-aligned
// rectangle rejection sampling); the middle of the room stays free for a robot.
//
// Deterministic: the same parameters give the same text, byte for byte (one std::mt19937_64
// stream read through raw bits, numbers printed rounded to the millimetre).

#include <Eigen/Core>
#include <cstdint>
#include <string>
#include <vector>

namespace rasm::sim {

enum class RoomKind { Office, Lab, Mixed };

/// "office", "lab" or "mixed"; anything else throws InputError naming `what` (e.g. "--kind").
RoomKind roomKindFromName(const std::string& name, const std::string& what = "kind");
const char* roomKindName(RoomKind kind);

/// Parameters of one generated room. Sizes are the room's interior (walls outside it).
struct TWorldGenParams {
  std::uint64_t seed = 0;
  /// Interior along x and y (m); <= 0: drawn from the seed (width 5.5-9 m, depth 4.5-7 m).
  double width_m = 0.0, depth_m = 0.0;
  RoomKind kind = RoomKind::Mixed;
  double height_m = 2.7;
  /// The robot the free area is kept for: its footprint radius plus this clearance to furniture
  /// and walls (so its camera, 0.1 m ahead of the centre, never faces anything closer than the
  /// sensor's 0.4 m minimum depth).
  double robot_radius_m = 0.25;
  double clearance_m = 0.35;

  static constexpr double kMinSide_m = 3.0, kMaxSide_m = 16.0;
  /// Throws InputError naming `--size` when a side is outside [kMinSide_m, kMaxSide_m].
  void validate() const;
};

/// Axis-aligned rectangle in the world's xy plane.
struct GenRect {
  double x0 = 0, y0 = 0, x1 = 0, y1 = 0;
  double width() const { return x1 - x0; }
  double depth() const { return y1 - y0; }
  bool contains(double x, double y) const { return x >= x0 && x <= x1 && y >= y0 && y <= y1; }
  /// Interiors intersect (touching edges do not).
  bool overlaps(const GenRect& o) const { return x0 < o.x1 && o.x0 < x1 && y0 < o.y1 && o.y0 < y1; }
};

/// A generated world: the YAML text plus what the trajectory generator and the tests need.
struct GeneratedWorld {
  TWorldGenParams params;  ///< with the drawn size filled in
  std::string name;        ///< `world:` of the file, from the parameters (not the file name)
  std::string yaml;

  /// How an entry of the file rests.
  enum class Rest { Structure, Floor, Surface, Wall, Attached };
  struct Placement {
    std::uint16_t id = 0;
    std::string name, class_name;
    Rest rest = Rest::Floor;
    std::uint16_t support_id = 0;  ///< Surface: the furniture or object it stands on
    double surface_z_m = 0.0;      ///< Surface: height of that surface
    /// Stands on the floor (furniture, clutter, radiators, the door): its footprint overlaps no
    /// other's in 2-D.
    bool furniture = false;
    /// World xy bounds of its geometry (furniture: with the parts resting on it, a lamp's shade).
    GenRect footprint;
    double z0_m = 0.0, z1_m = 0.0;  ///< height bounds of its geometry
  };
  std::vector<Placement> placements;  ///< every entry, in file order

  /// Where the robot's centre may be: every footprint stays robot_radius_m + clearance_m away.
  GenRect free_area;
  /// Points worth looking at (centres of objects on surfaces, furniture, wall items).
  std::vector<Eigen::Vector3d> view_targets;
};

/// Generates a room; throws InputError for bad parameters (validate()).
GeneratedWorld generateWorld(const TWorldGenParams& params);

}  // namespace rasm::sim
