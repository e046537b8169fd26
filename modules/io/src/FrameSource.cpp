#include "rasm/io/FrameSource.h"

#include <filesystem>

#include "rasm/core/Error.h"
#include "rasm/io/RawlogFrameSource.h"
#include "rasm/io/SevenScenesFrameSource.h"
#include "rasm/io/TumFrameSource.h"

namespace fs = std::filesystem;

namespace rasm::io {

std::unique_ptr<FrameSource> openFrameSource(
    const std::string& path, const std::optional<CameraIntrinsics>& intrinsics_override) {
  FrameSourceOptions opt;
  opt.intrinsics_override = intrinsics_override;
  return openFrameSource(path, opt);
}

std::unique_ptr<FrameSource> openFrameSource(const std::string& path,
                                             const FrameSourceOptions& opt) {
  if (!fs::exists(path))
    throwInputError(
        path,
        "not found (expected a rawlog file, a TUM RGB-D / ICL-NUIM folder or a 7-Scenes folder)");
  if (fs::is_directory(path)) {
    if (TumFrameSource::looksLikeTumFolder(path)) {
      TumSourceOptions t;
      t.intrinsics_override = opt.intrinsics_override;
      if (opt.depth_factor > 0) t.depth_factor = opt.depth_factor;
      return std::make_unique<TumFrameSource>(path, t);
    }
    if (SevenScenesFrameSource::looksLikeSevenScenesFolder(path)) {
      SevenScenesSourceOptions s;
      s.intrinsics_override = opt.intrinsics_override;
      return std::make_unique<SevenScenesFrameSource>(path, s);
    }
    throwInputError(
        "folder " + path,
        "neither a TUM RGB-D folder (missing rgb.txt and depth.txt) nor a 7-Scenes sequence folder "
        "(missing frame-000000.depth.png)");
  }
  RawlogSourceOptions r;
  r.sensor_label = opt.sensor_label;
  return std::make_unique<RawlogFrameSource>(path, r);
}

}  // namespace rasm::io
