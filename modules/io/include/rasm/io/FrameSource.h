#pragma once
// A sequence of RGB-D frames, whatever it is read from (rawlog, TUM / ICL-NUIM folder, 7-Scenes
// folder, simulator, OpenNI2). Frames come out validated (RgbdFrame::validate) with registered
// colour, depth in metres, intrinsics and, when the source has it, ground-truth pose.

#include <memory>
#include <optional>
#include <string>

#include "rasm/core/RgbdFrame.h"

namespace rasm::io {

class FrameSource {
 public:
  virtual ~FrameSource() = default;
  /// Next frame, or std::nullopt at the end. Throws InputError on bad data (naming the source
  /// and the frame).
  virtual std::optional<RgbdFrame> next() = 0;
  /// Total frames when known in advance (for progress / ETA), else -1.
  virtual long long sizeHint() const { return -1; }
  /// Human-readable name for messages ("rawlog /path/x.rawlog").
  virtual std::string describe() const = 0;
};

/// What openFrameSource passes on to the reader it picks (each reader has its own options
/// struct with more knobs: RawlogSourceOptions, TumSourceOptions, SevenScenesSourceOptions).
struct FrameSourceOptions {
  /// Replaces the intrinsics of TUM-format and 7-Scenes folders (ICL-NUIM, other cameras).
  std::optional<CameraIntrinsics> intrinsics_override;
  /// Rawlogs: only CObservation3DRangeScan with this sensor label (empty: all).
  std::string sensor_label;
  /// TUM-format folders: depth PNG units per metre (0: the format's 5000).
  double depth_factor = 0.0;
};

/// Opens a rawlog file, a TUM/ICL-NUIM sequence folder or a 7-Scenes folder, by inspecting the
/// path. `intrinsics_override` replaces the intrinsics for TUM-format folders (ICL-NUIM, other
/// freiburg cameras). Throws InputError naming the path and what was expected.
std::unique_ptr<FrameSource> openFrameSource(
    const std::string& path, const std::optional<CameraIntrinsics>& intrinsics_override = {});
std::unique_ptr<FrameSource> openFrameSource(const std::string& path,
                                             const FrameSourceOptions& opt);

}  // namespace rasm::io
