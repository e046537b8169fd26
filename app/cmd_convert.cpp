// `rasm convert`: dataset folders (TUM RGB-D / ICL-NUIM, 7-Scenes) -> MRPT rawlog plus the ground
// truth beside it as a TUM trajectory (rasm::io::convertToRawlog).
#include <unistd.h>

#include <chrono>
#include <cstdio>
#include <filesystem>
#include <iostream>
#include <sstream>

#include "Command.h"
#include "rasm/core/AtomicFile.h"
#include "rasm/core/Error.h"
#include "rasm/io/DatasetConverter.h"
#include "rasm/io/SevenScenesFrameSource.h"
#include "rasm/io/TumFrameSource.h"

namespace {

const rasm::app::CommandDecl kDecl{
    "convert",
    "dataset folder (tum | 7scenes) -> rawlog + ground truth",
    {{"tum|7scenes", "the dataset's format: TUM RGB-D / ICL-NUIM, or 7-Scenes"},
     {"folder", "the sequence folder"},
     {"out.rawlog", "the rawlog to write (in an existing folder)"}},
    {{"intrinsics", "fx,fy,cx,cy", "the depth camera's intrinsics (default: the dataset's)"},
     {"preset", "name", "intrinsics of a preset camera (tum only; listed below)"},
     {"depth-factor", "F", "depth counts per metre (tum only; default 5000)"},
     {"max-frames", "N", "convert the first N frames only"},
     {"external-images", "", "images in files beside the rawlog, not inside it"},
     {"no-register", "", "use 7-Scenes colour as is (treated as registered)"}},
    "7-Scenes colour is resampled into the depth camera with an approximate Kinect calibration;\n"
    "--no-register uses it as is (treated as registered).\n"
    "Writes <out.rawlog> (CObservation3DRangeScan per frame) and <out stem>_groundtruth.txt\n"
    "(TUM).\n"
    "Presets: kinect_v1 xtion tum_fr1 tum_fr2 tum_fr3 tum_default icl_nuim 7scenes\n"};

double parseNumber(const std::string& opt, const std::string& text) {
  try {
    std::size_t n = 0;
    const double v = std::stod(text, &n);
    if (n == text.size()) return v;
  } catch (const std::exception&) {
  }
  rasm::throwInputError(opt, "'" + text + "' is not a number");
}

rasm::CameraIntrinsics parseIntrinsics(const std::string& text) {
  std::vector<double> v;
  std::stringstream ss(text);
  std::string item;
  while (std::getline(ss, item, ',')) v.push_back(parseNumber("--intrinsics", item));
  if (v.size() != 4)
    rasm::throwInputError("--intrinsics", "expected fx,fy,cx,cy, got '" + text + "'");
  return rasm::CameraIntrinsics(v[0], v[1], v[2], v[3], 640, 480);  // size comes from the images
}

/// "\r 120/300 frames (40%)  45.2 frames/s  ETA 4 s" on a terminal; a line every 2 s otherwise.
class Progress {
 public:
  void operator()(std::size_t done, long long total) {
    const auto now = clock::now();
    const double el = std::chrono::duration<double>(now - start_).count();
    const bool last = total >= 0 && (long long)done >= total;
    if (!last && std::chrono::duration<double>(now - last_print_).count() < (tty_ ? 0.2 : 2.0))
      return;
    last_print_ = now;
    const double rate = el > 0 ? done / el : 0.0;
    char buf[160];
    if (total > 0) {
      const double eta = rate > 0 ? (total - (long long)done) / rate : 0.0;
      std::snprintf(buf, sizeof(buf),
                    "convert: %zu/%lld frames (%3.0f%%)  %.1f frames/s  ETA %.0f s", done, total,
                    100.0 * done / total, rate, eta);
    } else {
      std::snprintf(buf, sizeof(buf), "convert: %zu frames  %.1f frames/s", done, rate);
    }
    std::cerr << (tty_ ? "\r" : "") << buf << (tty_ ? "   " : "\n") << std::flush;
    printed_ = true;
  }
  void finish() {
    if (tty_ && printed_) std::cerr << "\n";
  }

