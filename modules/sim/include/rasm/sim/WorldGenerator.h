#pragma once
// Random worlds for `rasm sim generate` (docs/sim.md "Generated worlds"), in the world YAML
// schema, furnished from the shipped models (modules/sim/models) and primitives the way the shipped
// worlds are: desks, benches, tables, shelves and cabinets against the walls with chairs in front,
// objects resting on their surfaces (monitors, keyboards, laptops, mugs, bottles, books, boxes,
// unknown clutter), free-standing clutter along the walls, wall clocks, whiteboards and radiators,
// with colours and textures drawn from the shipped worlds' materials. Footprints never overlap
// (axis-aligned rectangle rejection sampling); the middle of every room stays free for a robot.
//
// Two layouts:
//  - room (default): one rectangular room (floor, four walls, ceiling, a door);
//  - flat: 2-5 rooms beside a hallway that runs the flat's length (one row of rooms north of it,
//    or, from 4 rooms, a row either side), each room open to the hallway through a doorway, the
//    flat's door at one end of the hallway.
// Break rooms (RoomKind::BreakRoom) and `plain_walls` give rooms whose long sides carry nothing
// (a bare wall) and, in break rooms, a long uniform kitchen counter: views a tracker finds hard.
//
// Deterministic: the same parameters give the same text, byte for byte (one std::mt19937_64
// stream read through raw bits, numbers printed rounded to the millimetre).

#include <Eigen/Core>
#include <cstdint>
#include <string>
#include <vector>

namespace rasm::sim {

/// What furnishes a room. BreakRoom: a kitchen counter along a long wall, tables, cabinets and
/// shelves on the other walls, and 1-2 plain long sides (see TWorldGenParams::plain_walls).
enum class RoomKind { Office, Lab, Mixed, BreakRoom };

/// "office", "lab", "mixed" or "break_room"; anything else throws InputError naming `what`
/// (e.g. "--kind").
RoomKind roomKindFromName(const std::string& name, const std::string& what = "kind");
const char* roomKindName(RoomKind kind);

enum class WorldLayout { Room, Flat };
/// "room" or "flat"; anything else throws InputError naming `what` (e.g. "--layout").
WorldLayout worldLayoutFromName(const std::string& name, const std::string& what = "layout");
const char* worldLayoutName(WorldLayout layout);

/// Parameters of a generated world. Sizes are the interior (the outer walls stand outside it).
struct TWorldGenParams {
  std::uint64_t seed = 0;
  /// Interior along x and y (m); <= 0: drawn from the seed (room: width 5.5-9 m, depth 4.5-7 m;
  /// flat: width 8-14 m (at least 3.6 m per room of a row), depth 6-10 m with one row of rooms,
  /// 9-11 m with two).
  double width_m = 0.0, depth_m = 0.0;
  /// Every room's kind; in a flat, Mixed draws each room's kind (office, lab, mixed or break room).
  RoomKind kind = RoomKind::Mixed;
  WorldLayout layout = WorldLayout::Room;
  /// Flat: number of rooms, 2-5 (up to 3 in one row north of the hallway, 4-5 in two rows).
  int rooms = 3;
  /// Long sides of each room left plain (no furniture, wall items or clutter against them): 0, 1
  /// or 2; -1: break rooms draw 1 or 2, other rooms have none. A plain side of a single room is
  /// painted with its wall's noise texture or a uniform colour (drawn); a flat's walls are shared
  /// and keep their material. A break room's counter stands along a long side that is not
  /// plain, or a short side when both long sides are.
  int plain_walls = -1;
  /// Flat: width of each doorway between a room and the hallway (m), at least 0.9 m (a 0.25 m
  /// robot passes with 0.2 m either side); doorways have a lintel at 2.05 m.
  double doorway_width_m = 1.0;
  double height_m = 2.7;
  /// The robot the free area is kept for: its footprint radius plus this clearance to furniture
  /// and walls (so its camera, 0.1 m ahead of the centre, never faces anything closer than the
  /// sensor's 0.4 m minimum depth).
  double robot_radius_m = 0.25;
  double clearance_m = 0.35;

  static constexpr double kMinSide_m = 3.0, kMaxSide_m = 16.0;
  /// Flat: rooms at least this wide and deep; the hallway is 1.4-1.8 m wide; flats at most
  /// kMaxFlatSide_m a side.
  static constexpr double kMinFlatRoom_m = 3.2, kMaxFlatSide_m = 20.0;
  /// Throws InputError naming the option (`--size`, `--rooms`, `--plain-walls`) when a value is
  /// outside its range.
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

  /// One room: where the robot's centre may be (every footprint stays robot_radius_m +
  /// clearance_m away). A flat: the hallway's free area (the robot's start and loop).
  GenRect free_area;

  /// The rooms: one for the room layout (interior x 0..W, y 0..D), `rooms` for a flat.
  struct Room {
    std::string name;  ///< room_1, room_2, ...
    RoomKind kind = RoomKind::Mixed;
    GenRect interior;
    GenRect free_area;  ///< as free_area above, for this room
    /// Flat: the opening to the hallway through the wall (x: the doorway's width, y: the wall's
    /// thickness); all 0 in the room layout.
    GenRect doorway;
    /// Sides (0 south y = y0, 1 east x = x1, 2 north y = y1, 3 west x = x0) with nothing against
    /// them.
    std::vector<int> plain_sides;
    /// Break rooms: the side the counter stands against and its footprint; -1 otherwise.
    int counter_side = -1;
    GenRect counter;
  };
  std::vector<Room> rooms;
  /// Flat: the hallway's interior (all 0 in the room layout).
  GenRect hallway;
  /// Where the robot's centre may be, as rectangles whose union is connected: one room's
  /// free_area; in a flat, the hallway's free area, each room's, and the centre line through each
  /// doorway (0 wide: the robot's radius plus (doorway_width_m / 2 - robot_radius_m) from the
  /// jambs) from one to the other.
  std::vector<GenRect> robot_free;
  /// Points worth looking at (centres of objects on surfaces, furniture, wall items).
  std::vector<Eigen::Vector3d> view_targets;
};

/// Generates a room or a flat; throws InputError for bad parameters (validate()).
GeneratedWorld generateWorld(const TWorldGenParams& params);

}  // namespace rasm::sim
