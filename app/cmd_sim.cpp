// `rasm sim ...`: the simulator's command line (thin layer over rasm::sim).
//   rasm sim record <world> <trajectory.yaml> <out.rawlog> [--seed N] [--noise on|off] [--camera
//   preset]
//                   [--max-frames N] [--set sim_sensor.key=value] [--set sim_robot.key=value]
//   rasm sim render <world> <out_prefix> (--eye x,y,z (--yaw deg [--pitch deg] | --look-at x,y,z))
//                   [--seed N] [--noise on|off] [--camera preset]
//   rasm sim info <world>
//   rasm sim make-models [dir]
//   rasm sim generate <out.yaml> --seed N [--size WxD] [--kind office|lab|mixed|break_room]
//                     [--layout room|flat] [--rooms N] [--plain-walls N]
//                     [--trajectories DIR_OR_PREFIX] [--fast]
//   rasm sim check-map <world> <map.ply> [--max-dist-m 0.05] [--cap-m 0.5] [--stable-only]
//                      [--json out.json]
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
#include "rasm/sim/CameraPoses.h"
#include "rasm/sim/FrameImages.h"
#include "rasm/sim/ProceduralModels.h"
#include "rasm/sim/RayScene.h"
#include "rasm/sim/Recorder.h"
#include "rasm/sim/RgbdSensor.h"
#include "rasm/sim/SimClasses.h"
#include "rasm/sim/SurfaceDistance.h"
#include "rasm/sim/TrajectoryGenerator.h"
#include "rasm/sim/World.h"
#include "rasm/sim/WorldGenerator.h"
#ifdef RASM_HAVE_MODULE_SURFEL_MAP
#include "rasm/surfel_map/MapExport.h"
#endif

