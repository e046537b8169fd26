#include "rasm/sim/WorldGenerator.h"

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <map>
#include <random>
#include <sstream>

#include "GenUtil.h"
#include "rasm/core/Error.h"
#include "rasm/models/ClassVocabulary.h"
#include "rasm/models/Mesh.h"
#include "rasm/models/ProceduralModels.h"

namespace rasm::sim {

RoomKind roomKindFromName(const std::string& name, const std::string& what) {
  if (name == "office") return RoomKind::Office;
  if (name == "lab") return RoomKind::Lab;
  if (name == "mixed") return RoomKind::Mixed;
  if (name == "break_room") return RoomKind::BreakRoom;
  throwInputError(what + " " + name,
                  "unknown room kind; expected office, lab, mixed or break_room");
}

const char* roomKindName(RoomKind kind) {
  switch (kind) {
    case RoomKind::Office:
      return "office";
    case RoomKind::Lab:
      return "lab";
    case RoomKind::BreakRoom:
      return "break_room";
    case RoomKind::Mixed:
      break;
  }
  return "mixed";
}

WorldLayout worldLayoutFromName(const std::string& name, const std::string& what) {
  if (name == "room") return WorldLayout::Room;
  if (name == "flat") return WorldLayout::Flat;
  throwInputError(what + " " + name, "unknown layout; expected room or flat");
}

const char* worldLayoutName(WorldLayout layout) {
  return layout == WorldLayout::Flat ? "flat" : "room";
}

namespace {

/// Flat: rows of rooms (one north of the hallway up to 3 rooms, else one either side) and the
/// most rooms in a row.
int flatRows(int rooms) {
  return rooms >= 4 ? 2 : 1;
}
int flatRowRooms(int rooms) {
  return flatRows(rooms) == 2 ? rooms - rooms / 2 : rooms;
}
constexpr double kWall_m = 0.1, kMaxHallway_m = 1.8;
/// Plain sides: nothing stands or hangs within this distance of the wall.
constexpr double kPlainKeep_m = 0.3;

/// The flat's options and, when given, its size.
void validateFlat(const TWorldGenParams& p) {
  if (p.rooms < 2 || p.rooms > 5)
    throwInputError("--rooms " + std::to_string(p.rooms), "expected 2 to 5 rooms in a flat");
  if (!(p.doorway_width_m >= 0.9 && p.doorway_width_m <= 1.6))
    throwInputError("doorway width " + gen::num(p.doorway_width_m),
                    "expected 0.9-1.6 m (a 0.25 m robot with clearance)");
  if (p.width_m <= 0.0 && p.depth_m <= 0.0) return;
  const std::string what = "--size " + gen::num(p.width_m, 2) + "x" + gen::num(p.depth_m, 2);
  if (!std::isfinite(p.width_m) || !std::isfinite(p.depth_m) || p.width_m <= 0.0 ||
      p.depth_m <= 0.0)
    throwInputError(what, "expected two positive sizes in metres, WxD (e.g. 12x8)");
  const int k = flatRowRooms(p.rooms), rows = flatRows(p.rooms);
  const double min_w = k * TWorldGenParams::kMinFlatRoom_m + (k - 1) * kWall_m;
  const double min_d = rows * (TWorldGenParams::kMinFlatRoom_m + kWall_m) + kMaxHallway_m;
  if (p.width_m < min_w - 1e-9 || p.depth_m < min_d - 1e-9)
    throwInputError(what, "too small for a flat of " + std::to_string(p.rooms) +
                              " rooms: expected at least " + gen::num(min_w, 2) + "x" +
                              gen::num(min_d, 2) + " m (" + std::to_string(k) +
                              " rooms of at least " + gen::num(TWorldGenParams::kMinFlatRoom_m) +
                              " m a side in " + (rows == 2 ? "each of two rows" : "a row") +
                              " beside a hallway of up to " + gen::num(kMaxHallway_m) + " m)");
  if (std::max(p.width_m, p.depth_m) > TWorldGenParams::kMaxFlatSide_m)
    throwInputError(what, "too large: each side of a flat must be at most " +
                              gen::num(TWorldGenParams::kMaxFlatSide_m) + " m");
}

}  // namespace

void TWorldGenParams::validate() const {
  if (plain_walls < -1 || plain_walls > 2)
    throwInputError("--plain-walls " + std::to_string(plain_walls),
                    "expected 0, 1 or 2 (long sides of each room left without furniture)");
  if (layout == WorldLayout::Flat) validateFlat(*this);
  const bool drawn = width_m <= 0.0 && depth_m <= 0.0;
  if (!drawn && layout == WorldLayout::Room) {
    const std::string what = "--size " + gen::num(width_m, 2) + "x" + gen::num(depth_m, 2);
    if (!std::isfinite(width_m) || !std::isfinite(depth_m) || width_m <= 0.0 || depth_m <= 0.0)
      throwInputError(what, "expected two positive sizes in metres, WxD (e.g. 7x5)");
    if (std::min(width_m, depth_m) < kMinSide_m)
      throwInputError(what, "too small for a room: each side must be at least " +
                                gen::num(kMinSide_m) +
                                " m (furniture along the walls, a 0.25 m robot with its "
                                "clearance and a free area of at least 1 m in the middle)");
    if (std::max(width_m, depth_m) > kMaxSide_m)
      throwInputError(what, "too large: each side must be at most " + gen::num(kMaxSide_m) +
                                " m (the sensor sees 4.5 m)");
  }
  if (!(height_m >= 2.2 && height_m <= 5.0))
    throwInputError("room height " + gen::num(height_m), "expected 2.2-5 m");
  if (!(robot_radius_m > 0.0 && robot_radius_m <= 0.6) ||
      !(clearance_m >= 0.0 && clearance_m <= 1.0))
    throwInputError("robot radius / clearance",
                    "expected a radius in (0, 0.6] m and a clearance in [0, 1] m");
}

namespace {

using gen::num;
using gen::Rng;
using Rest = GeneratedWorld::Rest;
using V2 = Eigen::Vector2d;
using V3 = Eigen::Vector3d;

double r3(double v) {
  return std::round(v * 1000.0) / 1000.0;
}
double r1(double v) {
  return std::round(v * 10.0) / 10.0;
}

// ---- materials: the colours and textures of the shipped worlds ----------------------------------

struct Rgb {
  int r = 180, g = 180, b = 180;
};
struct Mat {
  Rgb c;
  std::string pattern;  ///< empty: plain colour
  Rgb c2;
  double period_m = 0.1;
  char axis = 0;  ///< stripes: 'x', 'y' or 'z'
};

Mat plain(Rgb c) {
  return Mat{c, {}, {}, 0.1, 0};
}
Mat tex(Rgb c, const char* p, Rgb c2, double period, char axis = 0) {
  return Mat{c, p, c2, period, axis};
}

const std::vector<Mat>& floorMats() {
  static const std::vector<Mat> v = {tex({150, 150, 145}, "checker", {120, 120, 118}, 0.5),
                                     tex({110, 115, 120}, "noise", {90, 95, 100}, 0.15),
                                     tex({120, 120, 120}, "checker", {95, 95, 95}, 0.3),
                                     tex({160, 130, 95}, "stripes", {140, 112, 80}, 0.12, 'x'),
                                     tex({160, 130, 95}, "stripes", {140, 112, 80}, 0.12, 'y')};
  return v;
}
const std::vector<Mat>& wallMats() {
  static const std::vector<Mat> v = {tex({215, 210, 190}, "noise", {195, 190, 172}, 0.3),
                                     tex({200, 210, 215}, "noise", {180, 190, 196}, 0.3),
                                     tex({225, 225, 215}, "noise", {205, 205, 195}, 0.4),
                                     tex({220, 215, 200}, "noise", {200, 195, 180}, 0.3),
                                     tex({205, 215, 220}, "noise", {185, 195, 200}, 0.3)};
  return v;
}
const std::vector<Mat>& deskMats() {
  static const std::vector<Mat> v = {tex({160, 120, 80}, "noise", {125, 90, 55}, 0.05),
                                     plain({230, 230, 225}),
                                     tex({110, 80, 55}, "noise", {90, 62, 40}, 0.06),
                                     tex({190, 160, 110}, "noise", {160, 130, 90}, 0.04)};
  return v;
}
const Mat& benchMat() {
  static const Mat m = tex({200, 200, 195}, "noise", {175, 175, 170}, 0.08);
  return m;
}
const std::vector<Mat>& shelfMats() {
  static const std::vector<Mat> v = {tex({195, 175, 135}, "stripes", {180, 160, 120}, 0.03, 'y'),
                                     plain({150, 150, 160})};
  return v;
}
const std::vector<Mat>& cabinetMats() {
  static const std::vector<Mat> v = {tex({90, 110, 140}, "noise", {70, 88, 115}, 0.2),
                                     tex({190, 160, 110}, "noise", {160, 130, 90}, 0.04),
                                     plain({170, 170, 175})};
  return v;
}
const std::vector<Mat>& cardboardMats() {
  static const std::vector<Mat> v = {tex({185, 145, 95}, "stripes", {205, 175, 125}, 0.1, 'x'),
                                     tex({190, 150, 100}, "stripes", {160, 125, 80}, 0.15, 'z'),
                                     plain({175, 135, 85}), plain({120, 120, 125})};
  return v;
}
const std::vector<Rgb>& chairColours() {
  static const std::vector<Rgb> v = {{40, 55, 100}, {100, 40, 40}, {60, 60, 60}, {60, 70, 90}};
  return v;
}
const std::vector<Rgb>& counterColours() {
  static const std::vector<Rgb> v = {
      {235, 235, 230}, {150, 150, 155}, {170, 140, 100}, {60, 60, 65}};
  return v;
}
const std::vector<Mat>& doorMats() {
  static const std::vector<Mat> v = {tex({140, 95, 60}, "stripes", {120, 80, 50}, 0.04, 'z'),
                                     plain({90, 100, 130})};
  return v;
}

Rgb randomColour(Rng& rng, int lo = 30, int hi = 230) {
  return {lo + rng.index(hi - lo + 1), lo + rng.index(hi - lo + 1), lo + rng.index(hi - lo + 1)};
}

// ---- entries ------------------------------------------------------------------------------------

struct Shape {
  enum Kind { Model, Box, Cylinder, Sphere } kind = Box;
  std::string model;  ///< "desk" -> desk.obj
  V3 size = V3::Zero();
  double radius = 0.0, height = 0.0;
};

Shape model(const char* name) {
  return Shape{Shape::Model, name, V3::Zero(), 0, 0};
}
Shape box(double x, double y, double z) {
  return Shape{Shape::Box, {}, V3(r3(x), r3(y), r3(z)), 0, 0};
}
Shape cylinder(double r, double h) {
  return Shape{Shape::Cylinder, {}, V3::Zero(), r3(r), r3(h)};
}
Shape sphere(double r) {
  return Shape{Shape::Sphere, {}, V3::Zero(), r3(r), 0};
}

struct Box3 {
  V3 lo = V3::Constant(1e30), hi = V3::Constant(-1e30);
  void extend(const V3& p) {
    lo = lo.cwiseMin(p);
    hi = hi.cwiseMax(p);
  }
  GenRect rect() const { return {lo.x(), lo.y(), hi.x(), hi.y()}; }
  V3 centre() const { return 0.5 * (lo + hi); }
};

GenRect unite(const GenRect& a, const GenRect& b) {
  return {std::min(a.x0, b.x0), std::min(a.y0, b.y0), std::max(a.x1, b.x1), std::max(a.y1, b.y1)};
}
Box3 boxOf(const GenRect& r) {
  Box3 b;
  b.extend(V3(r.x0, r.y0, 0.0));
  b.extend(V3(r.x1, r.y1, 0.0));
  return b;
}
bool overlaps2d(const GenRect& a, const GenRect& b, double gap) {
  return a.x0 < b.x1 + gap && b.x0 < a.x1 + gap && a.y0 < b.y1 + gap && b.y0 < a.y1 + gap;
}

/// Boxes intersect: xy closer than `gap_xy`, z interiors overlapping (touching is fine).
bool overlaps(const Box3& a, const Box3& b, double gap_xy) {
  return a.lo.x() < b.hi.x() + gap_xy && b.lo.x() < a.hi.x() + gap_xy &&
         a.lo.y() < b.hi.y() + gap_xy && b.lo.y() < a.hi.y() + gap_xy &&
         a.lo.z() < b.hi.z() - 1e-6 && b.lo.z() < a.hi.z() - 1e-6;
}

struct Entry {
  bool is_static = false;
  std::string cls, name;
  Shape shape;
  V3 scale = V3::Ones();
  V3 pos = V3::Zero();
  double yaw = 0.0, pitch = 0.0, roll = 0.0;  ///< degrees, world
  Mat mat;
  Rest rest = Rest::Floor;
  int support = -1;  ///< entry index
  double surface_z = 0.0;
  /// Stands on the floor: its footprint `foot` (its own, or with the parts above it: a lamp's
  /// shade, a pot's plant) overlaps no other in 2-D, whatever the heights.
  bool furniture = false;
  GenRect foot;
  int side = -1;  ///< wall it stands against (for the band bookkeeping)
  Box3 box;       ///< world bounds
};

/// A wall of the room as a frame: v = distance into the room from the wall's inner face along
/// the inward normal n, u = position along the wall (t = z x n), local yaw 0 = facing n.
struct Side {
  V2 origin, n, t;
  double length = 0.0, yaw_deg = 0.0;
  V2 at(double v, double u) const { return origin + v * n + u * t; }
  /// v and u ranges of a world box.
  void range(const Box3& b, double& v0, double& v1, double& u0, double& u1) const {
    v0 = u0 = 1e30;
    v1 = u1 = -1e30;
    for (double x : {b.lo.x(), b.hi.x()})
      for (double y : {b.lo.y(), b.hi.y()}) {
        const V2 d = V2(x, y) - origin;
        v0 = std::min(v0, d.dot(n));
        v1 = std::max(v1, d.dot(n));
        u0 = std::min(u0, d.dot(t));
        u1 = std::max(u1, d.dot(t));
      }
  }
};

/// A horizontal surface objects can stand on: a rectangle in the frame of the side its
/// furniture stands against.
struct Surface {
  int entry = -1;
  int side = 0;
  double z = 0.0;
  double v0 = 0, v1 = 0, u0 = 0, u1 = 0;
  double max_height = 0.6;
};

double wrapDeg(double a) {
  a = std::fmod(a, 360.0);
  if (a > 180.0) a -= 360.0;
  if (a <= -180.0) a += 360.0;
  return a;
}

/// A room before and after it is furnished: its interior, the bands along its walls, what its
/// walls may carry, and (flat) its doorway to the hallway.
struct RoomPlan {
  GenRect rect;
  RoomKind kind = RoomKind::Mixed;
  double budget[4] = {0, 0, 0, 0};  ///< how far furniture may reach into the room from each side
  Rgb chair;
  bool plain[4] = {false, false, false, false};
  int counter_side = -1;
  int hall_side = -1;     ///< flat: the side open to the hallway (0 south or 2 north)
  double door_x = 0.0;    ///< flat: the doorway's centre (world x)
  std::size_t first = 0;  ///< its first entry
  GenRect free_area, counter;
};

class Generator {
 public:
  explicit Generator(const TWorldGenParams& p) : m_p(p), m_rng(p.seed) {}

