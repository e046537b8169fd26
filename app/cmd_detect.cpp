// `rasm detect <image> [file.ini] [options]`: runs the configured 2-D detector of section IV
// ([dnn_detector], rasm::classification:: DnnDetector) on one image and prints the detections as
// JSON: class, score, box (x, y, w, h in pixels) and every reported class's score. --out draws the
// boxes and labels into a PNG. Without an INI: Yolo-Fastest 1.1 (COCO) from the shared data folder.
// Paths under "../shared/data/" that do not exist relative to the working directory are looked up
// in $RASM_SHARED_DATA, the compiled-in shared data folder and next to the source tree of this
// binary (rasm/core/SharedData.h), so the default works from any directory. --threads sets OpenCV's
// thread count, --repeat N times N calls and reports their median (docs/classification.md "DNN
// detector").
#if defined(RASM_HAVE_MODULE_CLASSIFICATION) && defined(RASM_HAVE_MODULE_RUN)

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <iostream>
#include <memory>
#include <nlohmann/json.hpp>
#include <opencv2/core/utility.hpp>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>
#include <string>
#include <vector>

#include "Command.h"
#include "rasm/classification/DnnDetector.h"
#include "rasm/classification/TClassificationParams.h"
#include "rasm/classification/ZeroShotDetector.h"
#include "rasm/core/Error.h"
#include "rasm/core/Params.h"
#include "rasm/core/SharedData.h"
#include "rasm/core/Timing.h"
#include "rasm/pipeline/OutputFiles.h"
#include "rasm/run/RunConfig.h"

