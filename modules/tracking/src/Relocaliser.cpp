#include "rasm/tracking/Relocaliser.h"
#include "rasm/core/Angles.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>
#include <numeric>
#include <opencv2/calib3d.hpp>
#include <opencv2/core.hpp>
#include <opencv2/features2d.hpp>
#include <opencv2/imgproc.hpp>
#include <utility>

#include "rasm/core/SE3.h"

namespace rasm::tracking {

using maps::Keyframe;

namespace {

constexpr int kDescBytes = Keyframe::kDescriptorBytes;

/// Hamming distance of two 32-byte ORB descriptors.
inline int hamming32(const std::uint8_t* a, const std::uint8_t* b) {
  int d = 0;
  for (int w = 0; w < kDescBytes / 8; ++w) {
    std::uint64_t x, y;
    std::memcpy(&x, a + 8 * w, 8);
    std::memcpy(&y, b + 8 * w, 8);
    d += __builtin_popcountll(x ^ y);
  }
  return d;
}

/// Brute-force matches of `query` descriptors (rows of `query_desc` listed in `query_rows`)
/// against the `n_train` descriptors at `train`: Lowe's ratio test (best < ratio * second best)
/// and an absolute limit; each train descriptor keeps only its best query. Returns (query row,
/// train index) pairs.
std::vector<std::pair<int, int>> matchDescriptors(const cv::Mat& query_desc,
                                                  const std::vector<int>& query_rows,
                                                  const std::uint8_t* train, int n_train,
                                                  double ratio, int max_distance) {
  std::vector<std::pair<int, int>> out;
  if (n_train < 2) return out;
  std::vector<int> best_q(std::size_t(n_train), -1),
      best_d(std::size_t(n_train), std::numeric_limits<int>::max());
  for (int q : query_rows) {
    const std::uint8_t* d = query_desc.ptr<std::uint8_t>(q);
    int b1 = std::numeric_limits<int>::max(), b2 = b1, i1 = -1;
    for (int t = 0; t < n_train; ++t) {
      const int h = hamming32(d, train + std::size_t(kDescBytes) * t);
      if (h < b1) {
        b2 = b1;
        b1 = h;
        i1 = t;
      } else if (h < b2) {
        b2 = h;
      }
    }
    if (i1 < 0 || b1 > max_distance || double(b1) >= ratio * double(b2)) continue;
    if (b1 < best_d[i1]) {
      best_d[i1] = b1;
      best_q[i1] = q;
    }
  }
  for (int t = 0; t < n_train; ++t)
    if (best_q[t] >= 0) out.emplace_back(best_q[t], t);
  return out;
}

/// Depth (m) at the pixel nearest (u, v) when it and its 3x3 neighbourhood are valid, within
/// [min, max] and span at most step_ratio * depth; else 0 (no measurement or a depth edge).
float depthAt(const Image<float>& depth, float u, float v, const TRelocalisationParams& P) {
  const int x = int(std::lround(u)), y = int(std::lround(v));
  if (x < 1 || y < 1 || x >= depth.width() - 1 || y >= depth.height() - 1) return 0.0f;
  const float z = depth(x, y);
  if (!(z >= P.min_depth_m && z <= P.max_depth_m)) return 0.0f;
  float lo = z, hi = z;
  for (int dy = -1; dy <= 1; ++dy)
    for (int dx = -1; dx <= 1; ++dx) {
      const float n = depth(x + dx, y + dy);
      if (n <= 0.0f) return 0.0f;
      lo = std::min(lo, n);
      hi = std::max(hi, n);
    }
  return (hi - lo) <= P.max_depth_step_ratio * z ? z : 0.0f;
}

Eigen::Vector3d backProject(const CameraIntrinsics& K, float u, float v, float z) {
  return Eigen::Vector3d((u - K.cx) / K.fx * z, (v - K.cy) / K.fy * z, z);
}

/// Spacing metric of two keyframe poses: max(translation / keyframe_translation_m, rotation /
/// keyframe_rotation_deg). Below 1 = "near" (within both limits); a zero limit never is near.
double spacing(const Eigen::Isometry3d& a, const Eigen::Isometry3d& b,
               const TRelocalisationParams& P) {
  const double inf = std::numeric_limits<double>::infinity();
  const double t =
      P.keyframe_translation_m > 0 ? translationDistance(a, b) / P.keyframe_translation_m : inf;
  const double r = P.keyframe_rotation_deg > 0
                       ? rotationAngle(a, b) / (P.keyframe_rotation_deg * kRadPerDeg)
                       : inf;
  return std::max(t, r);
}

double elapsedMs(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
}

}  // namespace

struct Relocaliser::Impl {
  cv::Ptr<cv::ORB> orb;
  cv::Mat grey;
  cv::Mat grey_enlarged, mask_enlarged;