 private:
  using clock = std::chrono::steady_clock;
  clock::time_point start_ = clock::now(), last_print_{};
  bool tty_ = isatty(STDERR_FILENO) != 0;
  bool printed_ = false;
};

/// The frame source of `rasm convert <format> <folder>` with the options that apply to it.
std::unique_ptr<rasm::io::FrameSource> openSource(const rasm::app::ParsedArgs& args) {
  const std::string format = args.positional("tum|7scenes"), folder = args.positional("folder");
  std::optional<rasm::CameraIntrinsics> K;
  if (args.has("intrinsics")) K = parseIntrinsics(args.value("intrinsics"));
  if (args.has("preset")) K = rasm::CameraIntrinsics::preset(args.value("preset"));
  const double depth_factor =
      args.has("depth-factor") ? parseNumber("--depth-factor", args.value("depth-factor")) : 0.0;
  const bool register_colour = !args.has("no-register");
  if (format == "tum") {
    if (!register_colour) throw rasm::InputError("--no-register applies to 7scenes only");
    rasm::io::TumSourceOptions t;
    t.intrinsics_override = K;
    if (depth_factor > 0) t.depth_factor = depth_factor;
    auto s = std::make_unique<rasm::io::TumFrameSource>(folder, t);
    std::cout << "TUM sequence " << folder << ": " << s->sizeHint()
              << " associated frames, intrinsics " << s->intrinsics().toString()
              << (s->flipsRows() ? " (negative fy given: rows flipped)" : "") << "\n";
    return s;
  }
  if (format == "7scenes") {
    if (depth_factor > 0) throw rasm::InputError("--depth-factor applies to tum only");
    rasm::io::SevenScenesSourceOptions o;
    o.intrinsics_override = K;
    o.register_colour = register_colour;
    auto s = std::make_unique<rasm::io::SevenScenesFrameSource>(folder, o);
    std::cout << "7-Scenes sequence " << folder << ": " << s->sizeHint() << " frames, intrinsics "
              << s->intrinsics().toString() << "\n";
    return s;
  }
  throw rasm::InputError("unknown format '" + format + "' (expected tum or 7scenes)");
}

int convert(const rasm::app::ParsedArgs& args) {
  const std::vector<std::string> pos = {args.positional("tum|7scenes"), args.positional("folder"),
                                        args.positional("out.rawlog")};
  rasm::io::ConvertOptions copt;
  if (args.has("max-frames"))
    copt.max_frames = (long long)parseNumber("--max-frames", args.value("max-frames"));
  copt.writer.external_images = args.has("external-images");
  const std::unique_ptr<rasm::io::FrameSource> src = openSource(args);
  // The outputs must not replace a file of the input folder (its depth.txt, an image, ...); an
  // earlier conversion's rawlog and ground truth there may be replaced.
  {
    namespace fs = std::filesystem;
    const auto insideInput = [&](const std::string& out) {
      std::error_code e1, e2;
      const fs::path in = fs::weakly_canonical(pos[1], e1), o = fs::weakly_canonical(out, e2);
      if (e1 || e2 || !fs::exists(o)) return false;
      const fs::path rel = o.lexically_relative(in);
      return !rel.empty() && *rel.begin() != "..";
    };
    const std::string gt = rasm::io::groundTruthPathFor(pos[2]);
    const bool earlier_rawlog =
        fs::path(pos[2]).extension() == ".rawlog" && fs::is_regular_file(pos[2]);
    for (const std::string& out : {pos[2], gt})
      if (insideInput(out) && !earlier_rawlog)
        rasm::throwInputError("output '" + out + "'",
                              "is a file of the input folder " + pos[1] +
                                  ": converting would overwrite the input (write elsewhere)");
  }
  // Written only into an existing folder (a mistyped path created folders anywhere, even at the
  // filesystem root).
  rasm::requireParentFolder(pos[2], "output '" + pos[2] + "'");
  Progress progress;
  const auto res = rasm::io::convertToRawlog(*src, pos[2], copt, std::ref(progress));
  progress.finish();
  std::cout << "wrote " << res.rawlog_path << ": " << res.frames << " frames, "
            << res.frames_with_groundtruth << " with ground truth\n";
  if (!res.groundtruth_path.empty())
    std::cout << "wrote " << res.groundtruth_path << " (TUM format)\n";
  return 0;
}

const rasm::app::Registrar reg{kDecl, &convert};

}  // namespace
