#include "rasm/sim/World.h"

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <map>
#include <set>
#include <sstream>

#include "YamlNode.h"
#include "rasm/core/Error.h"
#include "rasm/models/ClassVocabulary.h"

namespace fs = std::filesystem;

namespace rasm::sim {

Eigen::Affine3f WorldObject::worldFromObjectScaled() const {
  Eigen::Affine3f T(T_world_object.matrix().cast<float>());
  return T * Eigen::Scaling(scale);
}

models::TriangleMesh WorldObject::worldMesh() const {
  models::TriangleMesh m;
  m.append(mesh, worldFromObjectScaled());
  return m;
}

int World::indexOfInstance(std::uint16_t id) const {
  for (int i = 0; i < int(objects.size()); ++i)
    if (objects[i].instance_id == id) return i;
  return -1;
}

Eigen::AlignedBox3f World::bounds() const {
  Eigen::AlignedBox3f b;
  for (const auto& o : objects) {
    const Eigen::Affine3f T = o.worldFromObjectScaled();
    for (const auto& v : o.mesh.vertices) b.extend(T * v);
  }
  return b;
}

std::string simDataDir() {
  if (const char* env = std::getenv("RASM_SIM_DATA_DIR"); env && *env) return env;
  // An installed binary (cmake --install, the .deb): <prefix>/bin/rasm beside
  // <prefix>/share/rasm/sim.
  std::error_code ec;
  const fs::path exe = fs::read_symlink("/proc/self/exe", ec);
  if (!ec) {
    const fs::path installed = exe.parent_path().parent_path() / "share" / "rasm" / "sim";
    if (fs::is_directory(installed / "worlds", ec)) return installed.string();
  }
#ifdef RASM_SIM_DATA_DIR
  return RASM_SIM_DATA_DIR;
#else
  return "modules/sim";
#endif
}

std::vector<std::string> shippedWorlds() {
  std::vector<std::string> names;
  const fs::path dir = fs::path(simDataDir()) / "worlds";
  std::error_code ec;
  for (const auto& e : fs::directory_iterator(dir, ec))
    if (e.path().extension() == ".yaml") names.push_back(e.path().stem().string());
  std::sort(names.begin(), names.end());
  return names;
}

std::string resolveWorldPath(const std::string& name) {
  const fs::path shipped = fs::path(simDataDir()) / "worlds" / (name + ".yaml");
  if (name.find('/') == std::string::npos && fs::is_regular_file(shipped)) return shipped.string();
  if (fs::is_regular_file(name)) return name;
  std::string list;
  for (const auto& w : shippedWorlds()) list += (list.empty() ? "" : ", ") + w;
  throwInputError("world '" + name + "'",
                  "no such file and not a shipped world (shipped: " + list + ")");
}

namespace {

using detail::YNode;

Eigen::Vector3f parseColour(const YNode& n) {
  if (n.raw().IsScalar()) {
    const std::string s = n.asString();
    if (s.size() == 7 && s[0] == '#') {
      char* end = nullptr;
      const long v = std::strtol(s.c_str() + 1, &end, 16);
      if (end && *end == 0)
        return Eigen::Vector3f(float((v >> 16) & 255), float((v >> 8) & 255), float(v & 255)) /
               255.f;
    }
    n.fail("expected a colour [r, g, b] (0-255) or \"#rrggbb\", got '" + s + "'");
  }
  if (!n.isSequence() || n.size() != 3)
    n.fail("expected a colour [r, g, b] (0-255) or \"#rrggbb\"");
  Eigen::Vector3f c;
  for (int i = 0; i < 3; ++i) c[i] = float(n.at(std::size_t(i)).asDouble(0, 255) / 255.0);
  return c;
}

/// A size or scale [x, y, z]: three numbers in (0, max].
Eigen::Vector3d parsePositiveVec3(const YNode& n, double max) {
  const Eigen::Vector3d v = n.asVector(3, 0.0, max);
  if ((v.array() <= 0).any()) n.fail("expected three positive numbers");
  return v;
}

Eigen::Matrix3d yprToRotation(double yaw_deg, double pitch_deg, double roll_deg) {
  const double d = M_PI / 180.0;
  // MRPT's CPose3D convention: R = Rz(yaw) * Ry(pitch) * Rx(roll).
  return (Eigen::AngleAxisd(yaw_deg * d, Eigen::Vector3d::UnitZ()) *
          Eigen::AngleAxisd(pitch_deg * d, Eigen::Vector3d::UnitY()) *
          Eigen::AngleAxisd(roll_deg * d, Eigen::Vector3d::UnitX()))
      .toRotationMatrix();
}

Material parseMaterial(const YNode& obj) {
  Material m;
  if (auto c = obj.optional("colour")) m.colour_rgb = parseColour(*c);
  m.colour2_rgb = 0.6f * m.colour_rgb;
  if (auto t = obj.optional("texture")) {
    t->allowKeys({"pattern", "colour2", "period_m", "axis"});
    const std::string p = (*t)["pattern"].asString();
    if (p == "solid")
      m.pattern = Pattern::Solid;
    else if (p == "checker")
      m.pattern = Pattern::Checker;
    else if (p == "stripes")
      m.pattern = Pattern::Stripes;
    else if (p == "noise")
      m.pattern = Pattern::Noise;
    else
      (*t)["pattern"].fail("unknown pattern '" + p +
                           "'; expected solid, checker, stripes or noise");
    if (auto c2 = t->optional("colour2")) m.colour2_rgb = parseColour(*c2);
    if (auto per = t->optional("period_m")) m.period_m = float(per->asDouble(1e-3, 100.0));
    if (auto ax = t->optional("axis")) {
      const std::string a = ax->asString();
      if (a == "x")
        m.stripe_axis = 0;
      else if (a == "y")
        m.stripe_axis = 1;
      else if (a == "z")
        m.stripe_axis = 2;
      else
        ax->fail("expected x, y or z");
    }
  }
  return m;
}

struct Loader {
  std::string base_dir;
  std::map<std::string, models::TriangleMesh> mesh_cache;

