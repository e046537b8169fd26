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

/// Opens a rawlog file, a TUM/ICL-NUIM sequence folder or a 7-Scenes folder, by inspecting the
/// path. `intrinsics_override` replaces the intrinsics for TUM-format folders (ICL-NUIM, other
/// freiburg cameras). Throws InputError naming the path and what was expected.
std::unique_ptr<FrameSource> openFrameSource(const std::string& path,
                                             const std::optional<CameraIntrinsics>& intrinsics_override = {});

}  // namespace rasm::io
