#include "rasm/meshing/SurfelMesh.h"

#include <dlfcn.h>
#include <mrpt/config/CConfigFileBase.h>

#include <cmath>
#include <mutex>
#include <stdexcept>

#include "MeshBackend.h"
#include "rasm/core/Error.h"
#include "rasm/core/Params.h"

namespace rasm::meshing {

void TMeshParams::loadFromConfigFile(const mrpt::config::CConfigFileBase& c, const std::string& s) {
  MRPT_LOAD_CONFIG_VAR(voxel_m, double, c, s);
  MRPT_LOAD_CONFIG_VAR(truncation_m, double, c, s);
  MRPT_LOAD_CONFIG_VAR(max_views, int, c, s);
  MRPT_LOAD_CONFIG_VAR(width, int, c, s);
  MRPT_LOAD_CONFIG_VAR(height, int, c, s);
  MRPT_LOAD_CONFIG_VAR(max_depth_m, double, c, s);
  validate(s);
}

void TMeshParams::validate(const std::string& s) const {
  requireInRange(voxel_m, 0.002, 0.5, s, "voxel_m");
  requireInRange(truncation_m, voxel_m, 1.0, s, "truncation_m");  // at least one cell
  requireInRange(max_views, 1, 100000, s, "max_views");
  requireInRange(width, 16, 4096, s, "width");
  requireInRange(height, 16, 4096, s, "height");
  // Beyond the renders' 0.1 m near plane (build): a bound of 0.1 itself renders nothing.
  requireInRange(max_depth_m, std::nextafter(0.1, 1.0), 20.0, s, "max_depth_m");
}

void TMeshParams::saveToConfigFile(mrpt::config::CConfigFileBase& c, const std::string& s) const {
  MRPT_SAVE_CONFIG_VAR(voxel_m, c, s);
  MRPT_SAVE_CONFIG_VAR(truncation_m, c, s);
  MRPT_SAVE_CONFIG_VAR(max_views, c, s);
  MRPT_SAVE_CONFIG_VAR(width, c, s);
  MRPT_SAVE_CONFIG_VAR(height, c, s);
  MRPT_SAVE_CONFIG_VAR(max_depth_m, c, s);
}

detail::MeshBackend::~MeshBackend() = default;

namespace {

struct Plugin {
  detail::BuildFn build = nullptr;
  std::string error;  ///< why build is null
};

/// The plugin's build function, loaded once from the folder this library was loaded from (the
/// build tree's modules/meshing, or the installed lib/rasm). Never unloaded: meshes it made may
/// outlive any caller.
const Plugin& plugin() {
  static std::once_flag once;
  static Plugin loaded;
  std::call_once(once, [] {
    auto& build = loaded.build;
    auto& error = loaded.error;
    Dl_info self{};
    std::string dir;
    if (dladdr(reinterpret_cast<const void*>(&plugin), &self) != 0 && self.dli_fname) {
      dir = self.dli_fname;
      const std::size_t slash = dir.rfind('/');
      dir = slash == std::string::npos ? std::string() : dir.substr(0, slash + 1);
    }
    const std::string path = dir + detail::kPluginFile;
    void* lib = dlopen(path.c_str(), RTLD_NOW | RTLD_LOCAL);
    if (!lib) {
      const char* why = dlerror();
      error = std::string("the mesh needs Open3D's plugin (Debian's libopen3d-dev): ") +
              (why ? why : path + " did not load");
      return;
    }
    build = reinterpret_cast<detail::BuildFn>(dlsym(lib, detail::kBuildSymbol));
    if (!build) error = "the plugin " + path + " has no " + detail::kBuildSymbol;
  });
  return loaded;
}

}  // namespace

SurfelMesh SurfelMesh::build(const maps::SurfelStore& map,
                             const std::vector<Eigen::Isometry3d>& T_world_cam,
                             const CameraIntrinsics& K, const TMeshParams& params) {
  if (K.width <= 0 || K.height <= 0 || !(K.fx > 0) || !(K.fy > 0))
    throwInputError("mesh camera", "intrinsics " + K.toString() + " are not valid");
  params.validate();
  const Plugin& p = plugin();
  if (!p.build) throw std::runtime_error(p.error);
  SurfelMesh out;
  out.m_mesh.reset(p.build(map, T_world_cam, K, params));
  return out;
}

std::string SurfelMesh::unavailable() {
  return plugin().error;
}

std::size_t SurfelMesh::vertices() const {
  return m_mesh ? m_mesh->vertices() : 0;
}
std::size_t SurfelMesh::triangles() const {
  return m_mesh ? m_mesh->triangles() : 0;
}
int SurfelMesh::views() const {
  return m_mesh ? m_mesh->views() : 0;
}

void SurfelMesh::colourByClass(const maps::SurfelStore& map) {
  if (m_mesh) m_mesh->colourByClass(map);
}

void SurfelMesh::writePly(const std::string& path) const {
  if (triangles() == 0)  // (Open3D writes no PLY of an empty mesh)
    throw std::runtime_error("the mesh " + path + " has no triangle to write");
  m_mesh->writePly(path);
}

std::vector<Eigen::Vector3d> SurfelMesh::vertexPositions() const {
  return m_mesh ? m_mesh->vertexPositions() : std::vector<Eigen::Vector3d>{};
}

std::vector<Eigen::Vector3d> SurfelMesh::vertexColours() const {
  return m_mesh ? m_mesh->vertexColours() : std::vector<Eigen::Vector3d>{};
}

}  // namespace rasm::meshing