namespace {

using Args = std::vector<std::string>;

const char* kUsage =
    "usage:\n"
    "  rasm sim record <world> <trajectory.yaml> <out.rawlog> [--seed N] [--noise on|off] "
    "[--camera preset]\n"
    "                  [--max-frames N] [--set sim_sensor.key=value] [--set sim_robot.key=value]\n"
    "  rasm sim render <world> <out_prefix> --eye x,y,z (--yaw deg [--pitch deg] | --look-at "
    "x,y,z)\n"
    "                  [--seed N] [--noise on|off] [--camera preset]\n"
    "  rasm sim info <world>\n"
    "  rasm sim make-models [dir]\n"
    "  rasm sim generate <out.yaml> --seed N [--size WxD] [--kind office|lab|mixed|break_room]\n"
    "                    [--layout room|flat] [--rooms N] [--plain-walls N]\n"
    "                    [--trajectories DIR_OR_PREFIX] [--fast]\n"
    "  rasm sim check-map <world> <map.ply> [--max-dist-m 0.05] [--cap-m 0.5] [--stable-only]\n"
    "                     [--json out.json]\n"
    "<world> is a shipped world name (office, cluttered_lab, two_rooms) or a YAML file "
    "(docs/sim.md).\n";

/// Splits positional arguments from --key value options and --flag options (no value).
struct Parsed {
  Args positional;
  std::map<std::string, std::string> options;
  std::vector<std::string> sets;  ///< every --set value, in order
  std::vector<std::string> flags;
  bool flag(const std::string& f) const {
    return std::find(flags.begin(), flags.end(), f) != flags.end();
  }
};

Parsed parse(const Args& args, std::initializer_list<const char*> known,
             std::initializer_list<const char*> flags = {}) {
  Parsed p;
  for (std::size_t i = 0; i < args.size(); ++i) {
    const std::string& a = args[i];
    if (a.rfind("--", 0) != 0) {
      p.positional.push_back(a);
      continue;
    }
    const std::string key = a.substr(2);
    bool is_flag = false;
    for (const char* f : flags) is_flag = is_flag || key == f;
    if (is_flag) {
      p.flags.push_back(key);
      continue;
    }
    bool ok = false;
    for (const char* k : known) ok = ok || key == k;
    if (!ok) rasm::throwInputError("option " + a, "unknown option\n" + std::string(kUsage));
    if (i + 1 >= args.size()) rasm::throwInputError("option " + a, "missing value");
    if (key == "set")
      p.sets.push_back(args[++i]);
    else
      p.options[key] = args[++i];
  }
  return p;
}

std::uint64_t parseSeed(const Parsed& p) {
  const auto it = p.options.find("seed");
  if (it == p.options.end()) return 0;
  try {
    std::size_t n = 0;
    const unsigned long long v = std::stoull(it->second, &n);
    if (n == it->second.size()) return v;
  } catch (const std::exception&) {
  }
  rasm::throwInputError("--seed " + it->second, "expected a non-negative integer");
}

bool parseOnOff(const Parsed& p, const std::string& key, bool def) {
  const auto it = p.options.find(key);
  if (it == p.options.end()) return def;
  if (it->second == "on") return true;
  if (it->second == "off") return false;
  rasm::throwInputError("--" + key + " " + it->second, "expected on or off");
}

Eigen::Vector3d parseVec3(const Parsed& p, const std::string& key) {
  const std::string& s = p.options.at(key);
  Eigen::Vector3d v;
  char c1 = 0, c2 = 0;
  std::istringstream in(s);
  if (!(in >> v.x() >> c1 >> v.y() >> c2 >> v.z()) || c1 != ',' || c2 != ',' || !in.eof())
    rasm::throwInputError("--" + key + " " + s, "expected x,y,z (three finite numbers)");
  for (int i = 0; i < 3; ++i) rasm::requireCoordinate(v[i], "--" + key + " " + s);
  return v;
}

double parseDouble(const Parsed& p, const std::string& key, double def) {
  const auto it = p.options.find(key);
  if (it == p.options.end()) return def;
  try {
    std::size_t n = 0;
    const double v = std::stod(it->second, &n);
    if (n == it->second.size() && std::isfinite(v)) return v;
  } catch (const std::exception&) {
  }
  rasm::throwInputError("--" + key + " " + it->second, "expected a finite number");
}

/// --set sim_sensor.key=value / sim_robot.key=value into the recorder's overrides.
void applySets(const Parsed& p, rasm::sim::RecordOptions& opt) {
  for (const std::string& s : p.sets) {
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

int cmdRecord(const Args& args) {
  const Parsed p = parse(args, {"seed", "noise", "camera", "max-frames", "set"});
  if (p.positional.size() != 3)
    rasm::throwInputError("rasm sim record", "expected <world> <trajectory.yaml> <out.rawlog>\n" +
                                                 std::string(kUsage));
  rasm::sim::RecordOptions opt;
  opt.world = p.positional[0];
  opt.trajectory_spec = p.positional[1];
  opt.out_rawlog = p.positional[2];
  opt.seed = parseSeed(p);
  if (p.options.count("noise")) {
    const char* v = parseOnOff(p, "noise", true) ? "true" : "false";
    opt.sensor_overrides["noise"] = v;  // --noise off: exact depth, no dropouts
    opt.sensor_overrides["dropouts"] = v;
  }
  if (p.options.count("camera")) opt.sensor_overrides["camera"] = p.options.at("camera");
  if (p.options.count("max-frames")) opt.max_frames = (long long)parseDouble(p, "max-frames", -1);
  applySets(p, opt);
  opt.progress = true;
  const rasm::sim::RecordResult r = rasm::sim::recordSequence(opt);
  std::cout << "wrote " << r.frames << " frames to " << r.rawlog_path
            << "\n  ground truth: " << r.groundtruth_path << "\n  labels: " << r.labels_dir << "\n";
  return 0;
}

int cmdRender(const Args& args) {
  const Parsed p = parse(args, {"eye", "yaw", "pitch", "look-at", "seed", "noise", "camera"});
  if (p.positional.size() != 2)
    rasm::throwInputError("rasm sim render",
                          "expected <world> <out_prefix>\n" + std::string(kUsage));
  if (!p.options.count("eye")) rasm::throwInputError("rasm sim render", "--eye x,y,z is required");
  const Eigen::Vector3d eye = parseVec3(p, "eye");
  Eigen::Isometry3d T;
  if (p.options.count("look-at")) {
    try {
      T = rasm::sim::cameraPoseLookingAt(eye, parseVec3(p, "look-at"));
    } catch (const std::invalid_argument& e) {
      rasm::throwInputError("--look-at " + p.options.at("look-at"), e.what());
    }
  } else {
    const double yaw = parseDouble(p, "yaw", 0.0), pitch = parseDouble(p, "pitch", 0.0);
    rasm::requireAngleDeg(yaw, "--yaw " + (p.options.count("yaw") ? p.options.at("yaw") : ""));
    rasm::requireFiniteIn(pitch, -90, 90,
                          "--pitch " + (p.options.count("pitch") ? p.options.at("pitch") : ""));
    T = rasm::sim::cameraPoseFromHeading(eye, yaw, pitch);
  }
  rasm::sim::TSensorParams sp;
  sp.noise = parseOnOff(p, "noise", true);
  sp.dropouts = sp.noise;
  if (p.options.count("camera")) sp.camera = p.options.at("camera");
  const rasm::sim::RayScene scene(rasm::sim::loadWorld(p.positional[0]));
  const rasm::sim::RgbdSensor sensor(scene, sp);
  const rasm::RgbdFrame f = sensor.render(T, parseSeed(p), 0);
  rasm::sim::savePreviewImages(f, p.positional[1], sp.max_depth_m);
  std::cout << "wrote " << p.positional[1] << "_{colour,depth,instance,class}.png\n";
  return 0;
}

int cmdInfo(const Args& args) {
  if (args.size() != 1)
    rasm::throwInputError("rasm sim info", "expected <world>\n" + std::string(kUsage));
  const rasm::sim::World w = rasm::sim::loadWorld(args[0]);
  std::map<std::string, int> per_class;
  std::size_t tris = 0;
  for (const auto& o : w.objects) {
    ++per_class[rasm::sim::className(o.class_id)];
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

int cmdMakeModels(const Args& args) {
  if (args.size() > 1)
    rasm::throwInputError("rasm sim make-models", "expected at most one directory");
  const std::string dir = args.empty() ? rasm::sim::simDataDir() + "/models" : args[0];
  for (const auto& f : rasm::sim::writeProceduralModels(dir)) std::cout << "wrote " << f << "\n";
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
int parseIntOption(const Parsed& p, const std::string& key, int lo, int hi,
                   const std::string& expected) {
  const std::string& v = p.options.at(key);
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

int cmdGenerate(const Args& args) {
  const Parsed p = parse(
      args, {"seed", "size", "kind", "layout", "rooms", "plain-walls", "trajectories"}, {"fast"});
  if (p.positional.size() != 1)
    rasm::throwInputError("rasm sim generate", "expected one <out.yaml>\n" + std::string(kUsage));
  if (!p.options.count("seed"))
    rasm::throwInputError("rasm sim generate",
                          "--seed N is required (the world is a function of it)");
  rasm::sim::TWorldGenParams wp;
  wp.seed = parseSeed(p);
  if (p.options.count("size")) parseSize(p.options.at("size"), wp.width_m, wp.depth_m);
  if (p.options.count("kind"))
    wp.kind = rasm::sim::roomKindFromName(p.options.at("kind"), "--kind");
  if (p.options.count("layout"))
    wp.layout = rasm::sim::worldLayoutFromName(p.options.at("layout"), "--layout");
  if (p.options.count("rooms")) {
    if (wp.layout != rasm::sim::WorldLayout::Flat)
      rasm::throwInputError("--rooms " + p.options.at("rooms"),
                            "only with --layout flat (the room layout is one room)");
    wp.rooms = parseIntOption(p, "rooms", 2, 5, "2 to 5 rooms in a flat");
  }
  if (p.options.count("plain-walls"))
    wp.plain_walls = parseIntOption(p, "plain-walls", 0, 2,
                                    "0, 1 or 2 (long sides of each room left without furniture)");
  wp.validate();
  const std::string traj = p.options.count("trajectories") ? p.options.at("trajectories") : "";
  const rasm::sim::GenerateFilesResult r =
      rasm::sim::generateWorldFiles(wp, p.positional[0], traj, p.flag("fast"));
  for (const std::string& line : r.summary) std::cout << "wrote " << line << "\n";
  return 0;
}

/// `rasm sim check-map`: how many surfels of a map (PLY of `rasm run`) lie further than
/// --max-dist-m from the world's ground-truth surface (SurfaceDistance.h: an upper bound of the
/// distance by ray casts).
int cmdCheckMap(const Args& args) {
  const Parsed p = parse(args, {"max-dist-m", "cap-m", "json"}, {"stable-only"});
  if (p.positional.size() != 2)
    rasm::throwInputError("rasm sim check-map",
                          "expected <world> <map.ply>\n" + std::string(kUsage));
  const double max_dist = parseDouble(p, "max-dist-m", 0.05);
  const double cap = parseDouble(p, "cap-m", 0.5);
  if (!(max_dist >= 0.0) || !std::isfinite(max_dist))
    rasm::throwInputError("--max-dist-m " + p.options.at("max-dist-m"), "expected a distance >= 0");
  if (!(cap > 0.0) || !std::isfinite(cap))
    rasm::throwInputError("--cap-m " + p.options.at("cap-m"), "expected a distance > 0");
#ifdef RASM_HAVE_MODULE_SURFEL_MAP
  const std::string& ply = p.positional[1];
  const rasm::maps::PlySurfels map = rasm::maps::readSurfelPly(ply);
  const bool stable_only = p.flag("stable-only");
  std::vector<Eigen::Vector3f> positions, normals;
  positions.reserve(map.size());
  normals.reserve(map.size());
  for (std::size_t i = 0; i < map.size(); ++i) {
    if (stable_only && !map.stable[i]) continue;
    positions.push_back(map.position[i]);
    normals.push_back(map.normal[i]);
  }
  const rasm::sim::RayScene scene(rasm::sim::loadWorld(p.positional[0]));
  const rasm::sim::SurfaceDistanceStats s =
      rasm::sim::surfaceDistanceStats(scene, positions, normals, max_dist, cap);
  std::printf(
      "%s: %zu %ssurfels, %zu within %.3g m of the surface of world %s, %zu beyond (%.2f %%); "
      "distance p50 %.4f p90 %.4f p95 %.4f p99 %.4f max %.4f m (capped at %.3g m)\n",
      ply.c_str(), s.points, stable_only ? "stable " : "", s.within, max_dist,
      scene.world().name.c_str(), s.beyond, 100.0 * s.fraction_beyond, s.p50_m, s.p90_m, s.p95_m,
      s.p99_m, s.max_m, cap);
  if (p.options.count("json")) {
    const std::string out = p.options.at("json");
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

int cmdSim(const Args& args) {
  if (args.empty()) {
    std::cerr << kUsage;
    return 1;
  }
  const Args rest(args.begin() + 1, args.end());
  if (args[0] == "record") return cmdRecord(rest);
  if (args[0] == "render") return cmdRender(rest);
  if (args[0] == "info") return cmdInfo(rest);
  if (args[0] == "make-models") return cmdMakeModels(rest);
  if (args[0] == "generate") return cmdGenerate(rest);
  if (args[0] == "check-map") return cmdCheckMap(rest);
  if (args[0] == "help") {
    std::cout << kUsage;
    return 0;
  }
  rasm::throwInputError("rasm sim " + args[0], "unknown subcommand\n" + std::string(kUsage));
}

const rasm::app::Registrar kRegistrar{
    "sim",
    "simulator: record rawlogs from worlds, render previews, generate rooms, check maps against "
    "the ground truth (rasm sim help)",
    &cmdSim, kUsage};

}  // namespace
