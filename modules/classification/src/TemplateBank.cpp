// Zero-shot template training (paper IV-A): models file, orthographic rendering, HOG templates and
// the bank file. See TemplateBank.h for the formats and the choices.
#include "rasm/classification/TemplateBank.h"

#include <yaml-cpp/yaml.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <limits>
#include <opencv2/core.hpp>
#include <opencv2/imgproc.hpp>
#include <opencv2/objdetect.hpp>
#include <sstream>

#include "rasm/core/AtomicFile.h"
#include "rasm/core/Error.h"
#include "rasm/models/ProceduralModels.h"

namespace rasm::classification {

namespace {

constexpr float kDegToRad = float(M_PI / 180.0);

// ---------------------------------------------------------------------------------------------
// Models file

/// "<file>:<line>: <key>" for messages about one YAML node.
std::string where(const std::string& file, const YAML::Node& node, const std::string& key) {
  const YAML::Mark m = node.Mark();
  return file + (m.line >= 0 ? ":" + std::to_string(m.line + 1) : "") + ": " + key;
}

double number(const std::string& file, const YAML::Node& node, const std::string& key) {
  if (!node || !node.IsScalar()) throwInputError(where(file, node, key), "expected a number");
  try {
    const double v = node.as<double>();
    if (!std::isfinite(v)) throw YAML::Exception(node.Mark(), "not finite");
    return v;
  } catch (const YAML::Exception&) {
    throwInputError(where(file, node, key), "expected a number, got '" + node.Scalar() + "'");
  }
}

void allowKeys(const std::string& file, const YAML::Node& node, const std::string& key,
               const std::vector<std::string>& allowed) {
  if (!node.IsMap()) throwInputError(where(file, node, key), "expected a mapping");
  for (const auto& kv : node) {
    const std::string k = kv.first.as<std::string>();
    if (std::find(allowed.begin(), allowed.end(), k) != allowed.end()) continue;
    std::string list;
    for (const auto& a : allowed) list += (list.empty() ? "" : ", ") + a;
    throwInputError(where(file, kv.first, key + "." + k), "unknown key; expected one of " + list);
  }
}

TemplateViews parseViews(const std::string& file, const YAML::Node& node) {
  TemplateViews v;
  allowKeys(file, node, "views",
            {"azimuth_step_deg", "elevation_deg", "elevation_step_deg", "render_px"});
  auto in = [&](const char* key, double value, double lo, double hi) {
    if (!(value >= lo && value <= hi))
      throwInputError(where(file, node[key], std::string("views.") + key),
                      "value " + std::to_string(value) + " out of range [" + std::to_string(lo) +
                          ", " + std::to_string(hi) + "]");
    return value;
  };
  if (node["azimuth_step_deg"])
    v.azimuth_step_deg =
        float(in("azimuth_step_deg",
                 number(file, node["azimuth_step_deg"], "views.azimuth_step_deg"), 0.5, 180));
  if (node["elevation_step_deg"])
    v.elevation_step_deg =
        float(in("elevation_step_deg",
                 number(file, node["elevation_step_deg"], "views.elevation_step_deg"), 0.5, 90));
  if (node["render_px"])
    v.render_px = int(in("render_px", number(file, node["render_px"], "views.render_px"), 16, 512));
  if (const YAML::Node e = node["elevation_deg"]) {
    if (!e.IsSequence() || e.size() != 2)
      throwInputError(where(file, e, "views.elevation_deg"), "expected [first, last] in degrees");
    v.elevation_min_deg = float(number(file, e[0], "views.elevation_deg[0]"));
    v.elevation_max_deg = float(number(file, e[1], "views.elevation_deg[1]"));
    if (!(v.elevation_min_deg > -90.f && v.elevation_max_deg < 90.f &&
          v.elevation_min_deg <= v.elevation_max_deg))
      throwInputError(where(file, e, "views.elevation_deg"),
                      "expected -90 < first <= last < 90 (degrees)");
  }
  return v;
}

/// box: {x: [min, max, steps], ...} -> the values tried per axis.
void parseBox(const std::string& file, const YAML::Node& node, const std::string& key,
              ModelSpec& m) {
  allowKeys(file, node, key, {"x", "y", "z"});
  const char* axes[3] = {"x", "y", "z"};
  for (int a = 0; a < 3; ++a) {
    const YAML::Node r = node[axes[a]];
    const std::string k = key + "." + axes[a];
    if (!r || !r.IsSequence() || r.size() != 3)
      throwInputError(where(file, r ? r : node, k), "expected [min_m, max_m, steps]");
    const double lo = number(file, r[0], k + "[0]"), hi = number(file, r[1], k + "[1]");
    const double steps = number(file, r[2], k + "[2]");
    if (!(lo > 0 && hi >= lo) || steps < 1 || steps > 64 || steps != std::floor(steps))
      throwInputError(where(file, r, k), "expected 0 < min_m <= max_m and 1 <= steps <= 64");
    for (int i = 0; i < int(steps); ++i)
      m.box_values[a].push_back(float(steps == 1 ? lo : lo + (hi - lo) * i / (steps - 1)));
  }
}

void applyScale(const std::string& file, const YAML::Node& node, const std::string& key,
                models::TriangleMesh& mesh) {
  Eigen::Vector3f s;
  if (node.IsSequence() && node.size() == 3) {
    for (int a = 0; a < 3; ++a)
      s[a] = float(number(file, node[a], key + "[" + std::to_string(a) + "]"));
  } else {
    s.setConstant(float(number(file, node, key)));
  }
  if (!(s.minCoeff() > 0.f)) throwInputError(where(file, node, key), "scale must be > 0");
  for (auto& v : mesh.vertices) v = v.cwiseProduct(s);
}

ModelSpec parseModel(const std::string& file, const std::string& base_dir, const YAML::Node& node,
                     const std::string& key) {
  allowKeys(file, node, key, {"class", "procedural", "mesh", "box", "scale", "azimuth_symmetry"});
  ModelSpec m;
  if (!node["class"] || !node["class"].IsScalar() || node["class"].Scalar().empty())
    throwInputError(where(file, node, key + ".class"), "missing class name");
  m.class_name = node["class"].Scalar();
  const int kinds =
      int(bool(node["procedural"])) + int(bool(node["mesh"])) + int(bool(node["box"]));
  if (kinds != 1)
    throwInputError(where(file, node, key), "expected exactly one of procedural, mesh, box");
  if (node["procedural"]) {
    const std::string name = node["procedural"].as<std::string>();
    m.source = "procedural:" + name;
    try {
      m.mesh = models::makeProceduralModel(name);
    } catch (const InputError& e) {
      throwInputError(where(file, node["procedural"], key + ".procedural"), e.what());
    }
  } else if (node["mesh"]) {
    std::filesystem::path p = node["mesh"].as<std::string>();
    if (p.is_relative()) p = std::filesystem::path(base_dir) / p;
    m.source = "mesh:" + p.lexically_normal().string();
    m.mesh =
        models::loadMesh(p.lexically_normal().string(), where(file, node["mesh"], key + ".mesh"));
  } else {
    m.source = "box";
    parseBox(file, node["box"], key + ".box", m);
  }
  if (node["scale"]) {
    if (node["box"]) throwInputError(where(file, node["scale"], key + ".scale"), "not for a box");
    applyScale(file, node["scale"], key + ".scale", m.mesh);
  }
  if (node["azimuth_symmetry"]) {
    const double s = number(file, node["azimuth_symmetry"], key + ".azimuth_symmetry");
    if (s < 1 || s > 36 || s != std::floor(s))
      throwInputError(where(file, node["azimuth_symmetry"], key + ".azimuth_symmetry"),
                      "expected an integer in [1, 36]");
    m.azimuth_symmetry = int(s);
  }
  return m;
}

// ---------------------------------------------------------------------------------------------
// Views

struct ViewJob {
  int model_index = 0;
  float azimuth_deg = 0.f, elevation_deg = 0.f;
  Eigen::Vector3f dimensions_m = Eigen::Vector3f::Zero();
};

std::vector<float> azimuths(const TemplateViews& v, int symmetry) {
  std::vector<float> out;
  const float period = 360.f / float(symmetry);
  for (int i = 0;; ++i) {
    const float a = float(i) * v.azimuth_step_deg;
    if (a >= period - 1e-3f) break;
    out.push_back(a);
  }
  return out;
}

std::vector<float> elevations(const TemplateViews& v) {
  std::vector<float> out;
  const int n =
      int(std::floor((v.elevation_max_deg - v.elevation_min_deg) / v.elevation_step_deg + 1e-4f)) +
      1;
  for (int i = 0; i < n; ++i) out.push_back(v.elevation_min_deg + float(i) * v.elevation_step_deg);
  return out;
}

/// Box combinations, skipping those proportional to an earlier one (orthographic templates are
/// normalised in size, so they would render the same).
std::vector<Eigen::Vector3f> boxCombinations(const ModelSpec& m) {
  std::vector<Eigen::Vector3f> out;
  for (float x : m.box_values[0])
    for (float y : m.box_values[1])
      for (float z : m.box_values[2]) {
        const Eigen::Vector3f d(x, y, z);
        bool proportional = false;
        for (const auto& e : out)
          proportional = proportional || (d / d.x() - e / e.x()).cwiseAbs().maxCoeff() < 1e-4f;
        if (!proportional) out.push_back(d);
      }
  return out;
}

std::vector<ViewJob> viewJobs(const ModelsSpec& spec, int model_index) {
  const ModelSpec& m = spec.models[model_index];
  std::vector<Eigen::Vector3f> dims{Eigen::Vector3f::Zero()};
  if (m.source == "box") dims = boxCombinations(m);
  std::vector<ViewJob> jobs;
  for (const auto& d : dims)
    for (float e : elevations(spec.views))
      for (float a : azimuths(spec.views, m.azimuth_symmetry))
        jobs.push_back({model_index, a, e, d});
  return jobs;
}

// ---------------------------------------------------------------------------------------------
// Bank file

constexpr char kMagic[8] = {'R', 'A', 'S', 'M', 'Z', 'S', 'C', '1'};

template <typename T>
void put(std::ostream& os, const T& v) {
  os.write(reinterpret_cast<const char*>(&v), sizeof(T));
}
void putString(std::ostream& os, const std::string& s) {
  put(os, std::uint32_t(s.size()));
  os.write(s.data(), std::streamsize(s.size()));
}

struct Reader {
  std::istream& is;
  const std::string& path;
  template <typename T>
  T get() {
    T v{};
    is.read(reinterpret_cast<char*>(&v), sizeof(T));
    if (!is) throwInputError("template bank '" + path + "'", "truncated file");
    return v;
  }
  std::uint32_t count(std::uint32_t max, const char* what) {
    const auto n = get<std::uint32_t>();
    if (n > max) throwInputError("template bank '" + path + "'", std::string("corrupt ") + what);
    return n;
  }
  std::string string() {
    std::string s(count(1u << 16, "string"), '\0');
    is.read(s.data(), std::streamsize(s.size()));
    if (!is) throwInputError("template bank '" + path + "'", "truncated file");
    return s;
  }
};

}  // namespace

// ---------------------------------------------------------------------------------------------

ModelsSpec loadModelsSpec(const std::string& yaml_path) {
  if (!std::filesystem::is_regular_file(yaml_path))
    throwInputError("zero-shot models file '" + yaml_path + "'", "not found");
  YAML::Node root;
  try {
    root = YAML::LoadFile(yaml_path);
  } catch (const YAML::Exception& e) {
    throwInputError(yaml_path + ":" + std::to_string(e.mark.line + 1),
                    "YAML syntax error: " + e.msg);
  }
  ModelsSpec spec;
  spec.path = yaml_path;
  allowKeys(yaml_path, root, "<document>", {"views", "models"});
  if (root["views"]) spec.views = parseViews(yaml_path, root["views"]);
  const YAML::Node models = root["models"];
  if (!models || !models.IsSequence() || models.size() == 0)
    throwInputError(where(yaml_path, models ? models : root, "models"),
                    "expected a non-empty list of models");
  const std::string base = std::filesystem::path(yaml_path).parent_path().string();
  for (std::size_t i = 0; i < models.size(); ++i)
    spec.models.push_back(
        parseModel(yaml_path, base, models[i], "models[" + std::to_string(i) + "]"));
  return spec;
}

int TemplateBank::classIndex(const std::string& name) const {
  const auto it = std::find(class_names.begin(), class_names.end(), name);
  return it == class_names.end() ? -1 : int(it - class_names.begin());
}

std::size_t TemplateBank::templatesOfClass(int class_index) const {
  return std::size_t(std::count_if(templates.begin(), templates.end(), [&](const TemplateInfo& t) {
    return t.class_index == class_index;
  }));
}

float modelAzimuthPeriodDeg(const TemplateBank& bank, int model_index) {
  float max_azimuth = -1.f;
  for (const TemplateInfo& t : bank.templates)
    if (t.model_index == model_index) max_azimuth = std::max(max_azimuth, t.azimuth_deg);
  if (max_azimuth < 0.f) return 360.f;
  const float span = max_azimuth + bank.views.azimuth_step_deg;
  const int symmetry = std::max(1, int(std::lround(360.f / std::max(span, 1e-3f))));
  return 360.f / float(symmetry);
}

cv::Mat renderTemplateView(const models::TriangleMesh& mesh, float azimuth_deg, float elevation_deg,
                           int render_px, float* aspect) {
  const float az = azimuth_deg * kDegToRad, el = elevation_deg * kDegToRad;
  // Camera frame of the orthographic view: `toward` points from the object to the camera.
  const Eigen::Vector3f toward(std::cos(el) * std::cos(az), std::cos(el) * std::sin(az),
                               std::sin(el));
  const Eigen::Vector3f right = (-toward).cross(Eigen::Vector3f::UnitZ()).normalized();
  const Eigen::Vector3f up = right.cross(-toward);
  // Light fixed to the camera, from the upper left, so faces of different orientation differ.
  const Eigen::Vector3f light = (0.8f * toward + 0.45f * up - 0.35f * right).normalized();
  std::vector<Eigen::Vector3f> p(mesh.vertices.size());  // (x right px, y down px, depth)
  Eigen::AlignedBox2f bounds;
  for (const auto& t : mesh.triangles)
    for (int k = 0; k < 3; ++k) {
      const Eigen::Vector3f& v = mesh.vertices[t[k]];
      bounds.extend(Eigen::Vector2f(v.dot(right), -v.dot(up)));
    }
  const Eigen::Vector2f extent = bounds.sizes(), centre = bounds.center();
  const float scale =
      float(render_px) * kTemplateObjectPx / kTemplatePx / std::max(extent.maxCoeff(), 1e-9f);
  if (aspect) *aspect = extent.x() / std::max(extent.y(), 1e-9f);
  for (std::size_t i = 0; i < p.size(); ++i) {
    const Eigen::Vector3f& v = mesh.vertices[i];
    p[i] = {(v.dot(right) - centre.x()) * scale + 0.5f * render_px,
            (-v.dot(up) - centre.y()) * scale + 0.5f * render_px, v.dot(toward)};
  }
  cv::Mat image(render_px, render_px, CV_8UC1, cv::Scalar(0));
  cv::Mat depth(render_px, render_px, CV_32FC1, cv::Scalar(-std::numeric_limits<float>::max()));
  for (const auto& t : mesh.triangles) {
    const Eigen::Vector3f &a = p[t[0]], &b = p[t[1]], &c = p[t[2]];
    const float area = (b.x() - a.x()) * (c.y() - a.y()) - (b.y() - a.y()) * (c.x() - a.x());
    if (std::abs(area) < 1e-12f) continue;
    const Eigen::Vector3f n = (mesh.vertices[t[1]] - mesh.vertices[t[0]])
                                  .cross(mesh.vertices[t[2]] - mesh.vertices[t[0]])
                                  .normalized();
    const auto shade = std::uint8_t(std::lround(255.f * (0.3f + 0.7f * std::abs(n.dot(light)))));
    const int x0 = std::max(0, int(std::floor(std::min({a.x(), b.x(), c.x()}))));
    const int x1 = std::min(render_px - 1, int(std::ceil(std::max({a.x(), b.x(), c.x()}))));
    const int y0 = std::max(0, int(std::floor(std::min({a.y(), b.y(), c.y()}))));
    const int y1 = std::min(render_px - 1, int(std::ceil(std::max({a.y(), b.y(), c.y()}))));
    for (int y = y0; y <= y1; ++y)
      for (int x = x0; x <= x1; ++x) {
        const float px = float(x) + 0.5f, py = float(y) + 0.5f;
        // Barycentric weights of the pixel centre (edge functions over the signed area).
        const float wa = ((b.x() - px) * (c.y() - py) - (b.y() - py) * (c.x() - px)) / area;
        const float wb = ((c.x() - px) * (a.y() - py) - (c.y() - py) * (a.x() - px)) / area;
        const float wc = 1.f - wa - wb;
        if (wa < 0.f || wb < 0.f || wc < 0.f) continue;
        const float z = wa * a.z() + wb * b.z() + wc * c.z();
        float& zbuf = depth.at<float>(y, x);
        if (z <= zbuf) continue;
        zbuf = z;
        image.at<std::uint8_t>(y, x) = shade;
      }
  }
  return image;
}

int descriptorLength() {
  static const int n = int(
      cv::HOGDescriptor({kTemplatePx, kTemplatePx}, {8, 8}, {4, 4}, {4, 4}, 9).getDescriptorSize());
  return n;
}

void describePatch(const cv::Mat& patch, float* out) {
  CV_Assert(patch.rows == kTemplatePx && patch.cols == kTemplatePx && patch.depth() == CV_8U);
  // winSize 16, blockSize 8, blockStride 4, cellSize 4, 9 unsigned bins (TemplateBank.h).
  static const cv::HOGDescriptor hog({kTemplatePx, kTemplatePx}, {8, 8}, {4, 4}, {4, 4}, 9);
  std::vector<float> d;
  hog.compute(patch, d);
  double norm2 = 0.0;
  for (float v : d) norm2 += double(v) * v;
  const float inv = norm2 > 0.0 ? float(1.0 / std::sqrt(norm2)) : 0.f;
  for (std::size_t i = 0; i < d.size(); ++i) out[i] = d[i] * inv;
}

cv::Mat squareCropWithMargin(const cv::Mat& image, const cv::Rect& box) {
  const int side = std::max(1, int(std::lround(std::max(box.width, box.height) *
                                               double(kTemplatePx) / kTemplateObjectPx)));
  const cv::Rect square(box.x + box.width / 2 - side / 2, box.y + box.height / 2 - side / 2, side,
                        side);
  const cv::Rect inside = square & cv::Rect(0, 0, image.cols, image.rows);
  cv::Mat patch;
  if (inside == square) {
    cv::resize(image(square), patch, {kTemplatePx, kTemplatePx}, 0, 0, cv::INTER_AREA);
    return patch;
  }
  if (inside.empty()) return cv::Mat(kTemplatePx, kTemplatePx, image.type(), cv::Scalar::all(0));
  cv::Mat padded;
  cv::copyMakeBorder(image(inside), padded, inside.y - square.y, square.br().y - inside.br().y,
                     inside.x - square.x, square.br().x - inside.br().x, cv::BORDER_REPLICATE);
  cv::resize(padded, patch, {kTemplatePx, kTemplatePx}, 0, 0, cv::INTER_AREA);
  return patch;
}

TemplateBank trainTemplateBank(const ModelsSpec& spec, const TrainingProgress& progress) {
  TemplateBank bank;
  bank.views = spec.views;
  const int dim = descriptorLength();
  for (std::size_t mi = 0; mi < spec.models.size(); ++mi) {
    const ModelSpec& m = spec.models[mi];
    int cls = bank.classIndex(m.class_name);
    if (cls < 0) {
      cls = int(bank.class_names.size());
      bank.class_names.push_back(m.class_name);
    }
    bank.model_sources.push_back(m.source);
    const std::vector<ViewJob> jobs = viewJobs(spec, int(mi));
    cv::Mat rows(int(jobs.size()), dim, CV_32F);
    std::vector<TemplateInfo> infos(jobs.size());
    // One view per index: each writes its own row, so the result does not depend on threads.
    cv::parallel_for_(cv::Range(0, int(jobs.size())), [&](const cv::Range& r) {
      for (int j = r.start; j < r.end; ++j) {
        const ViewJob& job = jobs[j];
        const models::TriangleMesh box_mesh =
            m.source == "box" ? models::makeBox(job.dimensions_m) : models::TriangleMesh{};
        float aspect = 1.f;
        const cv::Mat view =
            renderTemplateView(m.source == "box" ? box_mesh : m.mesh, job.azimuth_deg,
                               job.elevation_deg, spec.views.render_px, &aspect);
        cv::Mat patch;
        cv::resize(view, patch, {kTemplatePx, kTemplatePx}, 0, 0, cv::INTER_AREA);
        describePatch(patch, rows.ptr<float>(j));
        infos[j] = {cls, int(mi), job.azimuth_deg, job.elevation_deg, job.dimensions_m, aspect};
      }
    });
    bank.templates.insert(bank.templates.end(), infos.begin(), infos.end());
    bank.descriptors.push_back(rows);
    if (progress) progress(mi + 1, spec.models.size(), bank.templates.size());
  }
  return bank;
}

void saveTemplateBank(const TemplateBank& bank, const std::string& path) {
  std::ostringstream os(std::ios::binary);
  os.write(kMagic, sizeof(kMagic));
  const TemplateViews& v = bank.views;
  put(os, v.azimuth_step_deg), put(os, v.elevation_min_deg), put(os, v.elevation_max_deg);
  put(os, v.elevation_step_deg), put(os, std::int32_t(v.render_px));
  put(os, std::uint32_t(bank.class_names.size()));
  for (const auto& s : bank.class_names) putString(os, s);
  put(os, std::uint32_t(bank.model_sources.size()));
  for (const auto& s : bank.model_sources) putString(os, s);
  put(os, std::uint32_t(bank.templates.size()));
  put(os, std::uint32_t(bank.descriptors.cols));
  for (const TemplateInfo& t : bank.templates) {
    put(os, std::int32_t(t.class_index)), put(os, std::int32_t(t.model_index));
    put(os, t.azimuth_deg), put(os, t.elevation_deg);
    for (int a = 0; a < 3; ++a) put(os, t.dimensions_m[a]);
    put(os, t.aspect);
  }
  for (int r = 0; r < bank.descriptors.rows; ++r)
    os.write(reinterpret_cast<const char*>(bank.descriptors.ptr<float>(r)),
             std::streamsize(sizeof(float) * bank.descriptors.cols));
  try {
    writeFileAtomic(path, os.str());
  } catch (const std::runtime_error& e) {
    throwInputError("template bank '" + path + "'", e.what());
  }
}

TemplateBank loadTemplateBank(const std::string& path) {
  std::ifstream is(path, std::ios::binary);
  if (!is) throwInputError("template bank '" + path + "'", "not found or unreadable");
  char magic[sizeof(kMagic)] = {};
  is.read(magic, sizeof(magic));
  if (!is || std::memcmp(magic, kMagic, sizeof(kMagic)) != 0)
    throwInputError("template bank '" + path + "'",
                    "not a rasm zero-shot template bank (written by `rasm zsc train`)");
  Reader in{is, path};
  TemplateBank bank;
  TemplateViews& v = bank.views;
  v.azimuth_step_deg = in.get<float>(), v.elevation_min_deg = in.get<float>();
  v.elevation_max_deg = in.get<float>(), v.elevation_step_deg = in.get<float>();
  v.render_px = in.get<std::int32_t>();
  bank.class_names.resize(in.count(1u << 16, "class count"));
  for (auto& s : bank.class_names) s = in.string();
  bank.model_sources.resize(in.count(1u << 16, "model count"));
  for (auto& s : bank.model_sources) s = in.string();
  bank.templates.resize(in.count(1u << 26, "template count"));
  const std::uint32_t dim = in.get<std::uint32_t>();
  if (dim != std::uint32_t(descriptorLength()))
    throwInputError("template bank '" + path + "'",
                    "descriptor length " + std::to_string(dim) + ", expected " +
                        std::to_string(descriptorLength()) + " (retrain it)");
  for (TemplateInfo& t : bank.templates) {
    t.class_index = in.get<std::int32_t>(), t.model_index = in.get<std::int32_t>();
    t.azimuth_deg = in.get<float>(), t.elevation_deg = in.get<float>();
    for (int a = 0; a < 3; ++a) t.dimensions_m[a] = in.get<float>();
    t.aspect = in.get<float>();
    if (t.class_index < 0 || t.class_index >= int(bank.class_names.size()))
      throwInputError("template bank '" + path + "'", "corrupt template class index");
  }
  bank.descriptors.create(int(bank.templates.size()), int(dim), CV_32F);
  is.read(reinterpret_cast<char*>(bank.descriptors.data),
          std::streamsize(bank.descriptors.total() * sizeof(float)));
  if (!is) throwInputError("template bank '" + path + "'", "truncated file");
  return bank;
}

}  // namespace rasm::classification
