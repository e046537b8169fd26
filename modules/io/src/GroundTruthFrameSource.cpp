#include "rasm/io/GroundTruthFrameSource.h"

#include <algorithm>

namespace rasm::io {

GroundTruthFrameSource::GroundTruthFrameSource(std::unique_ptr<FrameSource> inner,
                                               Trajectory groundtruth, double max_dt_s)
    : m_inner(std::move(inner)), m_groundtruth(std::move(groundtruth)), m_max_dt_s(max_dt_s) {
  std::stable_sort(
      m_groundtruth.begin(), m_groundtruth.end(),
      [](const StampedPose& a, const StampedPose& b) { return a.timestamp_s < b.timestamp_s; });
}

std::optional<RgbdFrame> GroundTruthFrameSource::next() {
  std::optional<RgbdFrame> f = m_inner->next();
  if (!f || f->gt_T_world_cam) return f;
  f->gt_T_world_cam = interpolatePose(m_groundtruth, f->timestamp_s, m_max_dt_s);
  ++(f->gt_T_world_cam ? m_attached : m_unmatched);
  return f;
}

}  // namespace rasm::io