namespace {

namespace fs = std::filesystem;
using rasm::classification::Detection;
using rasm::classification::Detector;

const rasm::app::CommandDecl kDecl{
    "detect",
    "2-D detections on one image as JSON: rasm detect <image> [file.ini] [--set s.k=v] "
    "[--out boxes.png]",
    {{"image", "the image"},
     {"file.ini", "the configuration of the detectors (default: Yolo-Fastest 1.1)", false}},
    {{"set", "section.key=value", "set one key of the configuration", "", true},
     {"out", "boxes.png", "draw the detections into a PNG"},
     {"threads", "N", "OpenCV's thread count"},
     {"repeat", "N", "run each detector N times and report the median time"}},
    "Runs the detectors [classification] detectors lists (dnn_detector, zero_shot), or\n"
    "[dnn_detector] alone when the INI does not set that key (default: Yolo-Fastest 1.1 from\n"
    "../shared/data), on one image and prints the detections as JSON (with several detectors,\n"
    "one entry per detector under \"detectors\"); --out draws them into a PNG.\n"};

/// The detector `rasm detect` runs, from the configuration (one place, so more detectors join
/// here). InputError when it is disabled or its files are missing (whatever `required` says).
std::unique_ptr<Detector> makeConfiguredDnn(const rasm::run::RunConfig& cfg) {
  rasm::classification::TDnnDetectorParams params;
  rasm::loadParamsStrict(cfg.ini(), "dnn_detector", params, cfg.source());
  for (std::string* p : {&params.model, &params.weights, &params.names})
    *p = rasm::resolveSharedData(*p);
  if (!params.enabled)
    rasm::throwInputError("[dnn_detector] enabled", "false: there is no detector to run");
  params.required = true;  // this command has nothing to do without it: missing files are errors
  return rasm::classification::makeDnnDetector(params, nullptr);
}

/// The detectors [classification] detectors lists (the DNN detector alone when the INI does not
/// set that key): the same detectors a run with this INI would use, on one image.
std::vector<std::unique_ptr<Detector>> makeConfiguredDetectors(const rasm::run::RunConfig& cfg) {
  std::vector<std::unique_ptr<Detector>> out;
  if (!cfg.ini().keyExists("classification", "detectors")) {
    out.push_back(makeConfiguredDnn(cfg));
    return out;
  }
  rasm::classification::TClassificationParams params;
  rasm::loadParamsStrict(cfg.ini(), "classification", params, cfg.source());
  params.resolveAuto(/*simulated_source=*/false);  // an image: auto is the DNN detector
  for (const std::string& name : params.detectorList()) {
    if (name == "dnn_detector") {
      out.push_back(makeConfiguredDnn(cfg));
    } else if (name == "zero_shot") {
      rasm::classification::TZeroShotParams zsc;
      rasm::loadParamsStrict(cfg.ini(), "zero_shot", zsc, cfg.source());
      out.push_back(rasm::classification::ZeroShotDetector::fromParams(zsc, name));
    } else {
      rasm::throwInputError("[classification] detectors = " + params.detectors,
                            "'" + name + "' needs a simulated frame, not an image");
    }
  }
  if (out.empty())
    rasm::throwInputError("[classification] detectors", "is empty: there is no detector to run");
  return out;
}

/// v to `decimals` places (the nearest double, so the JSON prints it short).
double rounded(double v, int decimals) {
  const double scale = std::pow(10.0, decimals);
  return std::round(v * scale) / scale;
}

nlohmann::ordered_json detectionsJson(const std::vector<Detection>& detections,
                                      const std::vector<std::string>& names) {
  nlohmann::ordered_json list = nlohmann::ordered_json::array();
  for (const Detection& d : detections) {
    nlohmann::ordered_json scores = nlohmann::ordered_json::object();
    for (const auto& s : d.scores) scores[names.at(s.class_index)] = rounded(s.score, 4);
    list.push_back({{"class", names.at(d.bestIndex())},
                    {"score", rounded(d.bestScore(), 4)},
                    {"box",
                     {rounded(d.box.x, 1), rounded(d.box.y, 1), rounded(d.box.width, 1),
                      rounded(d.box.height, 1)}},
                    {"scores", scores}});
  }
  return list;
}

/// Boxes and "class score" labels drawn over the image, one colour per class.
void drawBoxes(cv::Mat& canvas, const std::vector<Detection>& detections,
               const std::vector<std::string>& names) {
  for (const Detection& d : detections) {
    const int c = d.bestIndex();
    const cv::Scalar colour((c * 67 + 40) % 256, (c * 131 + 90) % 256, (c * 199 + 160) % 256);
    const cv::Rect box(cv::Point(int(std::lround(d.box.x)), int(std::lround(d.box.y))),
                       cv::Point(int(std::lround(d.box.br().x)), int(std::lround(d.box.br().y))));
    cv::rectangle(canvas, box, colour, 2);
    char label[128];
    std::snprintf(label, sizeof label, "%s %.2f", names.at(c).c_str(), d.bestScore());
    int baseline = 0;
    const cv::Size text = cv::getTextSize(label, cv::FONT_HERSHEY_SIMPLEX, 0.5, 1, &baseline);
    const cv::Point origin(box.x, std::max(text.height + 4, box.y));
    cv::rectangle(canvas, origin + cv::Point(0, -text.height - 4),
                  origin + cv::Point(text.width + 4, baseline - 2), colour, cv::FILLED);
    cv::putText(canvas, label, origin + cv::Point(2, -3), cv::FONT_HERSHEY_SIMPLEX, 0.5,
                cv::Scalar(0, 0, 0), 1, cv::LINE_AA);
  }
}

void writePng(const cv::Mat& canvas, const std::string& path) {
  std::vector<uchar> png;
  if (!cv::imencode(".png", canvas, png))
    rasm::throwInputError("--out " + path, "PNG encoding failed");
  rasm::pipeline::writeFileAtomically(path, std::string(png.begin(), png.end()));
}

int positiveInt(const std::string& opt, const std::string& text) {
  std::size_t n = 0;
  int v = 0;
  try {
    v = std::stoi(text, &n);
  } catch (const std::exception&) {
  }
  if (n != text.size() || v < 1) rasm::throwInputError(opt, "'" + text + "' is not a count >= 1");
  return v;
}

int detectMain(const rasm::app::ParsedArgs& args) {
  using rasm::run::RunConfig;
  const std::string image_path = args.positional("image"), ini = args.positional("file.ini");
  const std::string out_png = args.value("out");
  if (args.has("threads")) cv::setNumThreads(positiveInt("--threads", args.value("threads")));
  const int repeat = args.has("repeat") ? positiveInt("--repeat", args.value("repeat")) : 1;
  std::error_code ec;
  if (!fs::is_regular_file(image_path, ec))
    rasm::throwInputError("image '" + image_path + "'", "not found");
  const cv::Mat bgr = cv::imread(image_path, cv::IMREAD_COLOR);
  if (bgr.empty())
    rasm::throwInputError("image '" + image_path + "'", "cannot be decoded as an image");

  RunConfig cfg = !ini.empty() ? RunConfig::fromFile(ini)
                               : RunConfig::fromString("", "built-in default (Yolo-Fastest 1.1)");
  for (const auto& o : args.values("set")) cfg.applyOverride(o);
  const std::vector<std::unique_ptr<Detector>> detectors = makeConfiguredDetectors(cfg);

  rasm::classification::DetectorInput input;
  input.bgr = bgr;
  nlohmann::ordered_json per_detector = nlohmann::ordered_json::array();
  cv::Mat canvas = bgr.clone();
  for (const auto& detector : detectors) {
    std::vector<Detection> detections;
    std::vector<double> ms;
    for (int r = 0; r < repeat; ++r) {
      const rasm::Clock::time_point t0 = rasm::Clock::now();
      detections = detector->detect(input);
      ms.push_back(rasm::msSince(t0));
    }
    std::nth_element(ms.begin(), ms.begin() + ms.size() / 2, ms.end());
    per_detector.push_back({{"detector", detector->name()},
                            {"detections", detectionsJson(detections, detector->classNames())},
                            {"ms", rounded(ms[ms.size() / 2], 2)}});
    drawBoxes(canvas, detections, detector->classNames());
  }
  nlohmann::ordered_json j = {{"image", image_path}};
  if (per_detector.size() == 1) {  // one detector: its fields at the top level
    for (auto it = per_detector[0].begin(); it != per_detector[0].end(); ++it) j[it.key()] = *it;
  } else {
    j["detectors"] = per_detector;
  }
  j["threads"] = cv::getNumThreads();
  std::cout << j.dump(2) << std::endl;
  if (!out_png.empty()) writePng(canvas, out_png);
  return 0;
}

const rasm::app::Registrar reg{kDecl, &detectMain};

}  // namespace

#endif