  GeneratedWorld run();

 private:
  // layouts
  void drawSize();
  void runRoom(GeneratedWorld& g);
  void runFlat(GeneratedWorld& g);
  std::vector<RoomPlan> planFlatRooms(double hy0, double hy1);
  void setSides(const GenRect& r);
  RoomPlan planRoom(const GenRect& r, RoomKind kind);
  void planPlainSides(RoomPlan& p, int n);
  void planDoorway(RoomPlan& p);
  Box3 doorwayKeepout(const RoomPlan& p) const;
  void enterRoom(const RoomPlan& p);
  void addStructure(const std::string& name, const char* cls, Shape sh, V3 pos, const Mat& mat);
  void roomStructure(const RoomPlan& p);
  void flatStructure(const std::vector<RoomPlan>& plans, double hy0, double hy1);
  void furnish(RoomPlan& p);
  GenRect freeAreaOf(std::size_t first) const;
  GeneratedWorld::Room roomOf(const RoomPlan& p, int index) const;
  void writeYaml(GeneratedWorld& g);

  // geometry
  const models::TriangleMesh& mesh(const Shape& s);
  Eigen::Matrix3d linear(const Entry& e) const;
  void computeBox(Entry& e);
  /// Sets the entry's world pose from side coordinates and a local yaw; z is the height of the
  /// bottom of its geometry (the origin is placed so the lowest point is there).
  void poseOnSide(Entry& e, int side, double v, double u, double yaw_local, double bottom_z);

  // placement
  bool insideRoom(const Box3& b, double margin = 0.005) const;
  double inward(const Box3& b, int side) const;
  bool collides(const Box3& b, double gap, int ignore1 = -1, int ignore2 = -1,
                const std::vector<Entry>* staged = nullptr) const;
  bool floorOk(const Entry& e, const std::vector<Entry>& staged) const;
  int commit(Entry e);
  bool placeOn(const Surface& s, Entry e, double v, double u, double yaw_local);
  bool placeOnRandom(const Surface& s, Entry e, int tries = 25);

  // units
  void door(int side);
  bool counterUnit(int side, GenRect& footprint);
  bool deskUnit(int side, int style);
  bool shelfUnit(int side, bool lab);
  bool cabinetUnit(int side);
  bool boxStack(int side);
  bool floorClutter(int side);
  bool wallItem(int side, int what);

  // surface contents
  void populateDesk(const Surface& s, int style, double u_centre, double width);
  void populateShelf(const Surface& s, bool lab, bool top);
  void populateCabinet(const Surface& s);
  Entry smallItem(bool lab);
  Entry cardboard(double sx, double sy, double sz);

  std::string entryYaml(const Entry& e, int id) const;

