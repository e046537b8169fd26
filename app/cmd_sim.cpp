// `rasm sim ...`: the simulator's command line (thin layer over rasm::sim): record rawlogs from
// worlds, render previews, describe worlds, write the procedural models, generate rooms and check
// maps against the ground-truth surface. Each subcommand declares its arguments below.
#include <nlohmann/json.hpp>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <iostream>
#include <map>
#include <sstream>
#include <stdexcept>

#include "Command.h"
#include "rasm/core/AtomicFile.h"
#include "rasm/core/Error.h"
#include "rasm/core/Printable.h"
#include "rasm/core/Validate.h"
#include "rasm/models/ClassVocabulary.h"
#include "rasm/models/ProceduralModels.h"
#include "rasm/sim/CameraPoses.h"
#include "rasm/sim/FrameImages.h"
#include "rasm/sim/RayScene.h"
#include "rasm/sim/Recorder.h"
#include "rasm/sim/RgbdSensor.h"
#include "rasm/sim/SurfaceDistance.h"
#include "rasm/sim/TrajectoryGenerator.h"
#include "rasm/sim/World.h"
#include "rasm/sim/WorldGenerator.h"
#ifdef RASM_HAVE_MODULE_SURFEL_MAP
#include "rasm/surfel_map/MapExport.h"
#endif

