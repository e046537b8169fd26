#pragma once
// Ground truth from a TUM trajectory for the frames of a source that carries none: a rawlog
// replayed with its run's groundtruth.txt (a run's annotated.rawlog holds the estimate, not the
// truth), or a rawlog converted elsewhere. Each frame without a pose gets the trajectory's pose at
// its timestamp (interpolatePose: linear and slerp between the samples around it, within
// max_dt_s); frames with a pose of their own keep it. The map then starts at the true pose and
// the run reports its world-frame error, as a simulated run does.

#include <memory>

#include "rasm/io/FrameSource.h"
#include "rasm/io/Trajectory.h"

namespace rasm::io {

class GroundTruthFrameSource : public FrameSource {
 public:
  /// `groundtruth` in any order (sorted here).
  GroundTruthFrameSource(std::unique_ptr<FrameSource> inner, Trajectory groundtruth,
                         double max_dt_s = 0.02);

  std::optional<RgbdFrame> next() override;
  long long sizeHint() const override { return m_inner->sizeHint(); }
  std::string describe() const override { return m_inner->describe(); }

  /// Frames that got a pose from the trajectory, and frames left without one (no sample within
  /// max_dt_s of their timestamp).
  long long attached() const { return m_attached; }
  long long unmatched() const { return m_unmatched; }

 private:
  std::unique_ptr<FrameSource> m_inner;
  Trajectory m_groundtruth;
  double m_max_dt_s;
  long long m_attached = 0, m_unmatched = 0;
};

}  // namespace rasm::io
