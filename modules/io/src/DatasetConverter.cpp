#include "rasm/io/DatasetConverter.h"

#include <filesystem>

#include "rasm/core/Error.h"
#include "rasm/io/Trajectory.h"

namespace fs = std::filesystem;

namespace rasm::io {

std::string groundTruthPathFor(const std::string& rawlog_path) {
  const fs::path p(rawlog_path);
  return (p.parent_path() / (p.stem().string() + "_groundtruth.txt")).string();
}

ConvertResult convertToRawlog(FrameSource& source, const std::string& rawlog_path,
                              const ConvertOptions& opt, const ConvertProgressFn& progress) {
  long long total = source.sizeHint();
  if (opt.max_frames >= 0 && (total < 0 || total > opt.max_frames)) total = opt.max_frames;

  ConvertResult res;
  res.rawlog_path = rawlog_path;
  RawlogWriter writer(rawlog_path, opt.writer);
  Trajectory gt;
  while (opt.max_frames < 0 || (long long)res.frames < opt.max_frames) {
    std::optional<RgbdFrame> f = source.next();
    if (!f) break;
    writer.write(*f);
    if (f->gt_T_world_cam) gt.push_back({f->timestamp_s, *f->gt_T_world_cam});
    ++res.frames;
    if (progress) progress(res.frames, total);
  }
  if (res.frames == 0) throwInputError(source.describe(), "no frames to convert");
  writer.close();

  res.frames_with_groundtruth = gt.size();
  if (opt.write_groundtruth && !gt.empty()) {
    res.groundtruth_path = groundTruthPathFor(rawlog_path);
    writeTumTrajectory(res.groundtruth_path, gt,
                       "ground truth T_world_cam (optical frame) of " +
                           fs::path(rawlog_path).filename().string() + "\nconverted by rasm from " +
                           source.describe());
  }
  return res;
}

}  // namespace rasm::io