namespace {

using rasm::app::CommandDecl;
using rasm::app::OptionDecl;
using rasm::app::ParsedArgs;

const char* kWorldNote =
    "<world> is a shipped world name (office, cluttered_lab, two_rooms) or a YAML file "
    "(docs/sim.md).\n";
const rasm::app::PositionalDecl kWorld{"world", "a shipped world name or a world YAML file"};
const OptionDecl kSeed{"seed", "N", "the noise seed (default 0)"};
const OptionDecl kNoise{"noise", "on|off", "sensor noise and dropouts (default on)"};
const OptionDecl kCamera{"camera", "preset", "the camera preset ([sim_sensor] camera)"};

std::uint64_t parseSeed(const ParsedArgs& p) {
  if (!p.has("seed")) return 0;
  const std::string v = p.value("seed");
  try {
    std::size_t n = 0;
    const unsigned long long seed = std::stoull(v, &n);
    if (n == v.size()) return seed;
  } catch (const std::exception&) {
  }
  rasm::throwInputError("--seed " + v, "expected a non-negative integer");
}

bool parseOnOff(const ParsedArgs& p, const std::string& key, bool def) {
  if (!p.has(key)) return def;
  const std::string v = p.value(key);
  if (v == "on") return true;
  if (v == "off") return false;
  rasm::throwInputError("--" + key + " " + v, "expected on or off");
}

Eigen::Vector3d parseVec3(const ParsedArgs& p, const std::string& key) {
  const std::string s = p.value(key);
  Eigen::Vector3d v;
  char c1 = 0, c2 = 0;
  std::istringstream in(s);
  if (!(in >> v.x() >> c1 >> v.y() >> c2 >> v.z()) || c1 != ',' || c2 != ',' || !in.eof())
    rasm::throwInputError("--" + key + " " + s, "expected x,y,z (three finite numbers)");
  for (int i = 0; i < 3; ++i) rasm::requireCoordinate(v[i], "--" + key + " " + s);
  return v;
}

double parseDouble(const ParsedArgs& p, const std::string& key, double def) {
  if (!p.has(key)) return def;
  const std::string v = p.value(key);
  try {
    std::size_t n = 0;
    const double d = std::stod(v, &n);
    if (n == v.size() && std::isfinite(d)) return d;
  } catch (const std::exception&) {
  }
  rasm::throwInputError("--" + key + " " + v, "expected a finite number");
}

/// --set sim_sensor.key=value / sim_robot.key=value into the recorder's overrides.
void applySets(const ParsedArgs& p, rasm::sim::RecordOptions& opt) {
  for (const std::string& s : p.values("set")) {
    const auto dot = s.find('.'), eq = s.find('=');
    if (dot == std::string::npos || eq == std::string::npos || eq < dot)
      rasm::throwInputError("--set " + s, "expected section.key=value");
    const std::string section = s.substr(0, dot), key = s.substr(dot + 1, eq - dot - 1),
                      value = s.substr(eq + 1);
    if (section == "sim_sensor")
      opt.sensor_overrides[key] = value;
    else if (section == "sim_robot")
      opt.robot_overrides[key] = value;
    else
      rasm::throwInputError("--set " + s,
                            "unknown section '" + section + "'; expected sim_sensor or sim_robot");
  }
}

const CommandDecl kRecordDecl{
    "sim record",
    "render a trajectory through a world into a rawlog with its ground truth and labels",
    {kWorld,
     {"trajectory.yaml", "the camera or robot path (docs/sim.md)"},
     {"out.rawlog", "the rawlog to write (ground truth and labels beside it)"}},
    {kSeed,
     kNoise,
     kCamera,
     {"max-frames", "N", "stop after N frames"},
     {"set", "section.key=value", "set a key of [sim_sensor] or [sim_robot]", "", true}},
    kWorldNote};

int cmdRecord(const ParsedArgs& p) {
  rasm::sim::RecordOptions opt;
  opt.world = p.positional("world");
  opt.trajectory_spec = p.positional("trajectory.yaml");
  opt.out_rawlog = p.positional("out.rawlog");
  opt.seed = parseSeed(p);
  if (p.has("noise")) {
    const char* v = parseOnOff(p, "noise", true) ? "true" : "false";
    opt.sensor_overrides["noise"] = v;  // --noise off: exact depth, no dropouts
    opt.sensor_overrides["dropouts"] = v;
  }
  if (p.has("camera")) opt.sensor_overrides["camera"] = p.value("camera");
  if (p.has("max-frames")) opt.max_frames = (long long)parseDouble(p, "max-frames", -1);
  applySets(p, opt);
  opt.progress = true;
  const rasm::sim::RecordResult r = rasm::sim::recordSequence(opt);
  std::cout << "wrote " << r.frames << " frames to " << r.rawlog_path
            << "\n  ground truth: " << r.groundtruth_path << "\n  labels: " << r.labels_dir << "\n";
  return 0;
}

const CommandDecl kRenderDecl{
    "sim render",
    "render one view of a world: colour, depth, instance and class PNGs",
    {kWorld, {"out_prefix", "writes <out_prefix>_{colour,depth,instance,class}.png"}},
    {{"eye", "x,y,z", "the camera position (m)", "", false, true},
     {"yaw", "deg", "the heading (default 0)"},
     {"pitch", "deg", "up (+) or down (-), -90..90 (default 0)"},
     {"look-at", "x,y,z", "the point the camera looks at (instead of --yaw and --pitch)"},
     kSeed,
     kNoise,
     kCamera},
    kWorldNote};

int cmdRender(const ParsedArgs& p) {
  const Eigen::Vector3d eye = parseVec3(p, "eye");
  Eigen::Isometry3d T;
  if (p.has("look-at")) {
    try {
      T = rasm::sim::cameraPoseLookingAt(eye, parseVec3(p, "look-at"));
    } catch (const std::invalid_argument& e) {
      rasm::throwInputError("--look-at " + p.value("look-at"), e.what());
    }
  } else {
    const double yaw = parseDouble(p, "yaw", 0.0), pitch = parseDouble(p, "pitch", 0.0);
    rasm::requireAngleDeg(yaw, "--yaw " + p.value("yaw"));
    rasm::requireFiniteIn(pitch, -90, 90, "--pitch " + p.value("pitch"));
    T = rasm::sim::cameraPoseFromHeading(eye, yaw, pitch);
  }
  rasm::sim::TSensorParams sp;
  sp.noise = parseOnOff(p, "noise", true);
  sp.dropouts = sp.noise;
  if (p.has("camera")) sp.camera = p.value("camera");
  const rasm::sim::RayScene scene(rasm::sim::loadWorld(p.positional("world")));
  const rasm::sim::RgbdSensor sensor(scene, sp);
  const rasm::RgbdFrame f = sensor.render(T, parseSeed(p), 0);
  const std::string prefix = p.positional("out_prefix");
  rasm::sim::savePreviewImages(f, prefix, sp.max_depth_m);
  std::cout << "wrote " << prefix << "_{colour,depth,instance,class}.png\n";
  return 0;
}

const CommandDecl kInfoDecl{
    "sim info", "a world's objects per class, triangles and bounds", {kWorld}, {}, kWorldNote};

int cmdInfo(const ParsedArgs& p) {
  const rasm::sim::World w = rasm::sim::loadWorld(p.positional("world"));
  std::map<std::string, int> per_class;
  std::size_t tris = 0;
  for (const auto& o : w.objects) {
    ++per_class[rasm::models::className(o.class_id)];
    tris += o.mesh.triangles.size();
  }
  const Eigen::AlignedBox3f b = w.bounds();
  std::cout << "world " << rasm::escapeControlChars(w.name) << " ("
            << rasm::escapeControlChars(w.source) << "): " << w.objects.size() << " objects, "
            << tris << " triangles, bounds [" << b.min().transpose() << "] - ["
            << b.max().transpose() << "] m\n";
  for (const auto& [name, n] : per_class) std::cout << "  " << n << " x " << name << "\n";
  return 0;
}

const CommandDecl kMakeModelsDecl{
    "sim make-models",
    "write the procedural object models",
    {{"dir", "where to write them (default: the simulator's models folder)", false}},
    {}};

int cmdMakeModels(const ParsedArgs& p) {
  const std::string dir =
      p.positional("dir").empty() ? rasm::sim::simDataDir() + "/models" : p.positional("dir");
  for (const auto& f : rasm::models::writeProceduralModels(dir)) std::cout << "wrote " << f << "\n";
  return 0;
}

/// "7x5" or "7.5x4.2" (metres).
void parseSize(const std::string& s, double& w, double& d) {
  char x = 0;
  std::istringstream in(s);
  if (!(in >> w >> x >> d) || (x != 'x' && x != 'X') || !in.eof() || !std::isfinite(w) ||
      !std::isfinite(d))
    rasm::throwInputError("--size " + s, "expected WxD in metres, e.g. 7x5 or 6.5x4.8");
}

/// An integer option (`--rooms`, `--plain-walls`) within [lo, hi]; `expected` says what it is.
int parseIntOption(const ParsedArgs& p, const std::string& key, int lo, int hi,
                   const std::string& expected) {
  const std::string v = p.value(key);
  std::size_t used = 0;
  int n = 0;
  try {
    n = std::stoi(v, &used);
  } catch (const std::exception&) {
    used = 0;
  }
  if (used == 0 || used != v.size() || n < lo || n > hi)
    rasm::throwInputError("--" + key + " " + v, "expected " + expected);
  return n;
}

const CommandDecl kGenerateDecl{
    "sim generate",
    "generate a furnished room or flat (world YAML) and, with --trajectories, paths through it",
    {{"out.yaml", "the world file to write"}},
    {{"seed", "N", "the world is a function of it", "", false, true},
     {"size", "WxD", "interior in metres, each side 3-16 (default: drawn from the seed)"},
     {"kind", "office|lab|mixed|break_room", "what furnishes the rooms (default mixed)"},
     {"layout", "room|flat", "one room (default), or a flat of rooms"},
     {"rooms", "N", "a flat's rooms, 2-5 (default 3; only with --layout flat)"},
     {"plain-walls", "N", "long sides of every room left plain: 0, 1 or 2"},
     {"trajectories", "DIR_OR_PREFIX", "where the trajectory specs go (default: beside the world)"},
     {"fast", "", "also the _handheld_fast and _robot_fast trajectories"}},
    "Writes <out.yaml> and the trajectories <stem>_handheld.yaml, <stem>_robot.yaml; the same\n"
    "options give byte-identical files (docs/sim.md \"Generated worlds\").\n"};

int cmdGenerate(const ParsedArgs& p) {
  rasm::sim::TWorldGenParams wp;
  wp.seed = parseSeed(p);
  if (p.has("size")) parseSize(p.value("size"), wp.width_m, wp.depth_m);
  if (p.has("kind")) wp.kind = rasm::sim::roomKindFromName(p.value("kind"), "--kind");
  if (p.has("layout")) wp.layout = rasm::sim::worldLayoutFromName(p.value("layout"), "--layout");
  if (p.has("rooms")) {
    if (wp.layout != rasm::sim::WorldLayout::Flat)
      rasm::throwInputError("--rooms " + p.value("rooms"),
                            "only with --layout flat (the room layout is one room)");
    wp.rooms = parseIntOption(p, "rooms", 2, 5, "2 to 5 rooms in a flat");
  }
  if (p.has("plain-walls"))
    wp.plain_walls = parseIntOption(p, "plain-walls", 0, 2,
                                    "0, 1 or 2 (long sides of each room left without furniture)");
  wp.validate();
  const rasm::sim::GenerateFilesResult r = rasm::sim::generateWorldFiles(
      wp, p.positional("out.yaml"), p.value("trajectories"), p.has("fast"));
  for (const std::string& line : r.summary) std::cout << "wrote " << line << "\n";
  return 0;
}

const CommandDecl kCheckMapDecl{
    "sim check-map",
    "how many surfels of a map lie farther than --max-dist-m from the world's surface",
    {kWorld, {"map.ply", "the surfel PLY of a `rasm run`"}},
    {{"max-dist-m", "0.05", "the distance (m) beyond which a surfel counts as off the surface"},
     {"cap-m", "0.5", "distances are measured up to this (m)"},
     {"stable-only", "", "only the surfels marked stable"},
     {"json", "out.json", "also write the result as JSON"}},
    kWorldNote};

/// `rasm sim check-map`: how many surfels of a map (PLY of `rasm run`) lie further than
/// --max-dist-m from the world's ground-truth surface (SurfaceDistance.h: an upper bound of the
/// distance by ray casts).
int cmdCheckMap(const ParsedArgs& p) {
  const double max_dist = parseDouble(p, "max-dist-m", 0.05);
  const double cap = parseDouble(p, "cap-m", 0.5);
  if (!(max_dist >= 0.0) || !std::isfinite(max_dist))
    rasm::throwInputError("--max-dist-m " + p.value("max-dist-m"), "expected a distance >= 0");
  if (!(cap > 0.0) || !std::isfinite(cap))
    rasm::throwInputError("--cap-m " + p.value("cap-m"), "expected a distance > 0");
#ifdef RASM_HAVE_MODULE_SURFEL_MAP
  const std::string ply = p.positional("map.ply");
  const rasm::maps::PlySurfels map = rasm::maps::readSurfelPly(ply);
  const bool stable_only = p.has("stable-only");
  std::vector<Eigen::Vector3f> positions, normals;
  positions.reserve(map.size());
  normals.reserve(map.size());
  for (std::size_t i = 0; i < map.size(); ++i) {
    if (stable_only && !map.stable[i]) continue;
    positions.push_back(map.position[i]);
    normals.push_back(map.normal[i]);
  }
  const rasm::sim::RayScene scene(rasm::sim::loadWorld(p.positional("world")));
  const rasm::sim::SurfaceDistanceStats s =
      rasm::sim::surfaceDistanceStats(scene, positions, normals, max_dist, cap);
  std::printf(
      "%s: %zu %ssurfels, %zu within %.3g m of the surface of world %s, %zu beyond (%.2f %%); "
      "distance p50 %.4f p90 %.4f p95 %.4f p99 %.4f max %.4f m (capped at %.3g m)\n",
      ply.c_str(), s.points, stable_only ? "stable " : "", s.within, max_dist,
      scene.world().name.c_str(), s.beyond, 100.0 * s.fraction_beyond, s.p50_m, s.p90_m, s.p95_m,
      s.p99_m, s.max_m, cap);
  if (p.has("json")) {
    const std::string out = p.value("json");
    nlohmann::json j;
    j["map"] = ply;
    j["world"] = scene.world().name;
    j["world_source"] = scene.world().source;
    j["stable_only"] = stable_only;
    j["surfels_in_file"] = map.size();
    j["surfels"] = s.points;
    j["within"] = s.within;
    j["beyond"] = s.beyond;
    j["fraction_beyond"] = s.fraction_beyond;
    j["max_dist_m"] = s.max_dist_m;
    j["cap_m"] = s.cap_m;
    j["distance_m"] = {{"p50", s.p50_m}, {"p90", s.p90_m}, {"p95", s.p95_m},
                       {"p99", s.p99_m}, {"max", s.max_m}, {"mean", s.mean_m}};
    try {
      rasm::writeFileAtomic(out, j.dump(2) + "\n");
    } catch (const std::runtime_error& e) {
      rasm::throwInputError("--json " + out, e.what());
    }
    std::cout << "wrote " << out << "\n";
  }
  return 0;
#else
  rasm::throwInputError("rasm sim check-map", "this build has no surfel_map module (PLY reader)");
#endif
}

const rasm::app::Registrar reg{
    {"sim",
     "simulator: record rawlogs from worlds, render previews, generate rooms, check maps against "
     "the ground truth (rasm sim help)",
     {},
     {},
     kWorldNote}};
const rasm::app::Registrar reg_record{kRecordDecl, &cmdRecord};
const rasm::app::Registrar reg_render{kRenderDecl, &cmdRender};
const rasm::app::Registrar reg_info{kInfoDecl, &cmdInfo};
const rasm::app::Registrar reg_make_models{kMakeModelsDecl, &cmdMakeModels};
const rasm::app::Registrar reg_generate{kGenerateDecl, &cmdGenerate};
const rasm::app::Registrar reg_check_map{kCheckMapDecl, &cmdCheckMap};

}  // namespace