  /// ORB keypoints and descriptors of `grey` (where `mask` is non-zero, if given), detected on
  /// the image enlarged by the smallest integer factor that makes it min_width wide; keypoint
  /// positions and sizes are given back at grey's resolution.
  void detect(const cv::Mat& mask, int min_width, std::vector<cv::KeyPoint>& kps, cv::Mat& desc) {
    const int factor = min_width > grey.cols ? (min_width + grey.cols - 1) / grey.cols : 1;
    if (factor == 1) {
      orb->detectAndCompute(grey, mask.empty() ? cv::noArray() : cv::InputArray(mask), kps, desc);
      return;
    }
    cv::resize(grey, grey_enlarged, cv::Size(), factor, factor, cv::INTER_LINEAR);
    if (!mask.empty())
      cv::resize(mask, mask_enlarged, cv::Size(), factor, factor, cv::INTER_NEAREST);
    orb->detectAndCompute(grey_enlarged,
                          mask.empty() ? cv::noArray() : cv::InputArray(mask_enlarged), kps, desc);
    // Pixel centres: x_enlarged = factor * (x + 0.5) - 0.5.
    const float f = float(factor);
    for (cv::KeyPoint& k : kps) {
      k.pt = cv::Point2f((k.pt.x + 0.5f) / f - 0.5f, (k.pt.y + 0.5f) / f - 0.5f);
      k.size /= f;
    }
  }

