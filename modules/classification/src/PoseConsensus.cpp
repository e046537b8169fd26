#include "rasm/classification/PoseConsensus.h"

#include <mrpt/core/bits_math.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>

namespace rasm::classification {

namespace {

/// Observations kept per (segment, class); the oldest go first (a long live run).
constexpr std::size_t kMaxObservationsPerKey = 128;
/// Held observations per (segment, class) that keep their surfels; older ones fall back to the
/// segment (a phantom held on a desk from every view would otherwise keep a copy per view).
constexpr std::size_t kMaxHeldSurfelLists = 8;

/// Columns x (right), y (down), z (forward) of a camera looking along `forward` whose up is
/// `up` seen from there (renderTemplateView's construction).
Eigen::Matrix3d lookFrame(const Eigen::Vector3d& forward, const Eigen::Vector3d& up) {
  const Eigen::Vector3d z = forward.normalized();
  const Eigen::Vector3d x = z.cross(up).normalized();
  Eigen::Matrix3d R;
  R.col(0) = x;
  R.col(1) = z.cross(x);
  R.col(2) = z;
  return R;
}

}  // namespace

Eigen::Matrix3d impliedModelRotation(const PoseHint& pose, const Eigen::Matrix3d& R_world_cam,
                                     const Eigen::Vector3d& ray_cam) {
  const double az = mrpt::DEG2RAD(double(pose.azimuth_deg)),
               el = mrpt::DEG2RAD(double(pose.elevation_deg));
  // The template camera in the model frame: at `toward` from the centre, up = model +z.
  const Eigen::Vector3d toward(std::cos(el) * std::cos(az), std::cos(el) * std::sin(az),
                               std::sin(el));
  const Eigen::Matrix3d R_model_tcam = lookFrame(-toward, Eigen::Vector3d::UnitZ());
  // The same camera in the real one's frame: looking along the ray, up = the camera's up.
  const Eigen::Matrix3d R_cam_tcam = lookFrame(ray_cam, -Eigen::Vector3d::UnitY());
  return R_world_cam * R_cam_tcam * R_model_tcam.transpose();
}

double orientationDisagreementDeg(const Eigen::Matrix3d& R_world_model_a,
                                  const Eigen::Matrix3d& R_world_model_b,
                                  double azimuth_period_deg) {
  const Eigen::Matrix3d D = R_world_model_a.transpose() * R_world_model_b;
  const int n = std::max(1, int(std::lround(360.0 / std::max(azimuth_period_deg, 1e-3))));
  double best = 180.0;
  for (int k = 0; k < n; ++k) {
    const Eigen::Matrix3d Dk =
        D * Eigen::AngleAxisd(-k * 2.0 * M_PI / n, Eigen::Vector3d::UnitZ()).toRotationMatrix();
    const double c = std::clamp((Dk.trace() - 1.0) / 2.0, -1.0, 1.0);
    best = std::min(best, mrpt::RAD2DEG(std::acos(c)));
  }
  return best;
}

PoseConsensus::PoseConsensus(double agreement_deg, double min_view_change_deg,
                             double max_fraction_of_view_change)
    : m_agreement_deg(agreement_deg),
      m_min_view_change_deg(min_view_change_deg),
      m_max_fraction_of_view_change(max_fraction_of_view_change) {}

bool PoseConsensus::agree(const PoseObservation& a, const PoseObservation& b) const {
  const double cos_view = std::clamp(a.sight_world.dot(b.sight_world), -1.0, 1.0);
  const double view_change_deg = mrpt::RAD2DEG(std::acos(cos_view));
  if (view_change_deg < m_min_view_change_deg) return false;
  const double period = std::max(a.azimuth_period_deg, b.azimuth_period_deg);
  const double apart_deg = orientationDisagreementDeg(a.R_world_model, b.R_world_model, period);
  return apart_deg <= m_agreement_deg &&
         apart_deg <= m_max_fraction_of_view_change * view_change_deg;
}

PoseConsensus::Released PoseConsensus::add(std::uint32_t segment, int class_id,
                                           PoseObservation observation) {
  Released out;
  auto& list = m_observations[{segment, class_id}];
  bool agreed = false;
  for (PoseObservation& earlier : list) {
    if (!agree(earlier, observation)) continue;
    agreed = true;
    if (!earlier.released) {
      earlier.released = true;
      out.earlier.push_back(
          {earlier.frame, std::move(earlier.evidence), std::move(earlier.surfels)});
      earlier.evidence.clear();
      earlier.surfels.clear();
    }
  }
  if (agreed) {
    observation.released = out.this_one = true;
    out.evidence = std::move(observation.evidence);
    observation.evidence.clear();
    observation.surfels.clear();  // only a held detection needs them
  }
  m_released += out.earlier.size() + (out.this_one ? 1 : 0);
  list.push_back(std::move(observation));
  if (list.size() > kMaxObservationsPerKey) list.erase(list.begin());
  std::size_t lists = 0;  // newest first: the oldest held ones give theirs up
  for (auto it = list.rbegin(); it != list.rend(); ++it)
    if (!it->surfels.empty() && ++lists > kMaxHeldSurfelLists) it->surfels = {};
  return out;
}

void PoseConsensus::relabel(const std::vector<std::uint32_t>& table) {
  std::map<std::pair<std::uint32_t, int>, std::vector<PoseObservation>> moved;
  for (auto& [key, list] : m_observations) {
    const std::uint32_t to = key.first < table.size() ? table[key.first] : key.first;
    if (to == 0) continue;
    auto& target = moved[{to, key.second}];
    for (PoseObservation& o : list) {
      for (SegmentEvidence& e : o.evidence) e.segment = to;
      target.push_back(std::move(o));
    }
  }
  for (auto& [key, list] : moved) {
    std::stable_sort(
        list.begin(), list.end(),
        [](const PoseObservation& a, const PoseObservation& b) { return a.frame < b.frame; });
    if (list.size() > kMaxObservationsPerKey)
      list.erase(list.begin(), list.end() - std::ptrdiff_t(kMaxObservationsPerKey));
  }
  m_observations = std::move(moved);
}

std::size_t PoseConsensus::heldDetections() const {
  std::size_t n = 0;
  for (const auto& [key, list] : m_observations)
    for (const PoseObservation& o : list) n += o.released ? 0 : 1;
  return n;
}

}  // namespace rasm::classification
