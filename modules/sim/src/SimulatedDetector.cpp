#include "rasm/sim/SimulatedDetector.h"

#include <mrpt/config/CConfigFileBase.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <random>
#include <sstream>

#include "ParamsWrite.h"
#include "rasm/core/Error.h"
#include "rasm/core/Params.h"
#include "rasm/models/ClassVocabulary.h"

namespace rasm::sim {

// ---- params -------------------------------------------------------------------------------------

std::vector<int> TDetectorParams::detectableClassIds() const {
  std::vector<int> ids;
  if (detectable_classes == "coco") {
    for (int i = 1; i <= models::kNumCocoClasses; ++i) ids.push_back(i);
  } else if (detectable_classes == "all") {
    for (int i = 1; i < models::numClasses(); ++i)
      if (!models::isStructureClass(i)) ids.push_back(i);
  } else {
    std::stringstream ss(detectable_classes);
    for (std::string name; std::getline(ss, name, ',');) {
      name.erase(0, name.find_first_not_of(' '));
      name.erase(name.find_last_not_of(' ') + 1);
      const int id = models::classIdFromName(name);
      if (id <= 0)
        throwInputError("[sim_detector] detectable_classes", "unknown class '" + name + "'");
      ids.push_back(id);
    }
  }
  if (ids.empty()) throwInputError("[sim_detector] detectable_classes", "no classes given");
  return ids;
}

void TDetectorParams::loadFromConfigFile(const mrpt::config::CConfigFileBase& c,
                                         const std::string& s) {
  MRPT_LOAD_CONFIG_VAR_CS(detectable_classes, string);
  MRPT_LOAD_CONFIG_VAR_CS(p_max, double);
  MRPT_LOAD_CONFIG_VAR_CS(size50_px, double);
  MRPT_LOAD_CONFIG_VAR_CS(size_scale_px, double);
  MRPT_LOAD_CONFIG_VAR_CS(min_visible_fraction, double);
  MRPT_LOAD_CONFIG_VAR_CS(occlusion_exponent, double);
  MRPT_LOAD_CONFIG_VAR_CS(box_jitter, double);
  MRPT_LOAD_CONFIG_VAR_CS(confusion_rate, double);
  MRPT_LOAD_CONFIG_VAR_CS(false_positives_per_frame, double);
  MRPT_LOAD_CONFIG_VAR_CS(score_noise, double);
  MRPT_LOAD_CONFIG_VAR_CS(min_mask_pixels, int);
  MRPT_LOAD_CONFIG_VAR_CS(occlusion_aware, bool);
  validate(s);
}

void TDetectorParams::saveToConfigFile(mrpt::config::CConfigFileBase& c,
                                       const std::string& s) const {
  RASM_SIM_SAVE(detectable_classes, "coco | all | comma-separated class names");
  RASM_SIM_SAVE(p_max, "detection probability of a large, fully visible object");
  RASM_SIM_SAVE(size50_px, "sqrt(mask area) at which the size factor is 1/2 (px)");
  RASM_SIM_SAVE(size_scale_px, "width of the logistic size factor (px)");
  RASM_SIM_SAVE(min_visible_fraction, "objects less visible than this are never detected");
  RASM_SIM_SAVE(occlusion_exponent, "visibility factor exponent");
  RASM_SIM_SAVE(box_jitter, "box edge noise std as a fraction of the box size");
  RASM_SIM_SAVE(confusion_rate, "probability of a wrong class");
  RASM_SIM_SAVE(false_positives_per_frame, "Poisson mean of false positives per frame");
  RASM_SIM_SAVE(score_noise, "score noise std");
  RASM_SIM_SAVE(min_mask_pixels, "smaller visible masks are never detected");
  RASM_SIM_SAVE(occlusion_aware, "visible fraction by ray casting (needs the scene)");
}

void TDetectorParams::validate(const std::string& s) const {
  (void)detectableClassIds();
  requireInRange(p_max, 0.0, 1.0, s, "p_max");
  requireInRange(size50_px, 0.0, 1e4, s, "size50_px");
  requireInRange(size_scale_px, 1e-3, 1e4, s, "size_scale_px");
  requireInRange(min_visible_fraction, 0.0, 0.999, s, "min_visible_fraction");
  requireInRange(occlusion_exponent, 0.0, 100.0, s, "occlusion_exponent");
  requireInRange(box_jitter, 0.0, 1.0, s, "box_jitter");
  requireInRange(confusion_rate, 0.0, 1.0, s, "confusion_rate");
  requireInRange(false_positives_per_frame, 0.0, 100.0, s, "false_positives_per_frame");
  requireInRange(score_noise, 0.0, 1.0, s, "score_noise");
  requireInRange(min_mask_pixels, 1, 1e9, s, "min_mask_pixels");
}

// ---- detector -----------------------------------------------------------------------------------

namespace {

/// Seeded draws from raw engine bits (the same sequence with every standard library).
struct Draw {
  std::mt19937_64 eng;
  double uniform() { return double(eng() >> 11) * (1.0 / 9007199254740992.0); }
  double gaussian() {
    const double u1 = (double(eng() >> 11) + 1.0) * (1.0 / 9007199254740992.0);
    return std::sqrt(-2.0 * std::log(u1)) * std::cos(2.0 * M_PI * uniform());
  }
  int poisson(double lambda) {  // Knuth; lambda is small
    const double L = std::exp(-lambda);
    int k = 0;
    for (double p = uniform(); p > L && k < 1000; p *= uniform()) ++k;
    return k;
  }
  template <typename T>
  const T& pick(const std::vector<T>& v) {
    return v[std::min(v.size() - 1, std::size_t(uniform() * double(v.size())))];
  }
};

struct MaskStats {
  int pixels = 0;
  int x0 = 1 << 30, y0 = 1 << 30, x1 = -1, y1 = -1;
  int class_id = 0;
};

/// Classes a detector plausibly mistakes each class for (by name; filtered by detectability).
const std::map<std::string, std::vector<std::string>>& confusions() {
  static const std::map<std::string, std::vector<std::string>> m = {
      {"cup", {"bottle", "vase", "bowl"}},
      {"bottle", {"cup", "vase"}},
      {"tv", {"laptop", "microwave"}},
      {"laptop", {"tv", "keyboard"}},
      {"keyboard", {"laptop", "remote"}},
      {"mouse", {"remote", "cell phone"}},
      {"chair", {"couch", "bench"}},
      {"dining table", {"bench", "bed"}},
      {"book", {"cell phone", "remote"}},
      {"clock", {"vase", "bowl"}},
      {"conference_phone", {"cell phone", "remote", "mouse"}},
      {"headphones", {"mouse", "backpack"}}};
  return m;
}

cv::Rect2f jitteredBox(const MaskStats& m, double jitter, Draw& d, int w, int h) {
  const double bw = m.x1 - m.x0 + 1, bh = m.y1 - m.y0 + 1;
  double x0 = m.x0 + jitter * bw * d.gaussian(), x1 = m.x1 + 1 + jitter * bw * d.gaussian();
  double y0 = m.y0 + jitter * bh * d.gaussian(), y1 = m.y1 + 1 + jitter * bh * d.gaussian();
  x0 = std::clamp(x0, 0.0, double(w - 1));
  y0 = std::clamp(y0, 0.0, double(h - 1));
  x1 = std::clamp(x1, x0 + 1.0, double(w));
  y1 = std::clamp(y1, y0 + 1.0, double(h));
  return cv::Rect2f(float(x0), float(y0), float(x1 - x0), float(y1 - y0));
}

/// Mask statistics (pixels, box, class) of every instance of the frame's ground-truth labels.
std::map<int, MaskStats> instanceMasks(const RgbdFrame& f) {
  const int w = f.gt_instance.width(), h = f.gt_instance.height();
  // Mask statistics per instance in one pass (a slot table instead of a map lookup per pixel),
  // then ordered by instance id: a deterministic draw order.
  std::vector<std::int32_t> slot(65536, -1);
  std::vector<std::pair<int, MaskStats>> found;
  for (int y = 0; y < h; ++y) {
    const std::uint16_t* ir = f.gt_instance.row(y);
    const std::uint16_t* cr = f.gt_class.row(y);
    for (int x = 0; x < w; ++x) {
      if (!ir[x]) continue;
      std::int32_t& k = slot[ir[x]];
      if (k < 0) {
        k = std::int32_t(found.size());
        found.push_back({ir[x], MaskStats{}});
      }
      MaskStats& m = found[std::size_t(k)].second;
      ++m.pixels;
      m.x0 = std::min(m.x0, x), m.x1 = std::max(m.x1, x), m.y0 = std::min(m.y0, y),
      m.y1 = std::max(m.y1, y);
      m.class_id = cr[x];
    }
  }
  std::sort(found.begin(), found.end(),
            [](const auto& a, const auto& b) { return a.first < b.first; });
  return std::map<int, MaskStats>(found.begin(), found.end());
}

}  // namespace

SimulatedDetector::SimulatedDetector(const TDetectorParams& params, const RayScene* scene)
    : m_params(params), m_scene(scene), m_detectable(std::size_t(models::numClasses()), 0) {
  m_params.validate();
  for (int id : m_params.detectableClassIds()) m_detectable[std::size_t(id)] = 1;
}

float SimulatedDetector::visibleFraction(const RgbdFrame& f, int instance_id,
                                         int mask_pixels) const {
  if (!m_scene || !m_params.occlusion_aware || !f.gt_T_world_cam) return 1.f;
  const int obj = m_scene->world().indexOfInstance(std::uint16_t(instance_id));
  if (obj < 0) return 1.f;
  const Eigen::Isometry3d& T = *f.gt_T_world_cam;
  const Eigen::Isometry3d T_cam_world = T.inverse();
  const CameraIntrinsics& K = f.intrinsics;
  // Region of the image plane the object can cover: its projected world box, within an extended
  // canvas (parts outside the image count as not visible, like truncation for a real detector).
  const double W = K.width, H = K.height;
  double u0 = -0.5 * W, u1 = 1.5 * W, v0 = -0.5 * H, v1 = 1.5 * H;
  const Eigen::AlignedBox3f& b = m_scene->objectBounds(obj);
  bool behind = false;
  double pu0 = 1e30, pu1 = -1e30, pv0 = 1e30, pv1 = -1e30;
  for (int c = 0; c < 8; ++c) {
    const Eigen::Vector3d p =
        T_cam_world * b.corner(Eigen::AlignedBox3f::CornerType(c)).cast<double>();
    if (p.z() < 0.05) {
      behind = true;
      break;
    }
    const double u = K.fx * p.x() / p.z() + K.cx, v = K.fy * p.y() / p.z() + K.cy;
    pu0 = std::min(pu0, u), pu1 = std::max(pu1, u), pv0 = std::min(pv0, v), pv1 = std::max(pv1, v);
  }
  if (!behind) {
    u0 = std::max(u0, std::floor(pu0)), u1 = std::min(u1, std::ceil(pu1));
    v0 = std::max(v0, std::floor(pv0)), v1 = std::min(v1, std::ceil(pv1));
  }
  if (u1 < u0 || v1 < v0) return 1.f;
  // At most ~4096 rays: a stride s samples every s-th pixel, each hit counting s^2 pixels.
  const double area = (u1 - u0 + 1) * (v1 - v0 + 1);
  const int s = std::max(1, int(std::ceil(std::sqrt(area / 4096.0))));
  const Eigen::Matrix3f R = T.linear().cast<float>();
  const Eigen::Vector3f o = T.translation().cast<float>();
  long long hits = 0;
  for (int v = int(v0); v <= int(v1); v += s)
    for (int u = int(u0); u <= int(u1); u += s) {
      const Eigen::Vector3f d =
          R * Eigen::Vector3f(float((u - K.cx) / K.fx), float((v - K.cy) / K.fy), 1.f);
      if (m_scene->castRayAlone(obj, o, d).hit) ++hits;
    }
  const double full = double(hits) * s * s;
  if (full <= 0) return 1.f;
  return float(std::min(1.0, mask_pixels / full));
}

std::vector<Detection> SimulatedDetector::detect(const RgbdFrame& f, std::uint64_t seed) const {
  std::vector<Detection> out;
  if (f.gt_instance.empty() || f.gt_class.empty())
    throwInputError("SimulatedDetector", "frame has no ground-truth labels");
  const int w = f.gt_instance.width(), h = f.gt_instance.height();
  const std::map<int, MaskStats> masks = instanceMasks(f);
  std::seed_seq seq{std::uint32_t(seed), std::uint32_t(seed >> 32), std::uint32_t(f.index),
                    std::uint32_t(std::uint64_t(f.index) >> 32), 0xDE7Eu};
  Draw d{std::mt19937_64(seq)};
  const std::vector<int> detectable = m_params.detectableClassIds();
  const TDetectorParams& P = m_params;

  std::vector<int> clutter;  // visible unlabelled objects: where false positives like to land
  for (const auto& [id, m] : masks) {
    if (m.class_id == 0 && m.pixels >= P.min_mask_pixels) clutter.push_back(id);
    if (m.class_id == 0 || !m_detectable[std::size_t(m.class_id)] || m.pixels < P.min_mask_pixels)
      continue;
    const float vis = visibleFraction(f, id, m.pixels);
    const double size_f =
        1.0 / (1.0 + std::exp(-(std::sqrt(double(m.pixels)) - P.size50_px) / P.size_scale_px));
    const double vis_f = std::pow(
        std::clamp((vis - P.min_visible_fraction) / (1.0 - P.min_visible_fraction), 0.0, 1.0),
        P.occlusion_exponent);
    const double p = P.p_max * size_f * vis_f;
    // Draw every variate whether or not it is used, so one object's outcome does not shift the
    // random stream of the next.
    const double u_det = d.uniform(), u_conf = d.uniform(), u_pick = d.uniform(),
                 g_score = d.gaussian();
    const cv::Rect2f box = jitteredBox(m, P.box_jitter, d, w, h);
    if (u_det >= p) continue;
    Detection det;
    det.box = box;
    det.gt_instance = id;
    det.visible_fraction = vis;
    det.class_id = m.class_id;
    double score = 0.25 + 0.7 * p + P.score_noise * g_score;
    if (u_conf < P.confusion_rate) {
      std::vector<int> similar;
      const auto it = confusions().find(models::className(m.class_id));
      if (it != confusions().end())
        for (const auto& n : it->second) {
          const int cid = models::classIdFromName(n);
          if (cid > 0 && m_detectable[std::size_t(cid)]) similar.push_back(cid);
        }
      const std::vector<int>& pool = similar.empty() ? detectable : similar;
      int cid = pool[std::min(pool.size() - 1, std::size_t(u_pick * double(pool.size())))];
      if (cid == m.class_id) cid = detectable[(std::size_t(u_pick * 7919) + 1) % detectable.size()];
      det.class_id = cid;
      det.confused = cid != m.class_id;
      score *= 0.7;
    }
    det.class_name = models::className(det.class_id);
    det.score = float(std::clamp(score, 0.01, 1.0));
    out.push_back(det);
  }

  const int n_fp = d.poisson(P.false_positives_per_frame);
  for (int k = 0; k < n_fp; ++k) {
    Detection fp;
    if (!clutter.empty() && d.uniform() < 0.5) {
      fp.box = jitteredBox(masks.at(d.pick(clutter)), 2.0 * P.box_jitter, d, w, h);
    } else {
      const double side =
          std::exp(std::log(20.0) + d.uniform() * (std::log(200.0) - std::log(20.0)));
      const double aspect = std::exp((d.uniform() - 0.5) * std::log(4.0));
      const double bw = std::min(double(w), side * std::sqrt(aspect)),
                   bh = std::min(double(h), side / std::sqrt(aspect));
      fp.box = cv::Rect2f(float(d.uniform() * (w - bw)), float(d.uniform() * (h - bh)), float(bw),
                          float(bh));
    }
    fp.class_id = d.pick(detectable);
    fp.class_name = models::className(fp.class_id);
    fp.score =
        float(std::clamp(0.05 + 0.4 * d.uniform() + P.score_noise * d.gaussian(), 0.01, 1.0));
    fp.visible_fraction = 0.f;
    out.push_back(fp);
  }
  return out;
}

}  // namespace rasm::sim