  /// Grey image of the frame's colour (false when it has none of the depth's size).
  bool toGrey(const RgbdFrame& f) {
    if (f.colour.empty() || !f.colour.sameSize(f.depth_m)) return false;
    const cv::Mat bgr(f.colour.height(), f.colour.width(), CV_8UC3,
                      const_cast<Bgr8*>(f.colour.data()), f.colour.pitchBytes());
    cv::cvtColor(bgr, grey, cv::COLOR_BGR2GRAY);
    return true;
  }
};

Relocaliser::Relocaliser(const TRelocalisationParams& params) : m_params(params), m_impl(new Impl) {
  m_params.validate();
  m_impl->orb =
      cv::ORB::create(m_params.orb_features, float(m_params.orb_scale_factor), m_params.orb_levels,
                      31, 0, 2, cv::ORB::HARRIS_SCORE, 31, m_params.orb_fast_threshold);
}

Relocaliser::~Relocaliser() = default;
Relocaliser::Relocaliser(Relocaliser&&) noexcept = default;
Relocaliser& Relocaliser::operator=(Relocaliser&&) noexcept = default;

// ---- keyframes ----

bool Relocaliser::needsKeyframe(const Eigen::Isometry3d& T_world_cam, std::size_t frame_index,
                                const std::vector<Keyframe>& db) const {
  if (m_last_attempt && frame_index >= *m_last_attempt &&
      frame_index - *m_last_attempt < std::size_t(m_params.keyframe_min_interval_frames))
    return false;
  for (const Keyframe& kf : db)
    if (spacing(kf.T_world_cam, T_world_cam, m_params) < 1.0) return false;
  return true;
}

std::optional<Keyframe> Relocaliser::makeKeyframe(const RgbdFrame& frame,
                                                  const Eigen::Isometry3d& T_world_cam) const {
  const TRelocalisationParams& P = m_params;
  if (!m_impl->toGrey(frame)) return std::nullopt;
  // Detect only where depth is valid: a keyframe feature without a 3-D point is useless.
  cv::Mat mask(frame.height(), frame.width(), CV_8U);
  for (int y = 0; y < frame.height(); ++y) {
    const float* d = frame.depth_m.row(y);
    std::uint8_t* m = mask.ptr<std::uint8_t>(y);
    for (int x = 0; x < frame.width(); ++x)
      m[x] = (d[x] >= P.min_depth_m && d[x] <= P.max_depth_m) ? 255 : 0;
  }
  std::vector<cv::KeyPoint> kps;
  cv::Mat desc;
  m_impl->detect(mask, P.orb_min_image_width, kps, desc);

  std::vector<int> order(kps.size());
  std::iota(order.begin(), order.end(), 0);
  std::stable_sort(order.begin(), order.end(),
                   [&](int a, int b) { return kps[a].response > kps[b].response; });

  Keyframe kf;
  kf.frame_index = frame.index;
  kf.timestamp_s = frame.timestamp_s;
  kf.T_world_cam = T_world_cam;
  kf.intrinsics = frame.intrinsics;
  for (int i : order) {
    if (int(kf.numFeatures()) >= P.keyframe_max_features) break;
    const cv::Point2f& pt = kps[i].pt;
    const float z = depthAt(frame.depth_m, pt.x, pt.y, P);
    if (z <= 0.0f) continue;
    kf.points_world.push_back(
        (T_world_cam * backProject(frame.intrinsics, pt.x, pt.y, z)).cast<float>());
    kf.keypoints_px.emplace_back(pt.x, pt.y);
    const std::uint8_t* d = desc.ptr<std::uint8_t>(i);
    kf.descriptors.insert(kf.descriptors.end(), d, d + kDescBytes);
  }
  if (int(kf.numFeatures()) < P.keyframe_min_features) return std::nullopt;

  if (P.thumbnail_width > 0) {
    kf.thumb_width = std::min(P.thumbnail_width, frame.width());
    kf.thumb_height =
        std::max(1, int(std::lround(double(frame.height()) * kf.thumb_width / frame.width())));
    kf.thumbnail.resize(std::size_t(kf.thumb_width) * std::size_t(kf.thumb_height));
    cv::Mat thumb(kf.thumb_height, kf.thumb_width, CV_8U, kf.thumbnail.data());
    cv::resize(m_impl->grey, thumb, thumb.size(), 0, 0, cv::INTER_AREA);
  }
  return kf;
}

bool Relocaliser::maybeAddKeyframe(const RgbdFrame& frame, const Eigen::Isometry3d& T_world_cam,
                                   std::vector<Keyframe>& db) {
  if (!needsKeyframe(T_world_cam, frame.index, db)) return false;
  m_last_attempt = frame.index;
  std::optional<Keyframe> kf = makeKeyframe(frame, T_world_cam);
  if (!kf) return false;
  if (int(db.size()) < m_params.max_keyframes) {
    db.push_back(std::move(*kf));
    return true;
  }
  // Full: replace the keyframe nearest to another keyframe, if it is more redundant than the
  // new one would be (the new one's nearest keyframe is at spacing >= 1 by needsKeyframe).
  double new_nearest = std::numeric_limits<double>::infinity();
  for (const Keyframe& k : db)
    new_nearest = std::min(new_nearest, spacing(k.T_world_cam, T_world_cam, m_params));
  std::size_t victim = db.size();
  double victim_nearest = new_nearest;
  for (std::size_t i = 0; i < db.size(); ++i) {
    double nearest = std::numeric_limits<double>::infinity();
    for (std::size_t j = 0; j < db.size(); ++j)
      if (j != i)
        nearest = std::min(nearest, spacing(db[i].T_world_cam, db[j].T_world_cam, m_params));
    if (nearest < victim_nearest) {
      victim_nearest = nearest;
      victim = i;
    }
  }
  if (victim == db.size()) return false;
  db[victim] = std::move(*kf);
  return true;
}

// ---- relocalisation ----

namespace {

/// One frame keypoint (query row q, pixel uv) matched to a keyframe world point.
struct Correspondence {
  int q;
  cv::Point2f uv;
  Eigen::Vector3d p_world;
};

/// What a pose explains of a set of correspondences: per query keypoint the candidate point with
/// the smallest reprojection error counts, so a keypoint matched in several keyframes is one
/// inlier at most. `best` receives, per inlier, its best correspondence.
struct PoseSupport {
  int inliers = 0;
  double rms_px = 0;
  int depth_checked = 0, depth_agreeing = 0;
  std::vector<const Correspondence*> best;
};

PoseSupport support(const Eigen::Isometry3d& T_world_cam, const std::vector<Correspondence>& cs,
                    const RgbdFrame& frame, const TRelocalisationParams& P) {
  // cs is sorted by q.
  const CameraIntrinsics& K = frame.intrinsics;
  const Eigen::Isometry3d T_cam_world = T_world_cam.inverse();
  const double thr2 = P.ransac_reprojection_px * P.ransac_reprojection_px;
  PoseSupport s;
  double se = 0;
  for (std::size_t i = 0; i < cs.size();) {
    std::size_t j = i;
    const Correspondence* best = nullptr;
    double best_e2 = thr2;
    for (; j < cs.size() && cs[j].q == cs[i].q; ++j) {
      const Eigen::Vector3d pc = T_cam_world * cs[j].p_world;
      if (pc.z() <= 1e-6) continue;
      const double du = K.fx * pc.x() / pc.z() + K.cx - cs[j].uv.x;
      const double dv = K.fy * pc.y() / pc.z() + K.cy - cs[j].uv.y;
      const double e2 = du * du + dv * dv;
      if (e2 <= best_e2) {
        best_e2 = e2;
        best = &cs[j];
      }
    }
    i = j;
    if (!best) continue;
    ++s.inliers;
    se += best_e2;
    s.best.push_back(best);
    // Depth check: the frame's own 3-D point at this keypoint, moved into the world.
    const float z = depthAt(frame.depth_m, best->uv.x, best->uv.y, P);
    if (z <= 0.0f) continue;
    ++s.depth_checked;
    const Eigen::Vector3d pw = T_world_cam * backProject(K, best->uv.x, best->uv.y, z);
    if ((pw - best->p_world).norm() <= P.depth_check_tolerance_m + P.depth_check_relative * z)
      ++s.depth_agreeing;
  }
  s.rms_px = s.inliers > 0 ? std::sqrt(se / s.inliers) : 0.0;
  return s;
}

Eigen::Isometry3d poseFromRvecTvec(const cv::Mat& rvec, const cv::Mat& tvec) {
  cv::Matx33d R;
  cv::Rodrigues(rvec, R);
  Eigen::Isometry3d T_cam_world = Eigen::Isometry3d::Identity();
  for (int r = 0; r < 3; ++r) {
    for (int c = 0; c < 3; ++c) T_cam_world.linear()(r, c) = R(r, c);
    T_cam_world.translation()(r) = tvec.at<double>(r);
  }
  return orthonormalize(T_cam_world.inverse());
}

void rvecTvecFromPose(const Eigen::Isometry3d& T_world_cam, cv::Mat& rvec, cv::Mat& tvec) {
  const Eigen::Isometry3d T_cam_world = T_world_cam.inverse();
  cv::Matx33d R;
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 3; ++c) R(r, c) = T_cam_world.linear()(r, c);
  cv::Rodrigues(R, rvec);
  tvec = (cv::Mat_<double>(3, 1) << T_cam_world.translation().x(), T_cam_world.translation().y(),
          T_cam_world.translation().z());
}

using Matches = std::vector<std::pair<int, int>>;  ///< (frame feature, keyframe feature)

/// Step 1: the keyframes to try, by ratio-test matches of the strongest frame features (all of
/// them when there are at most candidate_keyframes).
std::vector<std::size_t> rankKeyframes(const cv::Mat& desc, const std::vector<int>& all,
                                       const std::vector<cv::KeyPoint>& kps,
                                       const std::vector<Keyframe>& db,
                                       const TRelocalisationParams& P) {
  std::vector<std::size_t> candidates;
  if (int(db.size()) <= P.candidate_keyframes) {
    for (std::size_t k = 0; k < db.size(); ++k) candidates.push_back(k);
    return candidates;
  }
  std::vector<int> strongest = all;
  std::stable_sort(strongest.begin(), strongest.end(),
                   [&](int a, int b) { return kps[a].response > kps[b].response; });
  if (int(strongest.size()) > P.ranking_features) strongest.resize(std::size_t(P.ranking_features));
  std::vector<std::pair<int, std::size_t>> score;  // (matches, keyframe)
  score.reserve(db.size());
  for (std::size_t k = 0; k < db.size(); ++k) {
    const int n =
        int(matchDescriptors(desc, strongest, db[k].descriptors.data(), int(db[k].numFeatures()),
                             P.match_ratio, P.max_hamming_distance)
                .size());
    if (n > 0) score.emplace_back(n, k);
  }
  std::stable_sort(score.begin(), score.end(),
                   [](const auto& a, const auto& b) { return a.first > b.first; });
  for (std::size_t i = 0; i < score.size() && int(i) < P.candidate_keyframes; ++i)
    candidates.push_back(score[i].second);
  return candidates;
}

struct Hypothesis {
  std::size_t keyframe;
  int matches, ransac_inliers;
  Eigen::Isometry3d T_world_cam;
};

/// Step 2: RANSAC PnP on the matches `m` of the frame with keyframe k; nullopt when it fails or
/// keeps fewer than 6 inliers.
std::optional<Hypothesis> pnpHypothesis(std::size_t k, const Matches& m,
                                        const std::vector<cv::KeyPoint>& kps,
                                        const std::vector<Keyframe>& db, const cv::Matx33d& K,
                                        const TRelocalisationParams& P) {
  std::vector<cv::Point3f> obj;
  std::vector<cv::Point2f> img;
  for (const auto& [q, t] : m) {
    const Eigen::Vector3f& p = db[k].points_world[std::size_t(t)];
    obj.emplace_back(p.x(), p.y(), p.z());
    img.push_back(kps[std::size_t(q)].pt);
  }
  cv::Mat rvec, tvec;
  std::vector<int> inl;
  bool ok = false;
  try {
    ok = cv::solvePnPRansac(obj, img, K, cv::noArray(), rvec, tvec, false, P.ransac_iterations,
                            float(P.ransac_reprojection_px), 0.999, inl, cv::SOLVEPNP_AP3P);
  } catch (const cv::Exception&) {
    ok = false;  // degenerate point sets (e.g. all collinear) can make the minimal solver throw
  }
  if (!ok || inl.size() < 6) return std::nullopt;
  return Hypothesis{k, int(m.size()), int(inl.size()), poseFromRvecTvec(rvec, tvec)};
}

/// The keyframe of hypothesis h and its neighbour_keyframes nearest keyframes (in pose).
std::vector<std::size_t> keyframePool(std::size_t keyframe, const std::vector<Keyframe>& db,
                                      const TRelocalisationParams& P) {
  std::vector<std::pair<double, std::size_t>> near;
  for (std::size_t k = 0; k < db.size(); ++k)
    if (k != keyframe)
      near.emplace_back(spacing(db[keyframe].T_world_cam, db[k].T_world_cam, P), k);
  const std::size_t n_near = std::min(near.size(), std::size_t(P.neighbour_keyframes));
  std::partial_sort(near.begin(), near.begin() + std::ptrdiff_t(n_near), near.end());
  std::vector<std::size_t> pool{keyframe};
  for (std::size_t i = 0; i < n_near; ++i) pool.push_back(near[i].second);
  return pool;
}

bool byFrameFeature(const Correspondence& a, const Correspondence& b) {
  return a.q < b.q;
}

/// Step 3's refinement: up to two Levenberg-Marquardt refinements of T on its inliers among
/// `cs`, each kept when it does not lose inliers; T and its support on return.
PoseSupport refineOnInliers(Eigen::Isometry3d& T, const std::vector<Correspondence>& cs,
                            const RgbdFrame& frame, const cv::Matx33d& K,
                            const TRelocalisationParams& P) {
  PoseSupport s = support(T, cs, frame, P);
  for (int iter = 0; iter < 2 && s.inliers >= 6; ++iter) {
    std::vector<cv::Point3f> obj;
    std::vector<cv::Point2f> img;
    for (const Correspondence* c : s.best) {
      obj.emplace_back(float(c->p_world.x()), float(c->p_world.y()), float(c->p_world.z()));
      img.push_back(c->uv);
    }
    cv::Mat rvec, tvec;
    rvecTvecFromPose(T, rvec, tvec);
    cv::solvePnPRefineLM(obj, img, K, cv::noArray(), rvec, tvec);
    const Eigen::Isometry3d T_refined = poseFromRvecTvec(rvec, tvec);
    PoseSupport s2 = support(T_refined, cs, frame, P);
    if (s2.inliers < s.inliers) break;
    T = T_refined;
    s = std::move(s2);
  }
  return s;
}

}  // namespace

