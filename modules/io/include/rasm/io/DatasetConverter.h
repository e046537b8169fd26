#pragma once
// Converts any FrameSource into a rawlog (RawlogWriter) plus its ground truth as a TUM trajectory
// beside it: "<out stem>_groundtruth.txt". Drives `rasm convert`.

#include <cstddef>
#include <functional>
#include <string>

#include "rasm/io/FrameSource.h"
#include "rasm/io/RawlogWriter.h"

namespace rasm::io {

struct ConvertOptions {
  long long max_frames = -1;  ///< -1: all
  RawlogWriterOptions writer;
  bool write_groundtruth = true;  ///< only when at least one frame has ground truth
};

struct ConvertResult {
  std::size_t frames = 0;
  std::size_t frames_with_groundtruth = 0;
  std::string rawlog_path;
  std::string groundtruth_path;  ///< empty when none was written
};

/// Called after each frame with (frames done, total or -1).
using ConvertProgressFn = std::function<void(std::size_t done, long long total)>;

/// "<dir>/<stem>_groundtruth.txt" for "<dir>/<stem>.rawlog".
std::string groundTruthPathFor(const std::string& rawlog_path);

ConvertResult convertToRawlog(FrameSource& source, const std::string& rawlog_path,
                              const ConvertOptions& opt = {},
                              const ConvertProgressFn& progress = {});

}  // namespace rasm::io