  TWorldGenParams m_p;
  Rng m_rng;
  double m_w = 0, m_d = 0, m_h = 2.7, m_c = 0.6;
  GenRect m_room;  ///< the room being furnished (the flat's hallway while its door is placed)
  RoomKind m_kind = RoomKind::Mixed;
  std::string m_header, m_description;  ///< of the file: comment lines, `description:`
  Side m_sides[4];
  double m_budget[4] = {0, 0, 0, 0};
  std::vector<Entry> m_e;
  std::vector<Box3> m_keepout;
  std::map<std::string, models::TriangleMesh> m_models;
  std::map<std::string, int> m_count;  ///< for names: desk_1, desk_2, ...
  Rgb m_chair;
  bool m_officeish = true, m_labish = false;
  std::string nextName(const std::string& base) {
    return base + "_" + std::to_string(++m_count[base]);
  }
};

const models::TriangleMesh& Generator::mesh(const Shape& s) {
  std::string key;
  switch (s.kind) {
    case Shape::Model:
      key = "model:" + s.model;
      break;
    case Shape::Box:
      key = "box";
      break;
    case Shape::Cylinder:
      key = "cylinder:" + num(s.radius) + ":" + num(s.height);
      break;
    case Shape::Sphere:
      key = "sphere:" + num(s.radius);
      break;
  }
  auto it = m_models.find(key);
  if (it != m_models.end()) return it->second;
  models::TriangleMesh m;
  switch (s.kind) {
    case Shape::Model:
      m = models::makeProceduralModel(s.model);
      break;
    case Shape::Box:
      m = models::makeBox(Eigen::Vector3f::Ones());  // scaled by the size below
      break;
    case Shape::Cylinder:
      m = models::makeCylinder(float(s.radius), float(s.height));
      break;
    case Shape::Sphere:
      m = models::makeSphere(float(s.radius));
      break;
  }
  return m_models.emplace(key, std::move(m)).first->second;
}

Eigen::Matrix3d Generator::linear(const Entry& e) const {
  const double d = M_PI / 180.0;
  const Eigen::Matrix3d R =
      (Eigen::AngleAxisd(e.yaw * d, V3::UnitZ()) * Eigen::AngleAxisd(e.pitch * d, V3::UnitY()) *
       Eigen::AngleAxisd(e.roll * d, V3::UnitX()))
          .toRotationMatrix();
  V3 s = e.scale;
  if (e.shape.kind == Shape::Box) s = s.cwiseProduct(e.shape.size);
  return R * s.asDiagonal();
}

void Generator::computeBox(Entry& e) {
  const Eigen::Matrix3d M = linear(e);
  e.box = Box3();
  for (const auto& v : mesh(e.shape).vertices) e.box.extend(M * v.cast<double>() + e.pos);
}

void Generator::poseOnSide(Entry& e, int side, double v, double u, double yaw_local,
                           double bottom_z) {
  const Side& s = m_sides[side];
  e.yaw = r1(wrapDeg(s.yaw_deg + yaw_local));
  const V2 xy = s.at(v, u);
  const Eigen::Matrix3d M = linear(e);
  double zmin = 1e30;
  for (const auto& p : mesh(e.shape).vertices) zmin = std::min(zmin, (M * p.cast<double>()).z());
  e.pos = V3(r3(xy.x()), r3(xy.y()), r3(bottom_z - zmin));
  if (std::abs(e.pos.z()) < 5e-4) e.pos.z() = 0.0;
  computeBox(e);
  e.foot = e.box.rect();
}

bool Generator::insideRoom(const Box3& b, double m) const {
  return b.lo.x() >= m_room.x0 + m && b.lo.y() >= m_room.y0 + m && b.hi.x() <= m_room.x1 - m &&
         b.hi.y() <= m_room.y1 - m && b.hi.z() <= m_h - 0.05;
}

double Generator::inward(const Box3& b, int side) const {
  double v0, v1, u0, u1;
  m_sides[side].range(b, v0, v1, u0, u1);
  return v1;
}

bool Generator::collides(const Box3& b, double gap, int ignore1, int ignore2,
                         const std::vector<Entry>* staged) const {
  for (int i = 0; i < int(m_e.size()); ++i) {
    if (i == ignore1 || i == ignore2 || m_e[i].rest == Rest::Structure) continue;
    if (overlaps(b, m_e[i].box, gap)) return true;
  }
  for (const Box3& k : m_keepout)
    if (overlaps(b, k, 0.0)) return true;
  if (staged)
    for (const Entry& s : *staged)
      if (overlaps(b, s.box, gap)) return true;
  return false;
}

/// A floor-standing entry of a unit: inside the room, within its side's band, clear of
/// everything placed in 3-D and of every other footprint on the floor in 2-D (and of the unit's
/// other parts).
bool Generator::floorOk(const Entry& e, const std::vector<Entry>& staged) const {
  if (!insideRoom(e.box) || !insideRoom(boxOf(e.foot))) return false;
  if (e.side >= 0 && inward(boxOf(e.foot), e.side) > m_budget[e.side]) return false;
  if (collides(e.box, 0.03, -1, -1, &staged)) return false;
  const double gap = 0.03;
  for (const Entry& o : m_e)
    if (o.furniture && overlaps2d(e.foot, o.foot, gap)) return false;
  for (const Entry& o : staged)
    if (o.furniture && overlaps2d(e.foot, o.foot, gap)) return false;
  return true;
}

int Generator::commit(Entry e) {
  m_e.push_back(std::move(e));
  return int(m_e.size()) - 1;
}

bool Generator::placeOn(const Surface& s, Entry e, double v, double u, double yaw_local) {
  poseOnSide(e, s.side, v, u, yaw_local, s.z);
  double v0, v1, u0, u1;
  m_sides[s.side].range(e.box, v0, v1, u0, u1);
  const double m = 0.01;
  if (v0 < s.v0 + m || v1 > s.v1 - m || u0 < s.u0 + m || u1 > s.u1 - m) return false;
  if (e.box.hi.z() - s.z > s.max_height || !insideRoom(e.box)) return false;
  if (collides(e.box, 0.008, s.entry, m_e[std::size_t(s.entry)].support)) return false;
  e.rest = Rest::Surface;
  e.support = s.entry;
  e.surface_z = s.z;
  e.side = -1;
  commit(std::move(e));
  return true;
}

bool Generator::placeOnRandom(const Surface& s, Entry e, int tries) {
  for (int k = 0; k < tries; ++k) {
    const double v = m_rng.uniform(s.v0, s.v1), u = m_rng.uniform(s.u0, s.u1);
    if (placeOn(s, e, v, u, m_rng.uniform(-180.0, 180.0))) return true;
  }
  return false;
}

// ---- units against the walls --------------------------------------------------------------------

void Generator::door(int side) {
  const Side& s = m_sides[side];
  const double u = m_rng.uniform(0.8, s.length - 0.8);
  Entry d;
  d.is_static = true;
  d.cls = "door";
  d.name = "door";
  d.shape = box(0.04, 0.9, 2.05);
  d.mat = m_rng.pick(doorMats());
  d.rest = Rest::Wall;
  d.furniture = true;
  d.side = side;
  poseOnSide(d, side, 0.02, u, 0.0, 0.0);
  commit(d);
  // Keep the door's swing free: 0.95 m into the room, 0.55 m either side of its centre.
  Box3 k;
  for (double v : {0.0, 0.95})
    for (double w : {u - 0.55, u + 0.55}) {
      const V2 p = s.at(v, w);
      k.extend(V3(p.x(), p.y(), 0.0));
      k.extend(V3(p.x(), p.y(), m_h));
    }
  m_keepout.push_back(k);
}

/// style 0: office desk, 1: table, 2: lab bench.
bool Generator::deskUnit(int side, int style) {
  const Side& s = m_sides[side];
  Entry desk;
  desk.is_static = true;
  desk.cls = "dining table";
  desk.shape = model("desk");
  desk.furniture = true;
  desk.side = side;
  if (style == 0) {
    desk.scale = V3(1.0, m_rng.chance(0.3) ? 1.15 : 1.0, 1.0);
    desk.mat = m_rng.pick(deskMats());
  } else if (style == 1) {
    desk.scale = V3(r3(m_rng.uniform(1.1, 1.3)), r3(m_rng.uniform(1.0, 1.3)), 1.0);
    desk.mat = m_rng.pick(deskMats());
  } else {
    desk.scale = V3(1.1, r3(m_rng.uniform(1.5, 2.2)), 1.2);
    desk.mat = benchMat();
  }
  const double half_depth = 0.35 * desk.scale.x(), half_width = 0.70 * desk.scale.y();
  if (s.length < 2 * half_width + 0.1) return false;
  const double gap = style == 2 ? m_rng.uniform(0.02, 0.1) : m_rng.uniform(0.05, 0.25);
  const double u = m_rng.uniform(half_width + 0.02, s.length - half_width - 0.02);
  poseOnSide(desk, side, gap + half_depth, u, 0.0, 0.0);
  std::vector<Entry> staged;
  if (!floorOk(desk, staged)) return false;
  desk.name = nextName(style == 0 ? "desk" : style == 1 ? "table" : "bench");
  staged.push_back(desk);

  // Chairs in front, facing the desk; a chair that does not fit is left out.
  const int chairs = style == 0   ? (m_rng.chance(0.85) ? 1 : 0)
                     : style == 1 ? 1 + m_rng.index(2)
                                  : m_rng.index(3);
  const double front = gap + 2 * half_depth;
  for (int i = 0; i < chairs; ++i) {
    Entry c;
    c.cls = "chair";
    c.shape = model("chair");
    c.mat = plain(m_chair);
    c.furniture = true;
    c.side = side;
    const double slot = 2 * half_width / chairs;
    const double cu =
        u - half_width + slot * (i + 0.5) + m_rng.uniform(-0.25, 0.25) * std::min(slot - 0.5, 0.5);
    const double yaw = 180.0 + m_rng.uniform(-20.0, 20.0);
    poseOnSide(c, side, 0.0, cu, yaw, 0.0);
    double v0, v1, u0, u1;
    s.range(c.box, v0, v1, u0, u1);
    poseOnSide(c, side, front + 0.04 + m_rng.uniform(0.0, 0.12) - v0, cu, yaw, 0.0);
    if (floorOk(c, staged)) staged.push_back(c);
  }
  const int desk_index = int(m_e.size());
  for (Entry& e : staged) commit(std::move(e));

  Surface top;
  top.entry = desk_index;
  top.side = side;
  top.z = 0.74 * desk.scale.z();
  top.v0 = gap;
  top.v1 = front;
  top.u0 = u - half_width;
  top.u1 = u + half_width;
  top.max_height = 0.6;
  populateDesk(top, style, u, 2 * half_width);
  return true;
}

bool Generator::shelfUnit(int side, bool lab) {
  const Side& s = m_sides[side];
  Entry sh;
  sh.is_static = true;
  sh.cls = "shelf";
  sh.shape = model("shelf");
  sh.furniture = true;
  sh.side = side;
  sh.mat = lab ? plain({150, 150, 160}) : m_rng.pick(shelfMats());
  const double gap = m_rng.uniform(0.01, 0.05);
  const double u = m_rng.uniform(0.42, s.length - 0.42);
  poseOnSide(sh, side, gap + 0.175, u, 0.0, 0.0);
  if (!floorOk(sh, {})) return false;
  sh.name = nextName("shelf");
  const int index = commit(sh);
  // Board tops of shelf.obj at 0.02, 0.46, 0.91, 1.36 m (0.43 m apart) and the top at 1.80 m;
  // inside: 0.76 m wide, from the back panel (0.165 m behind the centre) to the front edge.
  const double levels[] = {0.02, 0.46, 0.91, 1.36};
  for (int k = 0; k < 4; ++k) {
    if (!m_rng.chance(k == 0 ? 0.5 : 0.85)) continue;
    Surface lv{index, side, levels[k], gap + 0.01, gap + 0.35, u - 0.38, u + 0.38, 0.39};
    populateShelf(lv, lab, false);
  }
  if (m_rng.chance(0.35)) {
    Surface top{index, side, 1.80, gap, gap + 0.35, u - 0.40, u + 0.40, 0.45};
    populateShelf(top, lab, true);
  }
  return true;
}

bool Generator::cabinetUnit(int side) {
  const Side& s = m_sides[side];
  Entry c;
  c.is_static = true;
  c.cls = "none";
  c.furniture = true;
  c.side = side;
  const double d = r3(m_rng.uniform(0.4, 0.5)), w = r3(m_rng.uniform(0.8, 1.6)),
               h = r3(m_rng.uniform(0.75, 1.0));
  c.shape = box(d, w, h);
  c.mat = m_rng.pick(cabinetMats());
  const double gap = m_rng.uniform(0.01, 0.05);
  if (s.length < w + 0.1) return false;
  const double u = m_rng.uniform(w / 2 + 0.02, s.length - w / 2 - 0.02);
  poseOnSide(c, side, gap + d / 2, u, 0.0, 0.0);
  if (!floorOk(c, {})) return false;
  c.name = nextName("cabinet");
  const int index = commit(c);
  populateCabinet(Surface{index, side, h, gap, gap + d, u - w / 2, u + w / 2, 0.6});
  return true;
}

/// A kitchen counter: one box of a uniform colour, 0.9 m high, 0.6 m deep, 3-5 m long (shorter
/// where the wall or what stands along it leaves less room, down to 1.5 m), bare.
bool Generator::counterUnit(int side, GenRect& footprint) {
  const Side& s = m_sides[side];
  const Mat mat = plain(m_rng.pick(counterColours()));
  for (double len = r1(std::min(m_rng.uniform(3.0, 5.0), s.length - 0.2)); len >= 1.5;
       len = r1(len - 0.3)) {
    for (int t = 0; t < 20; ++t) {
      Entry c;
      c.is_static = true;
      c.cls = "none";
      c.furniture = true;
      c.side = side;
      c.shape = box(0.6, len, 0.9);
      c.mat = mat;
      poseOnSide(c, side, 0.01 + 0.3, m_rng.uniform(len / 2 + 0.02, s.length - len / 2 - 0.02), 0.0,
                 0.0);
      if (!floorOk(c, {})) continue;
      c.name = nextName("counter");
      footprint = c.foot;
      commit(c);
      return true;
    }
  }
  return false;
}

Entry Generator::cardboard(double sx, double sy, double sz) {
  Entry b;
  b.cls = "box";
  b.shape = box(sx, sy, sz);
  b.mat = m_rng.pick(cardboardMats());
  return b;
}

bool Generator::boxStack(int side) {
  const Side& s = m_sides[side];
  Entry b = cardboard(m_rng.uniform(0.4, 0.6), m_rng.uniform(0.35, 0.6), m_rng.uniform(0.3, 0.5));
  b.furniture = true;
  b.side = side;
  const double yaw = m_rng.uniform(-20.0, 20.0);
  const double u = m_rng.uniform(0.4, s.length - 0.4);
  poseOnSide(b, side, 0.0, u, yaw, 0.0);
  double v0, v1, u0, u1;
  s.range(b.box, v0, v1, u0, u1);
  poseOnSide(b, side, m_rng.uniform(0.02, 0.3) - v0, u, yaw, 0.0);
  if (!floorOk(b, {})) return false;
  b.name = nextName("box");
  int below = commit(b);
  const int n = m_rng.index(3);  // 0-2 more on top
  for (int k = 0; k < n; ++k) {
    const Entry& lo = m_e[std::size_t(below)];
    const V3 size = lo.shape.size;
    Entry up = cardboard(size.x() * m_rng.uniform(0.6, 0.95), size.y() * m_rng.uniform(0.6, 0.95),
                         m_rng.uniform(0.2, 0.4));
    up.name = nextName("box");
    double lv0, lv1, lu0, lu1;
    s.range(lo.box, lv0, lv1, lu0, lu1);
    const Surface top{below,      side,       lo.box.hi.z(), lv0 - 0.02,
                      lv1 + 0.02, lu0 - 0.02, lu1 + 0.02,    0.45};
    const V3 c = lo.box.centre();
    const V2 d = V2(c.x(), c.y()) - s.origin;
    const double yaw_up = wrapDeg(lo.yaw - s.yaw_deg + m_rng.uniform(-15.0, 15.0));
    if (!placeOn(top, up, d.dot(s.n) + m_rng.uniform(-0.04, 0.04),
                 d.dot(s.t) + m_rng.uniform(-0.04, 0.04), yaw_up))
      break;
    below = int(m_e.size()) - 1;
  }
  return true;
}

bool Generator::floorClutter(int side) {
  const Side& s = m_sides[side];
  Entry a;
  a.furniture = true;
  a.side = side;
  a.cls = "none";
  // 0 bin, 1 potted plant, 2 backpack, 3 ball, 4 box, 5 gas cylinder (lab), 6 floor lamp (office)
  std::vector<int> kinds = {0, 1, 2, 3, 4};
  if (m_labish) kinds.push_back(5);
  if (m_officeish) kinds.push_back(6);
  const int what = m_rng.pick(kinds);
  if (what == 0) {
    a.name = nextName("bin");
    a.shape = cylinder(m_rng.uniform(0.12, 0.18), m_rng.uniform(0.3, 0.45));
    a.mat = plain(
        m_rng.pick(std::vector<Rgb>{{70, 70, 75}, {60, 90, 60}, {40, 40, 45}, {150, 150, 155}}));
  } else if (what == 1) {
    a.name = nextName("plant_pot");
    a.shape = cylinder(m_rng.uniform(0.14, 0.2), m_rng.uniform(0.28, 0.4));
    a.mat = plain({150, 80, 50});
  } else if (what == 2) {
    a.name = nextName("backpack");
    a.shape = box(m_rng.uniform(0.25, 0.35), m_rng.uniform(0.15, 0.22), m_rng.uniform(0.38, 0.48));
    a.mat = plain(randomColour(m_rng, 30, 160));
  } else if (what == 3) {
    a.name = nextName("ball");
    a.shape = sphere(m_rng.uniform(0.1, 0.13));
    a.mat = tex(randomColour(m_rng, 60, 230), "stripes", {30, 30, 30}, 0.05, 'z');
  } else if (what == 4) {
    a = cardboard(m_rng.uniform(0.3, 0.5), m_rng.uniform(0.3, 0.45), m_rng.uniform(0.25, 0.45));
    a.furniture = true;
    a.side = side;
    a.name = nextName("box");
  } else if (what == 5) {
    a.name = nextName("gas_cylinder");
    a.shape = cylinder(0.11, r3(m_rng.uniform(1.0, 1.4)));
    a.mat = plain(m_rng.pick(std::vector<Rgb>{{40, 110, 60}, {60, 60, 140}, {150, 150, 150}}));
  } else {
    a.name = nextName("lamp_pole");
    a.shape = cylinder(0.015, r3(m_rng.uniform(1.4, 1.7)));
    a.mat = plain({180, 180, 180});
  }
  const double yaw = m_rng.uniform(-30.0, 30.0);
  const double u = m_rng.uniform(0.3, s.length - 0.3);
  poseOnSide(a, side, 0.0, u, yaw, 0.0);
  double v0, v1, u0, u1;
  s.range(a.box, v0, v1, u0, u1);
  const double room = m_budget[side] - (v1 - v0) - 0.02;
  if (room < 0) return false;
  const double v = m_rng.uniform(0.02, std::min(room, 0.6)) - v0;
  poseOnSide(a, side, v, u, yaw, 0.0);
  // Lamp shade and plant above the pole / pot: their footprint (and the gas cylinder's cap) is
  // checked with the base's.
  Entry b;
  bool has_b = false;
  const V3 c = a.box.centre();
  const V2 d = V2(c.x(), c.y()) - s.origin;
  if (what == 1 || what == 6 || what == 5) {
    has_b = true;
    b.cls = "none";
    if (what == 1) {
      b.name = nextName("plant");
      const double r = r3(m_rng.uniform(0.22, 0.32));
      b.shape = sphere(r);
      b.scale = V3(1.0, 1.0, 1.4);
      b.mat = tex({50, 120, 50}, "noise", {30, 80, 30}, 0.05);
    } else if (what == 6) {
      b.name = nextName("lamp_shade");
      b.shape = cylinder(0.18, 0.25);
      b.mat = plain({240, 230, 200});
    } else {
      b.name = nextName("gas_cylinder_cap");
      b.shape = sphere(0.11);
      b.mat = a.mat;
    }
    poseOnSide(b, side, d.dot(s.n), d.dot(s.t), 0.0,
               what == 5 ? a.box.hi.z() - 0.11 : a.box.hi.z());
    // Centre the part exactly above the base (the side frame rounds differently).
    b.pos.x() = a.pos.x();
    b.pos.y() = a.pos.y();
    computeBox(b);
    a.foot = unite(a.foot, b.box.rect());
  }
  std::vector<Entry> staged;
  if (!floorOk(a, staged)) return false;
  // The part may overlap the base (the cap is half inside it), not anything else.
  if (has_b && (!insideRoom(b.box) || collides(b.box, 0.03))) return false;
  const int base = commit(a);
  if (has_b) {
    if (what == 5) {
      b.rest = Rest::Attached;
    } else {
      b.rest = Rest::Surface;
      b.surface_z = m_e[std::size_t(base)].box.hi.z();
    }
    b.support = base;
    commit(b);
  }
  return true;
}

/// what 0: wall clock, 1: whiteboard, 2: radiator.
bool Generator::wallItem(int side, int what) {
  const Side& s = m_sides[side];
  Entry e;
  e.cls = "none";
  e.rest = Rest::Wall;
  double v = 0.0, z = 0.0;
  if (what == 0) {
    e.cls = "clock";
    e.shape = model("clock");
    e.mat = plain(m_rng.pick(std::vector<Rgb>{{240, 240, 235}, {245, 245, 240}, {40, 40, 45}}));
    z = m_rng.uniform(1.75, 2.05);
  } else if (what == 1) {
    e.name = nextName("whiteboard");
    e.shape = box(0.03, m_rng.uniform(1.0, 1.8), m_rng.uniform(0.8, 1.1));
    e.mat = plain({245, 245, 245});
    z = m_rng.uniform(0.95, 1.1);
  } else {
    e.name = nextName("radiator");
    e.shape = box(0.1, m_rng.uniform(0.8, 1.4), 0.6);
    e.mat = tex({230, 230, 230}, "stripes", {200, 200, 200}, 0.04, 'y');
    e.furniture = true;
    e.side = side;
    v = 0.065;  // centre: 1.5 cm off the wall
    z = 0.15;
  }
  const double half = what == 0 ? 0.2 : e.shape.size.y() / 2 + 0.05;
  if (s.length < 2 * half) return false;
  poseOnSide(e, side, v, m_rng.uniform(half, s.length - half), 0.0, z);
  if (what == 0) {  // the clock's origin is its back, on the wall: move it back onto the face
    double v0, v1, u0, u1;
    s.range(e.box, v0, v1, u0, u1);
    const V2 back = s.at(-v0, 0.0) - s.at(0.0, 0.0);
    e.pos.x() = r3(e.pos.x() + back.x());
    e.pos.y() = r3(e.pos.y() + back.y());
    computeBox(e);
  }
  if (e.furniture ? !floorOk(e, {}) : (!insideRoom(e.box, -1e-3) || collides(e.box, 0.03)))
    return false;
  commit(e);
  return true;
}

// ---- what stands on the surfaces ----------------------------------------------------------------

Entry objectOf(const char* cls, Shape shape, Mat mat) {
  Entry e;
  e.cls = cls;
  e.shape = std::move(shape);
  e.mat = std::move(mat);
  return e;
}

Entry Generator::smallItem(bool lab) {
  const int n = lab ? 9 : 7;
  switch (m_rng.index(n)) {
    case 0:
      return objectOf("cup", model("mug"), plain(randomColour(m_rng)));
    case 1:
      return objectOf("bottle", model("bottle"), plain(randomColour(m_rng)));
    case 2: {
      Entry b = objectOf("book", box(0.17, 0.24, m_rng.uniform(0.02, 0.04)),
                         plain(randomColour(m_rng, 30, 200)));
      return b;
    }
    case 3:
      return objectOf(
          "headphones", model("headphones"),
          plain(m_rng.pick(std::vector<Rgb>{{25, 25, 25}, {200, 200, 205}, {200, 60, 60}})));
    case 4: {
      Entry p = objectOf("none", box(0.21, 0.3, m_rng.uniform(0.02, 0.07)), plain({250, 250, 250}));
      p.name = nextName("paper_stack");
      return p;
    }
    case 5:
      return objectOf("cup", model("mug"), plain(randomColour(m_rng)));
    case 6: {
      Entry t = objectOf("none", cylinder(m_rng.uniform(0.03, 0.05), m_rng.uniform(0.15, 0.3)),
                         plain(randomColour(m_rng)));
      t.name = nextName("tube");
      return t;
    }
    case 7: {
      Entry c = objectOf(
          "none", box(m_rng.uniform(0.08, 0.3), m_rng.uniform(0.08, 0.4), m_rng.uniform(0.06, 0.3)),
          plain(randomColour(m_rng)));
      c.name = nextName("instrument");
      return c;
    }
    default: {
      Entry c = objectOf("none", sphere(m_rng.uniform(0.03, 0.06)), plain(randomColour(m_rng)));
      c.name = nextName("part");
      return c;
    }
  }
}

void Generator::populateDesk(const Surface& s, int style, double u_centre, double width) {
  const double depth = s.v1 - s.v0;
  auto workstation = [&](double u) {
    Entry mon = objectOf("tv", model("monitor"), plain({28, 28, 32}));
    const bool placed = placeOn(s, mon, s.v0 + 0.17, u, m_rng.uniform(-8.0, 8.0));
    Entry kb =
        objectOf("keyboard", model("keyboard"),
                 m_rng.chance(0.7) ? tex({35, 35, 38}, "checker", {85, 85, 90}, 0.017)
                                   : tex({220, 220, 215}, "checker", {170, 170, 165}, 0.017));
    placeOn(s, kb, s.v1 - 0.16, u + m_rng.uniform(-0.05, 0.05), m_rng.uniform(-6.0, 6.0));
    if (m_rng.chance(0.6)) {
      Entry mouse = objectOf("mouse", sphere(0.03), plain({50, 50, 55}));
      mouse.scale = V3(1.0, 1.8, 0.6);
      placeOn(s, mouse, s.v1 - 0.17, u + (m_rng.chance(0.5) ? 0.32 : -0.32), -90.0);
    }
    return placed;
  };
  if (style == 0) {
    const double du = m_rng.uniform(-0.2, 0.2) * (width - 0.6) / 0.8;
    if (m_rng.chance(0.65)) {
      workstation(u_centre + du);
    } else if (m_rng.chance(0.6)) {
      Entry lap = objectOf(
          "laptop", model("laptop"),
          plain(m_rng.pick(std::vector<Rgb>{{170, 170, 175}, {160, 160, 165}, {60, 60, 65}})));
      placeOn(s, lap, s.v0 + depth * 0.5, u_centre + du, m_rng.uniform(-15.0, 15.0));
    }
    const int n = 1 + m_rng.index(3);
    for (int k = 0; k < n; ++k) placeOnRandom(s, smallItem(false));
  } else if (style == 1) {
    if (m_rng.chance(0.6)) {
      Entry phone = objectOf("conference_phone", model("conference_phone"), plain({45, 45, 50}));
      placeOn(s, phone, s.v0 + depth * 0.5 + m_rng.uniform(-0.05, 0.05),
              u_centre + m_rng.uniform(-0.1, 0.1), m_rng.uniform(-180.0, 180.0));
    }
    if (m_rng.chance(0.3)) {
      Entry lap = objectOf("laptop", model("laptop"), plain({170, 170, 175}));
      placeOnRandom(s, lap);
    }
    const int n = 1 + m_rng.index(4);
    for (int k = 0; k < n; ++k) placeOnRandom(s, smallItem(false));
  } else {
    const int stations = m_rng.index(3);
    for (int k = 0; k < stations; ++k)
      workstation(s.u0 + width * (k + 0.5) / stations + m_rng.uniform(-0.1, 0.1));
    if (m_rng.chance(0.3)) {
      Entry phone = objectOf("conference_phone", model("conference_phone"), plain({50, 50, 55}));
      placeOnRandom(s, phone);
    }
    if (m_rng.chance(0.3)) {
      Entry lap = objectOf("laptop", model("laptop"), plain({160, 160, 165}));
      placeOnRandom(s, lap);
    }
    const int n = 5 + m_rng.index(8);
    for (int k = 0; k < n; ++k) placeOnRandom(s, smallItem(true));
  }
}

void Generator::populateShelf(const Surface& s, bool lab, bool top) {
  if (top) {  // something on top of the bookcase
    Entry b = m_rng.chance(0.5) ? cardboard(m_rng.uniform(0.25, 0.33), m_rng.uniform(0.2, 0.5),
                                            m_rng.uniform(0.15, 0.35))
                                : smallItem(lab);
    placeOnRandom(s, b);
    return;
  }
  if (lab || m_rng.chance(0.2)) {  // boxes and containers
    const int n = 2 + m_rng.index(3);
    for (int k = 0; k < n; ++k) {
      Entry b =
          cardboard(m_rng.uniform(0.2, 0.3), m_rng.uniform(0.12, 0.29), m_rng.uniform(0.15, 0.36));
      b.mat = plain(randomColour(m_rng));
      if (m_rng.chance(0.3)) b.cls = "none";
      for (int t = 0; t < 30; ++t)
        if (placeOn(s, b, s.v0 + 0.02 + b.shape.size.x() / 2, m_rng.uniform(s.u0, s.u1), 0.0))
          break;
    }
    return;
  }
  // A row of books standing with their spines to the front.
  double u = s.u0 + 0.02 + m_rng.uniform(0.0, 0.25);
  const int n = 3 + m_rng.index(7);
  for (int k = 0; k < n; ++k) {
    const double d = m_rng.uniform(0.2, 0.24), w = m_rng.uniform(0.025, 0.06),
                 h = m_rng.uniform(0.22, 0.3);
    Entry b = objectOf("book", box(d, w, h), plain(randomColour(m_rng, 30, 210)));
    if (!placeOn(s, b, s.v0 + 0.02 + d / 2, u + w / 2, 0.0)) break;
    u += w + m_rng.uniform(0.009, 0.015);
  }
  if (m_rng.chance(0.25)) {  // a small clock standing on its rim
    Entry c = objectOf("clock", cylinder(m_rng.uniform(0.06, 0.08), 0.04), plain({220, 220, 210}));
    c.pitch = 90.0;
    for (int t = 0; t < 10; ++t)
      if (placeOn(s, c, s.v0 + 0.12, m_rng.uniform(s.u0, s.u1), 0.0)) break;
  }
}

void Generator::populateCabinet(const Surface& s) {
  if (m_rng.chance(0.3)) {  // a potted plant
    Entry pot = objectOf("none", cylinder(m_rng.uniform(0.08, 0.12), m_rng.uniform(0.12, 0.2)),
                         plain({150, 80, 50}));
    pot.name = nextName("plant_pot");
    if (placeOnRandom(s, pot)) {
      const int pi = int(m_e.size()) - 1;
      Entry p = objectOf("none", sphere(r3(m_rng.uniform(0.1, 0.16))),
                         tex({50, 120, 50}, "noise", {30, 80, 30}, 0.05));
      p.name = nextName("plant");
      p.scale = V3(1.0, 1.0, 1.3);
      const Entry& base = m_e[std::size_t(pi)];
      poseOnSide(p, s.side, 0.0, 0.0, 0.0, base.box.hi.z());
      p.pos.x() = base.pos.x();
      p.pos.y() = base.pos.y();
      computeBox(p);
      if (insideRoom(p.box) && !collides(p.box, 0.01, pi, s.entry) && p.box.hi.z() < s.z + 0.7) {
        p.rest = Rest::Surface;
        p.support = pi;
        p.surface_z = base.box.hi.z();
        commit(p);
      }
    }
  }
  if (m_rng.chance(0.15)) placeOnRandom(s, objectOf("tv", model("monitor"), plain({28, 28, 32})));
  const int n = 1 + m_rng.index(4);
  for (int k = 0; k < n; ++k) {
    Entry e = m_rng.chance(0.3) ? cardboard(m_rng.uniform(0.15, 0.35), m_rng.uniform(0.15, 0.4),
                                            m_rng.uniform(0.1, 0.3))
                                : smallItem(m_labish);
    placeOnRandom(s, e);
  }
}

// ---- rooms --------------------------------------------------------------------------------------

void Generator::setSides(const GenRect& r) {
  m_room = r;
  const double w = r.x1 - r.x0, d = r.y1 - r.y0;
  m_sides[0] = {V2(r.x1, r.y0), V2(0, 1), V2(-1, 0), w, 90.0};    // south wall, y = y0
  m_sides[1] = {V2(r.x1, r.y1), V2(-1, 0), V2(0, -1), d, 180.0};  // east, x = x1
  m_sides[2] = {V2(r.x0, r.y1), V2(0, -1), V2(1, 0), w, -90.0};   // north, y = y1
  m_sides[3] = {V2(r.x0, r.y0), V2(1, 0), V2(0, 1), d, 0.0};      // west, x = x0
}

/// Band budgets: how far furniture may reach into the room from each wall, so that a free area
/// of at least max(1 m, 20 % of the side) stays, m_c away from everything; the chairs' colour;
/// plain sides and the counter's side.
RoomPlan Generator::planRoom(const GenRect& r, RoomKind kind) {
  RoomPlan p;
  p.rect = r;
  p.kind = kind;
  setSides(r);
  for (int axis = 0; axis < 2; ++axis) {
    const double len = axis == 0 ? r.x1 - r.x0 : r.y1 - r.y0;  // west/east bands eat into x
    const double free_min = std::clamp(0.2 * len, 1.0, 2.5);
    const double avail = std::max(0.0, len - 2 * m_c - free_min);
    const double f = m_rng.uniform(0.4, 0.6);
    const int a = axis == 0 ? 3 : 0, b = axis == 0 ? 1 : 2;
    p.budget[a] = std::min(1.6, avail * f);
    p.budget[b] = std::min(1.6, avail * (1 - f));
  }
  p.chair = m_rng.pick(chairColours());
  const int plain_sides = m_p.plain_walls >= 0          ? m_p.plain_walls
                          : kind == RoomKind::BreakRoom ? 1 + m_rng.index(2)
                                                        : 0;
  if (plain_sides > 0 || kind == RoomKind::BreakRoom) planPlainSides(p, plain_sides);
  return p;
}

/// Marks `n` long sides plain and, in a break room, picks the counter's side (a long side that is
/// not plain, else a short one) and widens its band to hold the counter.
void Generator::planPlainSides(RoomPlan& p, int n) {
  const bool along_x = p.rect.width() >= p.rect.depth();
  const int lng[2] = {along_x ? 0 : 1, along_x ? 2 : 3};
  const int shrt[2] = {along_x ? 1 : 0, along_x ? 3 : 2};
  const int first = m_rng.index(2);
  for (int k = 0; k < n; ++k) p.plain[lng[(first + k) % 2]] = true;
  if (p.kind != RoomKind::BreakRoom) return;
  const int side = n == 0 ? lng[first] : n == 1 ? lng[1 - first] : shrt[m_rng.index(2)];
  const int opposite = (side + 2) % 4;
  const double total = p.budget[side] + p.budget[opposite];
  p.counter_side = side;
  p.budget[side] = std::max(p.budget[side], 0.65);
  p.budget[opposite] =
      p.plain[opposite] ? 0.0 : std::max(0.0, std::min(p.budget[opposite], total - 0.65));
}

void Generator::enterRoom(const RoomPlan& p) {
  setSides(p.rect);
  for (int s = 0; s < 4; ++s) m_budget[s] = p.budget[s];
  m_chair = p.chair;
  m_kind = p.kind;
  m_officeish = p.kind != RoomKind::Lab;
  m_labish = p.kind != RoomKind::Office && p.kind != RoomKind::BreakRoom;
}

void Generator::addStructure(const std::string& name, const char* cls, Shape sh, V3 pos,
                             const Mat& mat) {
  Entry e;
  e.is_static = true;
  e.name = name;
  e.cls = cls;
  e.shape = std::move(sh);
  e.pos = V3(r3(pos.x()), r3(pos.y()), r3(pos.z()));
  e.mat = mat;
  e.rest = Rest::Structure;
  computeBox(e);
  commit(e);
}

/// One room: floor and ceiling slabs, walls outside the interior, as in the shipped worlds; a
/// plain side's wall keeps its noise texture or turns a uniform colour.
void Generator::roomStructure(const RoomPlan& p) {
  const Mat floor_mat = m_rng.pick(floorMats());
  const Mat wall_a = m_rng.pick(wallMats());
  const Mat wall_b = m_rng.chance(0.5) ? wall_a : m_rng.pick(wallMats());
  const Mat ceiling = plain(m_rng.chance(0.5) ? Rgb{235, 235, 230} : Rgb{230, 230, 230});
  Mat wall[4] = {wall_a, wall_b, wall_a, wall_b};
  for (int s = 0; s < 4; ++s)
    if (p.plain[s] && m_rng.chance(0.5)) wall[s] = plain(wall[s].c);
  const double H = m_h;
  addStructure("floor", "floor", box(m_w + 0.2, m_d + 0.2, 0.1), V3(m_w / 2, m_d / 2, -0.05),
               floor_mat);
  addStructure("ceiling", "ceiling", box(m_w + 0.2, m_d + 0.2, 0.1), V3(m_w / 2, m_d / 2, H + 0.05),
               ceiling);
  addStructure("wall_south", "wall", box(m_w + 0.2, 0.1, H), V3(m_w / 2, -0.05, H / 2), wall[0]);
  addStructure("wall_north", "wall", box(m_w + 0.2, 0.1, H), V3(m_w / 2, m_d + 0.05, H / 2),
               wall[2]);
  addStructure("wall_west", "wall", box(0.1, m_d, H), V3(-0.05, m_d / 2, H / 2), wall[3]);
  addStructure("wall_east", "wall", box(0.1, m_d, H), V3(m_w + 0.05, m_d / 2, H / 2), wall[1]);
}

/// The room's furniture: the counter first (break rooms), then units on random sides that are
/// neither plain nor the counter's (rejection sampling), wall items, clutter along the walls.
/// Nothing comes within kPlainKeep_m of a plain side (not even from a neighbouring wall's band).
void Generator::furnish(RoomPlan& p) {
  for (int s = 0; s < 4; ++s) {
    if (!p.plain[s]) continue;
    Box3 k;
    for (double v : {0.0, kPlainKeep_m})
      for (double u : {0.0, m_sides[s].length}) {
        const V2 q = m_sides[s].at(v, u);
        k.extend(V3(q.x(), q.y(), 0.0));
        k.extend(V3(q.x(), q.y(), m_h));
      }
    m_keepout.push_back(k);
  }
  if (p.counter_side >= 0 && !counterUnit(p.counter_side, p.counter)) p.counter_side = -1;
  std::vector<int> sides;
  for (int s = 0; s < 4; ++s)
    if (!p.plain[s] && s != p.counter_side) sides.push_back(s);
  if (sides.empty()) return;
  auto randomSide = [&] { return sides[std::size_t(m_rng.index(int(sides.size())))]; };
  double perimeter = 2 * (m_room.width() + m_room.depth());
  if (sides.size() < 4) {
    perimeter = 0.0;
    for (int s : sides) perimeter += m_sides[s].length;
  }
  const int target = std::max(3, int(perimeter / 2.1));
  // Weights of desk, table, bench, shelf, cabinet.
  std::vector<double> weights;
  if (m_kind == RoomKind::Office)
    weights = {0.45, 0.12, 0.0, 0.3, 0.13};
  else if (m_kind == RoomKind::Lab)
    weights = {0.05, 0.0, 0.5, 0.33, 0.12};
  else if (m_kind == RoomKind::BreakRoom)
    weights = {0.1, 0.45, 0.0, 0.15, 0.3};
  else
    weights = {0.3, 0.08, 0.22, 0.28, 0.12};
  // A rejected attempt leaves no trace (its names are not used up).
  auto attempt = [this](auto&& unit) {
    const std::map<std::string, int> names = m_count;
    const bool ok = unit();
    if (!ok) m_count = names;
    return ok;
  };
  int placed = 0;
  for (int k = 0; k < 60 * target && placed < target; ++k) {
    const int side = randomSide();
    const int unit = m_rng.weighted(weights);
    const bool lab_shelf = m_kind == RoomKind::Lab || (m_labish && m_rng.chance(0.4));
    placed += attempt([&] {
      return unit <= 2   ? deskUnit(side, unit)
             : unit == 3 ? shelfUnit(side, lab_shelf)
                         : cabinetUnit(side);
    })
                  ? 1
                  : 0;
  }
  // Wall items, then clutter on the floor along the walls (30 tries each).
  auto tries = [&](auto&& unit) {
    for (int t = 0; t < 30; ++t)
      if (attempt([&] { return unit(randomSide()); })) return;
  };
  if (m_rng.chance(m_officeish ? 0.85 : 0.6)) tries([this](int s) { return wallItem(s, 0); });
  if (m_rng.chance(m_officeish ? 0.6 : 0.3)) tries([this](int s) { return wallItem(s, 1); });
  const int radiators = m_rng.index(3);
  for (int k = 0; k < radiators; ++k) tries([this](int s) { return wallItem(s, 2); });
  const int stacks = 1 + m_rng.index(3);
  for (int k = 0; k < stacks; ++k) tries([this](int s) { return boxStack(s); });
  const int clutter = 2 + m_rng.index(5);
  for (int k = 0; k < clutter; ++k) tries([this](int s) { return floorClutter(s); });
}

/// Free area of the current room from its entries (from `first` on): whatever reaches into the
/// robot's height band (up to 0.6 m) belongs to the band of the wall it (or what it rests on) was
/// placed against, which it reaches at most ext[side] into the room (within the band's budget,
/// but for a few cm of a box stacked on another).
GenRect Generator::freeAreaOf(std::size_t first) const {
  double ext[4] = {0, 0, 0, 0};
  for (std::size_t i = first; i < m_e.size(); ++i) {
    const Entry& e = m_e[i];
    if (e.rest == Rest::Structure || e.box.lo.z() > 0.65) continue;
    int side = e.side;
    for (int s = e.support; side < 0 && s >= 0; s = m_e[std::size_t(s)].support)
      side = m_e[std::size_t(s)].side;
    if (side < 0)
      for (int s = 0; s < 4; ++s)
        if (side < 0 || inward(e.box, s) < inward(e.box, side)) side = s;
    ext[side] = std::max(ext[side], inward(e.box, side));
  }
  return {r3(m_room.x0 + ext[3] + m_c), r3(m_room.y0 + ext[0] + m_c), r3(m_room.x1 - ext[1] - m_c),
          r3(m_room.y1 - ext[2] - m_c)};
}

GeneratedWorld::Room Generator::roomOf(const RoomPlan& p, int index) const {
  GeneratedWorld::Room r;
  r.name = "room_" + std::to_string(index);
  r.kind = p.kind;
  r.interior = p.rect;
  r.free_area = p.free_area;
  for (int s = 0; s < 4; ++s)
    if (p.plain[s]) r.plain_sides.push_back(s);
  r.counter_side = p.counter_side;
  if (p.counter_side >= 0) r.counter = p.counter;
  if (p.hall_side >= 0) {
    const double half = m_p.doorway_width_m / 2;
    const double y = p.hall_side == 0 ? p.rect.y0 - kWall_m : p.rect.y1;
    r.doorway = {p.door_x - half, y, p.door_x + half, y + kWall_m};
  }
  return r;
}

void Generator::runRoom(GeneratedWorld& g) {
  RoomPlan p = planRoom({0.0, 0.0, m_w, m_d}, m_p.kind);
  enterRoom(p);
  roomStructure(p);
  std::vector<int> door_sides;
  for (int s = 0; s < 4; ++s)
    if (!p.plain[s] && s != p.counter_side) door_sides.push_back(s);
  door(door_sides[std::size_t(m_rng.index(int(door_sides.size())))]);
  p.first = 0;
  furnish(p);
  p.free_area = freeAreaOf(0);
  g.free_area = p.free_area;
  g.rooms.push_back(roomOf(p, 1));
  g.robot_free = {g.free_area};

  std::string plain_note;
  if (m_p.plain_walls >= 0) plain_note = " --plain-walls " + std::to_string(m_p.plain_walls);
  std::ostringstream out;
  out << "# rasm simulator world generated by `rasm sim generate <out.yaml> --seed " << m_p.seed
      << " --size " << num(m_w, 2) << "x" << num(m_d, 2) << " --kind " << roomKindName(m_p.kind)
      << plain_note
      << "`\n# (modules/sim/src/WorldGenerator.cpp; schema: docs/sim.md). Regenerate rather than "
         "edit.\n# Room interior x 0.."
      << num(m_w) << ", y 0.." << num(m_d) << " m, " << num(m_h)
      << " m high; the robot's free area (centres) is x " << num(g.free_area.x0) << ".."
      << num(g.free_area.x1) << ", y " << num(g.free_area.y0) << ".." << num(g.free_area.y1)
      << ".\n";
  const char* side_names[4] = {"south", "east", "north", "west"};
  if (p.counter_side >= 0 || !g.rooms[0].plain_sides.empty()) {
    out << "# Plain sides:";
    for (int s : g.rooms[0].plain_sides) out << " " << side_names[s];
    if (g.rooms[0].plain_sides.empty()) out << " none";
    if (p.counter_side >= 0)
      out << "; a counter along the " << side_names[p.counter_side] << " wall";
    out << ".\n";
  }
  m_header = out.str();
  m_description = "random " + std::string(roomKindName(m_p.kind)) + " room " + num(m_w) + " x " +
                  num(m_d) + " m, seed " + std::to_string(m_p.seed);
}

// ---- flats --------------------------------------------------------------------------------------

/// Flat: the doorway's centre on the room's hallway side, where the robot's path from it straight
/// into the room's free area crosses no band of the room's side walls.
void Generator::planDoorway(RoomPlan& p) {
  const double half = m_p.doorway_width_m / 2;
  const double lo = std::max(p.rect.x0 + p.budget[3] + m_c + 0.1, p.rect.x0 + half + 0.15);
  const double hi = std::min(p.rect.x1 - p.budget[1] - m_c - 0.1, p.rect.x1 - half - 0.15);
  p.door_x = r3(lo <= hi ? m_rng.uniform(lo, hi) : 0.5 * (p.rect.x0 + p.rect.x1));
}

/// What holds that path free, floor to ceiling: the doorway's width plus 0.15 m either side,
/// through the band of its wall and the clearance to the free area.
Box3 Generator::doorwayKeepout(const RoomPlan& p) const {
  const double half = m_p.doorway_width_m / 2 + 0.15;
  const double depth = p.budget[p.hall_side] + m_c + 0.1;
  const double y0 = p.hall_side == 0 ? p.rect.y0 : p.rect.y1 - depth;
  Box3 k;
  k.extend(V3(p.door_x - half, y0, 0.0));
  k.extend(V3(p.door_x + half, y0 + depth, m_h));
  return k;
}

/// Rooms north of the hallway (y hy1 + wall .. D), and south of it (0 .. hy0 - wall) in a flat of
/// 4-5; each row split along x at random (every room at least about kMinFlatRoom_m wide).
std::vector<RoomPlan> Generator::planFlatRooms(double hy0, double hy1) {
  const int n = m_p.rooms, rows = flatRows(n);
  const std::vector<RoomKind> kinds = {RoomKind::Office, RoomKind::Lab, RoomKind::Mixed,
                                       RoomKind::BreakRoom};
  std::vector<RoomPlan> plans;
  for (int row = 0; row < rows; ++row) {
    const int k = row == 0 ? flatRowRooms(n) : n - flatRowRooms(n);
    const double ya = row == 0 ? hy1 + kWall_m : 0.0, yb = row == 0 ? m_d : hy0 - kWall_m;
    const double jitter =
        std::clamp(m_w / k - kWall_m - TWorldGenParams::kMinFlatRoom_m - 0.1, 0.0, 0.6);
    double xa = 0.0;
    for (int i = 0; i < k; ++i) {
      const double xb =
          i + 1 == k ? m_w
                     : r3((i + 1) * m_w / k + m_rng.uniform(-0.5, 0.5) * jitter) - kWall_m / 2;
      const RoomKind kind = m_p.kind == RoomKind::Mixed
                                ? kinds[std::size_t(m_rng.weighted({0.3, 0.2, 0.2, 0.3}))]
                                : m_p.kind;
      RoomPlan p = planRoom({xa, ya, xb, yb}, kind);
      p.hall_side = row == 0 ? 0 : 2;
      planDoorway(p);
      plans.push_back(p);
      xa = xb + kWall_m;
    }
  }
  return plans;
}

/// The flat's floor, ceiling and outer walls as a room's; the hallway's walls in segments between
/// the doorways, a lintel above each doorway (2.05 m up); partitions between neighbouring rooms.
void Generator::flatStructure(const std::vector<RoomPlan>& plans, double hy0, double hy1) {
  const Mat floor_mat = m_rng.pick(floorMats());
  const Mat outer = m_rng.pick(wallMats());
  const Mat inner = m_rng.chance(0.5) ? outer : m_rng.pick(wallMats());
  const Mat ceiling = plain(m_rng.chance(0.5) ? Rgb{235, 235, 230} : Rgb{230, 230, 230});
  const double H = m_h, t = kWall_m, half = m_p.doorway_width_m / 2, lintel = H - 2.05;
  addStructure("floor", "floor", box(m_w + 0.2, m_d + 0.2, 0.1), V3(m_w / 2, m_d / 2, -0.05),
               floor_mat);
  addStructure("ceiling", "ceiling", box(m_w + 0.2, m_d + 0.2, 0.1), V3(m_w / 2, m_d / 2, H + 0.05),
               ceiling);
  addStructure("wall_south", "wall", box(m_w + 0.2, t, H), V3(m_w / 2, -t / 2, H / 2), outer);
  addStructure("wall_north", "wall", box(m_w + 0.2, t, H), V3(m_w / 2, m_d + t / 2, H / 2), outer);
  addStructure("wall_west", "wall", box(t, m_d, H), V3(-t / 2, m_d / 2, H / 2), outer);
  addStructure("wall_east", "wall", box(t, m_d, H), V3(m_w + t / 2, m_d / 2, H / 2), outer);
  int segments = 0, lintels = 0, partitions = 0;
  for (int hall_side : {0, 2}) {
    const double wy = hall_side == 0 ? hy1 + t / 2 : hy0 - t / 2;
    double x = 0.0;
    const RoomPlan* prev = nullptr;
    for (const RoomPlan& p : plans) {
      if (p.hall_side != hall_side) continue;
      addStructure("wall_hallway_" + std::to_string(++segments), "wall",
                   box(p.door_x - half - x, t, H), V3((x + p.door_x - half) / 2, wy, H / 2), inner);
      addStructure("lintel_" + std::to_string(++lintels), "wall", box(2 * half, t, lintel),
                   V3(p.door_x, wy, H - lintel / 2), inner);
      x = p.door_x + half;
      if (prev) {
        const double b = 0.5 * (prev->rect.x1 + p.rect.x0);
        addStructure("wall_partition_" + std::to_string(++partitions), "wall",
                     box(t, p.rect.depth(), H), V3(b, 0.5 * (p.rect.y0 + p.rect.y1), H / 2), inner);
      }
      prev = &p;
    }
    if (prev)
      addStructure("wall_hallway_" + std::to_string(++segments), "wall", box(m_w - x, t, H),
                   V3((x + m_w) / 2, wy, H / 2), inner);
  }
}

void Generator::runFlat(GeneratedWorld& g) {
  const int rows = flatRows(m_p.rooms);
  const double h = r1(m_rng.uniform(1.4, kMaxHallway_m));
  const double hy0 = rows == 2 ? r1((m_d - h - 2 * kWall_m) / 2) + kWall_m : 0.0, hy1 = hy0 + h;
  const GenRect hall{0.0, hy0, m_w, hy1};
  std::vector<RoomPlan> plans = planFlatRooms(hy0, hy1);
  flatStructure(plans, hy0, hy1);
  setSides(hall);  // the flat's door, at an end of the hallway
  m_budget[1] = m_budget[3] = 0.0;
  door(m_rng.chance(0.5) ? 1 : 3);
  for (RoomPlan& p : plans) {
    enterRoom(p);
    m_keepout.push_back(doorwayKeepout(p));
    p.first = m_e.size();
    furnish(p);
    p.free_area = freeAreaOf(p.first);
  }
  g.hallway = hall;
  g.free_area = {r3(hall.x0 + m_c), r3(hy0 + m_c), r3(hall.x1 - m_c), r3(hy1 - m_c)};
  g.robot_free = {g.free_area};
  for (std::size_t i = 0; i < plans.size(); ++i) {
    const RoomPlan& p = plans[i];
    g.rooms.push_back(roomOf(p, int(i) + 1));
    g.robot_free.push_back(p.free_area);
    const double ya = p.hall_side == 0 ? g.free_area.y1 : p.free_area.y1;
    const double yb = p.hall_side == 0 ? p.free_area.y0 : g.free_area.y0;
    g.robot_free.push_back({p.door_x, ya, p.door_x, yb});
  }

  std::ostringstream out;
  out << "# rasm simulator world generated by `rasm sim generate <out.yaml> --seed " << m_p.seed
      << " --layout flat --rooms " << m_p.rooms << " --size " << num(m_w, 2) << "x" << num(m_d, 2)
      << " --kind " << roomKindName(m_p.kind)
      << (m_p.plain_walls >= 0 ? " --plain-walls " + std::to_string(m_p.plain_walls) : "")
      << "`\n# (modules/sim/src/WorldGenerator.cpp; schema: docs/sim.md). Regenerate rather than "
         "edit.\n# Flat interior x 0.."
      << num(m_w) << ", y 0.." << num(m_d) << " m, " << num(m_h) << " m high; hallway y "
      << num(hy0) << ".." << num(hy1) << ", the robot's free area in it (centres) x "
      << num(g.free_area.x0) << ".." << num(g.free_area.x1) << ", y " << num(g.free_area.y0) << ".."
      << num(g.free_area.y1) << ".\n";
  for (const GeneratedWorld::Room& r : g.rooms)
    out << "# " << r.name << " (" << roomKindName(r.kind) << "): x " << num(r.interior.x0) << ".."
        << num(r.interior.x1) << ", y " << num(r.interior.y0) << ".." << num(r.interior.y1)
        << ", doorway x " << num(r.doorway.x0) << ".." << num(r.doorway.x1) << ", "
        << r.plain_sides.size() << " plain side(s)" << (r.counter_side >= 0 ? ", a counter" : "")
        << ".\n";
  m_header = out.str();
  m_description = "random flat of " + std::to_string(m_p.rooms) + " rooms " + num(m_w) + " x " +
                  num(m_d) + " m, seed " + std::to_string(m_p.seed);
}

// ---- the world ----------------------------------------------------------------------------------

void Generator::drawSize() {
  if (m_p.width_m > 0.0) return;
  if (m_p.layout == WorldLayout::Room) {  // a stream of its own, so --size W x D reproduces it
    Rng size_rng(m_p.seed ^ 0x243F6A8885A308D3ull);
    m_p.width_m = r1(size_rng.uniform(5.5, 9.0));
    m_p.depth_m = r1(size_rng.uniform(4.5, 7.0));
    return;
  }
  Rng size_rng(m_p.seed ^ 0xBE5466CF34E90C6Cull);
  const int k = flatRowRooms(m_p.rooms);
  m_p.width_m = r1(size_rng.uniform(std::max(8.0, 3.6 * k), 14.0));
  m_p.depth_m =
      flatRows(m_p.rooms) == 2 ? r1(size_rng.uniform(9.0, 11.0)) : r1(size_rng.uniform(6.0, 10.0));
}

GeneratedWorld Generator::run() {
  m_p.validate();
  GeneratedWorld g;
  drawSize();
  g.params = m_p;
  m_w = m_p.width_m;
  m_d = m_p.depth_m;
  m_h = m_p.height_m;
  m_c = m_p.robot_radius_m + m_p.clearance_m;
  char name[128];
  if (m_p.layout == WorldLayout::Flat)
    std::snprintf(name, sizeof(name), "gen_flat%d_%s_%sx%s_s%llu", m_p.rooms,
                  roomKindName(m_p.kind), num(m_w, 2).c_str(), num(m_d, 2).c_str(),
                  (unsigned long long)m_p.seed);
  else
    std::snprintf(name, sizeof(name), "gen_%s_%sx%s_s%llu", roomKindName(m_p.kind),
                  num(m_w, 2).c_str(), num(m_d, 2).c_str(), (unsigned long long)m_p.seed);
  g.name = name;
  if (m_p.layout == WorldLayout::Flat)
    runFlat(g);
  else
    runRoom(g);
  writeYaml(g);
  return g;
}

/// Bookkeeping for the trajectories and tests (ids as written: static first), then the text.
void Generator::writeYaml(GeneratedWorld& g) {
  std::vector<int> order, ids(m_e.size(), 0);
  for (int pass = 0; pass < 2; ++pass)
    for (int i = 0; i < int(m_e.size()); ++i)
      if (m_e[std::size_t(i)].is_static == (pass == 0)) order.push_back(i);
  int next_static = 1, next_object = 0;
  for (int i : order) {
    const Entry& e = m_e[std::size_t(i)];
    if (e.is_static) {
      ids[std::size_t(i)] = next_static++;
      if (next_static == 8) next_static = 10;  // structure 1..7, furniture from 10 (as office)
    } else {
      if (next_object == 0) next_object = std::max(100, next_static);
      ids[std::size_t(i)] = next_object++;
    }
  }
  for (int i : order) {
    const Entry& e = m_e[std::size_t(i)];
    GeneratedWorld::Placement p;
    p.id = std::uint16_t(ids[std::size_t(i)]);
    p.name = e.name;
    p.class_name = e.cls;
    p.rest = e.rest;
    p.support_id = e.support >= 0 ? std::uint16_t(ids[std::size_t(e.support)]) : 0;
    p.surface_z_m = e.surface_z;
    p.furniture = e.furniture;
    p.footprint = e.furniture ? e.foot : e.box.rect();
    p.z0_m = e.box.lo.z();
    p.z1_m = e.box.hi.z();
    g.placements.push_back(p);
    if (e.rest != Rest::Structure && e.rest != Rest::Attached && e.name.rfind("door", 0) != 0)
      g.view_targets.push_back(e.box.centre());
  }

  std::ostringstream out;
  out << m_header;
  out << "world: " << g.name << "\n";
  out << "description: " << m_description << "\n";
  const double lx = r3(m_rng.uniform(-0.4, 0.4)), ly = r3(m_rng.uniform(-0.4, 0.4));
  const double amb = r3(m_rng.uniform(0.33, 0.42));
  out << "light: {direction: [" << num(lx) << ", " << num(ly) << ", -1], ambient: " << num(amb)
      << ", diffuse: " << num(1.0 - amb) << "}\n";
  out << "background: [0, 0, 0]\n";
  for (int pass = 0; pass < 2; ++pass) {
    out << "\n" << (pass == 0 ? "static:" : "objects:") << "\n";
    for (int i : order)
      if (m_e[std::size_t(i)].is_static == (pass == 0))
        out << entryYaml(m_e[std::size_t(i)], ids[std::size_t(i)]) << "\n";
  }
  g.yaml = out.str();
}

std::string matYaml(const Mat& m) {
  auto rgb = [](const Rgb& c) {
    return "[" + std::to_string(c.r) + ", " + std::to_string(c.g) + ", " + std::to_string(c.b) +
           "]";
  };
  std::string s = "colour: " + rgb(m.c);
  if (!m.pattern.empty()) {
    s += ", texture: {pattern: " + m.pattern + ", colour2: " + rgb(m.c2) +
         ", period_m: " + num(m.period_m);
    if (m.axis) s += std::string(", axis: ") + m.axis;
    s += "}";
  }
  return s;
}

std::string Generator::entryYaml(const Entry& e, int id) const {
  std::string s = "  - {id: " + std::to_string(id);
  if (!e.name.empty()) s += ", name: " + e.name;
  s += ", class: " + e.cls;
  switch (e.shape.kind) {
    case Shape::Model:
      s += ", mesh: " + e.shape.model + ".obj";
      break;
    case Shape::Box:
      s += ", primitive: box, size: [" + num(e.shape.size.x()) + ", " + num(e.shape.size.y()) +
           ", " + num(e.shape.size.z()) + "]";
      break;
    case Shape::Cylinder:
      s += ", primitive: cylinder, radius: " + num(e.shape.radius) +
           ", height: " + num(e.shape.height);
      break;
    case Shape::Sphere:
      s += ", primitive: sphere, radius: " + num(e.shape.radius);
      break;
  }
  if (e.scale != V3::Ones())
    s += ", scale: [" + num(e.scale.x()) + ", " + num(e.scale.y()) + ", " + num(e.scale.z()) + "]";
  s += ", position: [" + num(e.pos.x()) + ", " + num(e.pos.y()) + ", " + num(e.pos.z()) + "]";
  if (e.pitch != 0.0 || e.roll != 0.0)
    s += ", ypr_deg: [" + num(e.yaw, 1) + ", " + num(e.pitch, 1) + ", " + num(e.roll, 1) + "]";
  else if (e.yaw != 0.0)
    s += ", yaw_deg: " + num(e.yaw, 1);
  s += ", " + matYaml(e.mat) + "}";
  return s;
}

}  // namespace

GeneratedWorld generateWorld(const TWorldGenParams& params) {
  return Generator(params).run();
}

}  // namespace rasm::sim