std::optional<RelocalisationResult> Relocaliser::relocalise(const RgbdFrame& frame,
                                                            const std::vector<Keyframe>& db) {
  const auto t0 = std::chrono::steady_clock::now();
  const TRelocalisationParams& P = m_params;
  m_stats = RelocalisationStats{};
  const char* reason = "too few matches";
  int reason_rank = 0;  // the furthest stage a rejected hypothesis reached names the reason
  auto note = [&](int rank, const char* why) {
    if (rank >= reason_rank) {
      reason_rank = rank;
      reason = why;
    }
  };
  auto fail = [&](const char* why) -> std::optional<RelocalisationResult> {
    m_stats.reason = why;
    m_stats.ms = elapsedMs(t0);
    return std::nullopt;
  };
  if (db.empty()) return fail("empty database");
  if (!m_impl->toGrey(frame)) return fail("no colour");

  std::vector<cv::KeyPoint> kps;
  cv::Mat desc;
  m_impl->detect(cv::Mat(), P.orb_min_image_width, kps, desc);
  m_stats.detect_ms = elapsedMs(t0);
  m_stats.features = int(kps.size());
  if (int(kps.size()) < P.min_inliers) return fail("too few features");
  std::vector<int> all(kps.size());
  std::iota(all.begin(), all.end(), 0);

  // Full matches of the frame with keyframe k (computed once per call).
  std::vector<std::optional<Matches>> full(db.size());
  auto matchesWith = [&](std::size_t k) -> const Matches& {
    if (!full[k]) {
      const auto tm = std::chrono::steady_clock::now();
      full[k] = matchDescriptors(desc, all, db[k].descriptors.data(), int(db[k].numFeatures()),
                                 P.match_ratio, P.max_hamming_distance);
      m_stats.match_ms += elapsedMs(tm);
    }
    return *full[k];
  };

  // 1. Rank keyframes by ratio-test matches of the strongest frame features.
  const auto t_rank = std::chrono::steady_clock::now();
  const std::vector<std::size_t> candidates = rankKeyframes(desc, all, kps, db, P);
  m_stats.match_ms += elapsedMs(t_rank);

  // 2. A pose hypothesis per candidate: RANSAC PnP on its own matches.
  const cv::Matx33d K(frame.intrinsics.fx, 0, frame.intrinsics.cx, 0, frame.intrinsics.fy,
                      frame.intrinsics.cy, 0, 0, 1);
  std::vector<Hypothesis> hyps;
  for (std::size_t k : candidates) {
    const Matches& m = matchesWith(k);
    m_stats.best_matches = std::max(m_stats.best_matches, int(m.size()));
    if (int(m.size()) < P.min_matches) continue;
    ++m_stats.candidates_tried;
    if (std::optional<Hypothesis> h = pnpHypothesis(k, m, kps, db, K, P))
      hyps.push_back(*h);
    else
      note(1, "too few inliers");
  }
  std::stable_sort(hyps.begin(), hyps.end(), [](const Hypothesis& a, const Hypothesis& b) {
    return a.ransac_inliers > b.ransac_inliers;
  });

  // 3. Verify hypotheses, best first: pool the matches of the keyframe and its nearest keyframes
  //    (in pose), refine on the inliers, then the inlier and depth checks.
  for (const Hypothesis& h : hyps) {
    if (h.ransac_inliers < P.min_inlier_ratio * h.matches) {
      note(2, "inlier ratio");
      continue;
    }
    std::vector<Correspondence> cs;
    for (std::size_t k : keyframePool(h.keyframe, db, P))
      for (const auto& [q, t] : matchesWith(k))
        cs.push_back(
            {q, kps[std::size_t(q)].pt, db[k].points_world[std::size_t(t)].cast<double>()});
    std::stable_sort(cs.begin(), cs.end(), byFrameFeature);

    Eigen::Isometry3d T = h.T_world_cam;
    const PoseSupport s = refineOnInliers(T, cs, frame, K, P);
    if (s.inliers > m_stats.best_inliers) {
      m_stats.best_inliers = s.inliers;
      m_stats.best_depth_checked = s.depth_checked;
      m_stats.best_depth_agreeing = s.depth_agreeing;
    }
    if (s.inliers < P.min_inliers) {
      note(3, "too few inliers");
      continue;
    }
    if (s.depth_agreeing < P.min_depth_agreeing ||
        s.depth_agreeing < P.min_depth_agreement * s.depth_checked) {
      note(4, "depth check");
      continue;
    }
    m_stats.ms = elapsedMs(t0);
    return RelocalisationResult{T,        h.keyframe,      int(cs.size()),  s.inliers,
                                s.rms_px, s.depth_checked, s.depth_agreeing};
  }
  return fail(reason);
}

}  // namespace rasm::tracking