  std::string resolveMesh(const YNode& n) {
    const std::string f = n.asString();
    std::vector<fs::path> tried;
    if (fs::path(f).is_absolute())
      tried.emplace_back(f);
    else {
      if (!base_dir.empty()) tried.push_back(fs::path(base_dir) / f);
      tried.push_back(fs::path(simDataDir()) / "models" / f);
    }
    for (const auto& p : tried)
      if (fs::is_regular_file(p)) return p.string();
    std::string where;
    for (const auto& p : tried) where += (where.empty() ? "" : ", ") + p.string();
    n.fail("mesh file '" + f + "' not found (looked in: " + where + ")");
  }

  WorldObject parseObject(const YNode& o, bool is_static) {
    o.allowKeys({"id", "name", "class", "mesh", "primitive", "size", "radius", "height", "scale",
                 "position", "ypr_deg", "yaw_deg", "quaternion", "colour", "texture"});
    WorldObject w;
    w.is_static = is_static;
    w.instance_id = std::uint16_t(o["id"].asInt(1, 65535));
    if (auto n = o.optional("name")) w.name = n->asString();
    {
      const YNode c = o["class"];
      const std::string cname = c.isNull() ? std::string("none") : c.asString();
      const int id = models::classIdFromName(cname);
      if (id < 0)
        c.fail("unknown class '" + cname +
               "' (use a COCO name, a project class or none; see docs/sim.md)");
      w.class_id = std::uint16_t(id);
    }
    const bool has_mesh = o.has("mesh"), has_prim = o.has("primitive");
    if (has_mesh == has_prim) o.fail("expected exactly one of 'mesh' or 'primitive'");
    if (has_mesh) {
      const std::string path = resolveMesh(o["mesh"]);
      auto it = mesh_cache.find(path);
      if (it == mesh_cache.end())
        it =
            mesh_cache.emplace(path, models::loadMesh(path, o.source() + ": " + o.path() + ".mesh"))
                .first;
      w.mesh = it->second;
      w.mesh_source = path;
      for (const char* k : {"size", "radius", "height"})
        if (o.has(k)) o[k].fail("only for primitives");
    } else {
      const YNode p = o["primitive"];
      w.mesh_source = p.asString();
      if (w.mesh_source == "box") {
        w.mesh = models::makeBox(parsePositiveVec3(o["size"], kMaxSize_m).cast<float>());
      } else if (w.mesh_source == "cylinder") {
        w.mesh = models::makeCylinder(float(o["radius"].asDouble(1e-4, 1e3)),
                                      float(o["height"].asDouble(1e-4, 1e3)));
      } else if (w.mesh_source == "sphere") {
        w.mesh = models::makeSphere(float(o["radius"].asDouble(1e-4, 1e3)));
      } else {
        p.fail("unknown primitive '" + w.mesh_source + "'; expected box, cylinder or sphere");
      }
      const bool box = w.mesh_source == "box";
      if (box && (o.has("radius") || o.has("height")))
        o.fail("a box takes 'size', not radius/height");
      if (!box && o.has("size")) o["size"].fail("only boxes take 'size'");
      if (w.mesh_source == "sphere" && o.has("height"))
        o["height"].fail("a sphere takes only 'radius'");
    }
    if (auto s = o.optional("scale")) {
      if (s->raw().IsScalar())
        w.scale.setConstant(float(s->asDouble(1e-4, 1e4)));
      else
        w.scale = parsePositiveVec3(*s, 1e4).cast<float>();
    }
    w.T_world_object.setIdentity();
    w.T_world_object.translation() = o["position"].asPosition();
    const int nrot = int(o.has("ypr_deg")) + int(o.has("yaw_deg")) + int(o.has("quaternion"));
    if (nrot > 1) o.fail("give at most one of ypr_deg, yaw_deg, quaternion");
    if (auto r = o.optional("ypr_deg")) {
      const Eigen::Vector3d ypr = r->asVec3();
      w.T_world_object.linear() = yprToRotation(ypr[0], ypr[1], ypr[2]);
    } else if (auto y = o.optional("yaw_deg")) {
      w.T_world_object.linear() = yprToRotation(y->asDouble(), 0, 0);
    } else if (auto q = o.optional("quaternion")) {
      const Eigen::VectorXd v = q->asVector(4);  // x y z w (TUM / ROS order)
      Eigen::Quaterniond qq(v[3], v[0], v[1], v[2]);
      if (qq.norm() < 1e-9) q->fail("zero quaternion");
      w.T_world_object.linear() = qq.normalized().toRotationMatrix();
    }
    w.material = parseMaterial(o);
    return w;
  }
};

}  // namespace

World loadWorldFromString(const std::string& text, const std::string& source,
                          const std::string& base_dir) {
  const YNode doc = YNode::parse(text, source);
  if (doc.isNull()) doc.fail("empty world file");
  doc.allowKeys({"world", "description", "light", "background", "static", "objects"});
  World w;
  w.source = source;
  w.name = doc.has("world") ? doc["world"].asString() : fs::path(source).stem().string();
  if (auto l = doc.optional("light")) {
    l->allowKeys({"direction", "ambient", "diffuse"});
    if (auto d = l->optional("direction")) {
      const Eigen::Vector3d v = d->asVec3();
      if (v.norm() < 1e-9) d->fail("zero direction");
      w.light.direction_world = v.normalized().cast<float>();
    }
    if (auto a = l->optional("ambient")) w.light.ambient = float(a->asDouble(0, 1));
    if (auto d = l->optional("diffuse")) w.light.diffuse = float(d->asDouble(0, 1));
  }
  w.light.direction_world.normalize();
  if (auto b = doc.optional("background")) w.background_rgb = parseColour(*b);

  Loader loader{base_dir, {}};
  std::map<int, std::string> seen;  // instance id -> key path
  for (const char* section : {"static", "objects"}) {
    const auto list = doc.optional(section);
    if (!list || list->isNull()) continue;
    for (const YNode& o : list->items()) {
      WorldObject obj = loader.parseObject(o, std::string(section) == "static");
      const auto [it, fresh] = seen.emplace(obj.instance_id, o.path());
      if (!fresh)
        o["id"].fail("instance id " + std::to_string(obj.instance_id) + " already used by " +
                     it->second);
      w.objects.push_back(std::move(obj));
    }
  }
  if (w.objects.empty())
    doc.fail("the world has no geometry: expected 'static' and/or 'objects' lists");
  return w;
}

World loadWorld(const std::string& name_or_path) {
  const std::string path = resolveWorldPath(name_or_path);
  std::ifstream f(path);
  if (!f) throwInputError(path, "cannot open world file");
  std::stringstream ss;
  ss << f.rdbuf();
  return loadWorldFromString(ss.str(), path, fs::path(path).parent_path().string());
}

}  // namespace rasm::sim
