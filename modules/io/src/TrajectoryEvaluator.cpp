#include "rasm/io/TrajectoryEvaluator.h"

#include <Eigen/SVD>
#include <algorithm>
#include <cmath>
#include <limits>
#include <sstream>

#include "rasm/core/Error.h"
#include "rasm/io/TimestampAssociation.h"

namespace rasm::io {

ErrorStats ErrorStats::of(std::vector<double> v) {
  ErrorStats s;
  s.count = v.size();
  if (v.empty()) return s;
  double sum = 0, sum2 = 0;
  for (double x : v) sum += x, sum2 += x * x;
  const double n = double(v.size());
  s.mean = sum / n;
  s.rmse = std::sqrt(sum2 / n);
  double var = 0;
  for (double x : v) var += (x - s.mean) * (x - s.mean);
  s.std = std::sqrt(var / n);  // population std, as numpy.std in the TUM scripts
  std::sort(v.begin(), v.end());
  s.min = v.front();
  s.max = v.back();
  const std::size_t h = v.size() / 2;
  s.median = v.size() % 2 ? v[h] : 0.5 * (v[h - 1] + v[h]);
  return s;
}

void alignUmeyama(const std::vector<Eigen::Vector3d>& src, const std::vector<Eigen::Vector3d>& dst,
                  bool with_scale, Eigen::Matrix3d& R, Eigen::Vector3d& t, double& s) {
  if (src.size() != dst.size() || src.empty())
    throw std::invalid_argument("alignUmeyama: point sets must be non-empty and of equal size");
  const double n = double(src.size());
  Eigen::Vector3d mu_s = Eigen::Vector3d::Zero(), mu_d = Eigen::Vector3d::Zero();
  for (std::size_t i = 0; i < src.size(); ++i) mu_s += src[i], mu_d += dst[i];
  mu_s /= n;
  mu_d /= n;
  // Cross-covariance Sigma = 1/n sum (d - mu_d)(s - mu_s)^T and source variance (Umeyama eq.
  // 38-42).
  Eigen::Matrix3d Sigma = Eigen::Matrix3d::Zero();
  double var_s = 0;
  for (std::size_t i = 0; i < src.size(); ++i) {
    const Eigen::Vector3d a = src[i] - mu_s, b = dst[i] - mu_d;
    Sigma += b * a.transpose();
    var_s += a.squaredNorm();
  }
  Sigma /= n;
  var_s /= n;
  const Eigen::JacobiSVD<Eigen::Matrix3d> svd(Sigma, Eigen::ComputeFullU | Eigen::ComputeFullV);
  Eigen::Matrix3d S = Eigen::Matrix3d::Identity();
  if (svd.matrixU().determinant() * svd.matrixV().determinant() < 0) S(2, 2) = -1;  // no reflection
  R = svd.matrixU() * S * svd.matrixV().transpose();
  s = (with_scale && var_s > 0) ? (svd.singularValues().asDiagonal() * S).trace() / var_s : 1.0;
  t = mu_d - s * R * mu_s;
}

namespace {

std::vector<double> stampsOf(const Trajectory& tr) {
  std::vector<double> s;
  s.reserve(tr.size());
  for (const auto& p : tr) s.push_back(p.timestamp_s);
  return s;
}

Trajectory sortedByTime(Trajectory tr) {
  std::stable_sort(tr.begin(), tr.end(), [](const StampedPose& a, const StampedPose& b) {
    return a.timestamp_s < b.timestamp_s;
  });
  return tr;
}

std::string span(const Trajectory& tr) {
  std::ostringstream s;
  s.precision(6);
  s << std::fixed << tr.size() << " poses";
  if (!tr.empty()) s << ", t " << tr.front().timestamp_s << " .. " << tr.back().timestamp_s;
  return s.str();
}

double medianPeriod(const std::vector<double>& sorted) {
  std::vector<double> d;
  for (std::size_t i = 1; i < sorted.size(); ++i) d.push_back(sorted[i] - sorted[i - 1]);
  return d.empty() ? 0.0 : ErrorStats::of(d).median;
}

}  // namespace

AteResult TrajectoryEvaluator::computeAte(const Trajectory& ground_truth,
                                          const Trajectory& estimate, const AteOptions& opt) {
  if (!(std::isfinite(opt.max_dt_s) && opt.max_dt_s > 0))
    throwInputError("ATE max_dt_s " + std::to_string(opt.max_dt_s),
                    "expected a finite association tolerance > 0 s");
  if (!std::isfinite(opt.offset_s))
    throwInputError("ATE offset_s", "expected a finite time offset (s)");
  const auto pairs =
      associateTimestamps(stampsOf(ground_truth), stampsOf(estimate), opt.max_dt_s, opt.offset_s);
  const std::size_t need = opt.align ? 3 : 1;
  if (pairs.size() < need) {
    std::ostringstream s;
    s << "only " << pairs.size() << " pose pairs associate within " << opt.max_dt_s << " s (need "
      << need << "); ground truth: " << span(ground_truth) << "; estimate: " << span(estimate);
    throwInputError("ATE", s.str());
  }
  std::vector<Eigen::Vector3d> p_gt, p_est;
  AteResult r;
  for (const auto& [i, j] : pairs) {
    p_gt.push_back(ground_truth[i].T_world_cam.translation());
    p_est.push_back(estimate[j].T_world_cam.translation());
    r.gt_stamps.push_back(ground_truth[i].timestamp_s);
    r.est_stamps.push_back(estimate[j].timestamp_s);
  }
  Eigen::Matrix3d R = Eigen::Matrix3d::Identity();
  Eigen::Vector3d t = Eigen::Vector3d::Zero();
  double s = 1.0;
  if (opt.align) alignUmeyama(p_est, p_gt, opt.scale, R, t, s);
  r.T_gt_est.setIdentity();
  r.T_gt_est.linear() = R;
  r.T_gt_est.translation() = t;
  r.scale = s;
  for (std::size_t k = 0; k < p_gt.size(); ++k)
    r.errors_m.push_back((p_gt[k] - (s * R * p_est[k] + t)).norm());
  r.translation_m = ErrorStats::of(r.errors_m);
  return r;
}

bool WorldFrameError::startsAtGroundTruth(double max_position_m, double max_rotation_deg) const {
  return start_position_error_m <= max_position_m && start_rotation_error_deg <= max_rotation_deg;
}

WorldFrameError TrajectoryEvaluator::computeWorldFrameError(const Trajectory& ground_truth,
                                                            const Trajectory& estimate,
                                                            const WorldFrameOptions& opt) {
  if (!(std::isfinite(opt.max_dt_s) && opt.max_dt_s > 0))
    throwInputError("world-frame error max_dt_s " + std::to_string(opt.max_dt_s),
                    "expected a finite association tolerance > 0 s");
  if (!(opt.up_world.allFinite() && opt.up_world.norm() > 0))
    throwInputError("world-frame error up_world", "expected a finite non-zero direction");
  const auto pairs =
      associateTimestamps(stampsOf(ground_truth), stampsOf(estimate), opt.max_dt_s, 0.0);
  if (pairs.size() < 2) {
    std::ostringstream s;
    s << "only " << pairs.size() << " pose pairs associate within " << opt.max_dt_s
      << " s (need 2); ground truth: " << span(ground_truth) << "; estimate: " << span(estimate);
    throwInputError("world-frame error", s.str());
  }
  const Eigen::Vector3d up = opt.up_world.normalized();
  const auto first_est = std::min_element(
      estimate.begin(), estimate.end(),
      [](const StampedPose& a, const StampedPose& b) { return a.timestamp_s < b.timestamp_s; });
  const std::size_t first_j = std::size_t(first_est - estimate.begin());
  WorldFrameError r;
  r.start_position_error_m = r.start_rotation_error_deg = std::numeric_limits<double>::quiet_NaN();
  std::vector<double> position, vertical, horizontal, tilt, heading;
  for (const auto& [i, j] : pairs) {
    const Eigen::Isometry3d& T_gt = ground_truth[i].T_world_cam;
    const Eigen::Isometry3d& T_est = estimate[j].T_world_cam;
    const Eigen::Vector3d d = T_est.translation() - T_gt.translation();
    const double dz = d.dot(up);
    position.push_back(d.norm());
    vertical.push_back(std::abs(dz));
    horizontal.push_back((d - dz * up).norm());
    // The up direction in each camera's frame; their angle is the roll and pitch error.
    const Eigen::Vector3d up_est = T_est.linear().transpose() * up;
    const Eigen::Vector3d up_gt = T_gt.linear().transpose() * up;
    tilt.push_back(std::atan2(up_est.cross(up_gt).norm(), up_est.dot(up_gt)) * 180.0 / M_PI);
    // The twist about up of the world-frame rotation from the truth to the estimate (swing-twist
    // decomposition of its quaternion): the heading error, whatever the tilt.
    const Eigen::Quaterniond q(T_est.linear() * T_gt.linear().transpose());
    const double twist = 2.0 * std::atan2(q.vec().dot(up), q.w());
    heading.push_back(std::abs(std::remainder(twist, 2.0 * M_PI)) * 180.0 / M_PI);
    if (j == first_j) {
      r.start_position_error_m = d.norm();
      r.start_rotation_error_deg =
          Eigen::AngleAxisd(T_gt.linear().transpose() * T_est.linear()).angle() * 180.0 / M_PI;
    }
  }
  r.position_m = ErrorStats::of(std::move(position));
  r.vertical_m = ErrorStats::of(std::move(vertical));
  r.horizontal_m = ErrorStats::of(std::move(horizontal));
  r.tilt_deg = ErrorStats::of(std::move(tilt));
  r.heading_deg = ErrorStats::of(std::move(heading));
  return r;
}

RpeResult TrajectoryEvaluator::computeRpe(const Trajectory& ground_truth_in,
                                          const Trajectory& estimate_in, const RpeOptions& opt) {
  if (!(std::isfinite(opt.delta) && opt.delta > 0))
    throwInputError("RPE", "delta must be a finite value > 0");
  if (!std::isfinite(opt.offset_s)) throwInputError("RPE offset_s", "expected a finite offset (s)");
  const Trajectory gt = sortedByTime(ground_truth_in), est = sortedByTime(estimate_in);
  if (gt.size() < 2 || est.size() < 2)
    throwInputError("RPE", "needs >= 2 poses in each trajectory; ground truth: " + span(gt) +
                               "; estimate: " + span(est));
  const std::vector<double> ts_gt = stampsOf(gt), ts_est = stampsOf(est);
  // Ground-truth lookups as evaluate_rpe.py: the nearest stamp, within twice the median period.
  const double gt_max_dt = 2.0 * medianPeriod(ts_gt);
  // Interval end: the estimate pose nearest to t_i + delta, within half a median estimate period
  // (so that intervals near the end or across gaps are not silently shortened).
  const double est_tol = 0.5 * medianPeriod(ts_est) + 1e-6;
  const long frames = std::lround(opt.delta);

  std::vector<double> et, er;
  for (std::size_t i = 0; i < est.size(); ++i) {
    std::size_t j;
    if (opt.delta_in_frames) {
      j = i + std::size_t(std::max(1L, frames));
      if (j >= est.size()) break;
    } else {
      const double target = ts_est[i] + opt.delta;
      j = closestIndex(ts_est, target);
      if (j <= i || std::abs(ts_est[j] - target) > est_tol) continue;
    }
    const std::size_t g0 = closestIndex(ts_gt, ts_est[i] + opt.offset_s);
    const std::size_t g1 = closestIndex(ts_gt, ts_est[j] + opt.offset_s);
    if (std::abs(ts_gt[g0] - (ts_est[i] + opt.offset_s)) > gt_max_dt ||
        std::abs(ts_gt[g1] - (ts_est[j] + opt.offset_s)) > gt_max_dt)
      continue;
    // E_ij = (Q_i^-1 Q_j)^-1 (P_i^-1 P_j), Sturm et al. 2012 eq. (1).
    const Eigen::Isometry3d dQ = gt[g0].T_world_cam.inverse() * gt[g1].T_world_cam;
    const Eigen::Isometry3d dP = est[i].T_world_cam.inverse() * est[j].T_world_cam;
    const Eigen::Isometry3d E = dQ.inverse() * dP;
    et.push_back(E.translation().norm());
    er.push_back(Eigen::AngleAxisd(E.linear()).angle() * 180.0 / M_PI);
  }
  if (et.empty()) {
    std::ostringstream s;
    s << "no pose interval of " << opt.delta << (opt.delta_in_frames ? " frames" : " s")
      << " has ground truth; ground truth: " << span(gt) << "; estimate: " << span(est);
    throwInputError("RPE", s.str());
  }
  RpeResult r;
  r.pairs = et.size();
  r.translation_m = ErrorStats::of(et);
  r.rotation_deg = ErrorStats::of(er);
  return r;
}

}  // namespace rasm::io
