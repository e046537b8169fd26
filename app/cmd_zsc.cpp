// `rasm zsc train | detect`: the zero-shot classifier of paper IV-A (thin layer over
// rasm::classification::TemplateBank / ZeroShotDetector; docs/classification-zero-shot.md).
#ifdef RASM_HAVE_MODULE_CLASSIFICATION
#include <mrpt/config/CConfigFileMemory.h>

#include <chrono>
#include <cstdio>
#include <filesystem>
#include <iostream>
#include <nlohmann/json.hpp>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "Command.h"
#include "rasm/classification/TemplateBank.h"
#include "rasm/classification/ZeroShotDetector.h"
#include "rasm/core/Error.h"
#include "rasm/core/Params.h"
#include "rasm/core/Timing.h"
#include "rasm/pipeline/OutputFiles.h"

namespace {

using namespace rasm::classification;
using rasm::app::CommandDecl;
using rasm::app::ParsedArgs;

const char* kModelsNote =
    "models.yaml: docs/classification-zero-shot.md (shipped: "
    "modules/classification/models/*.yaml)\n";

const CommandDecl kTrainDecl{
    "zsc train",
    "render the models' templates into a template bank",
    {{"models.yaml", "the models and their views"}, {"bank", "the template bank to write"}},
    {},
    kModelsNote};

const CommandDecl kDetectDecl{
    "zsc detect",
    "zero-shot detections on one image as JSON",
    {{"bank", "a template bank of rasm zsc train"}, {"image", "the image"}},
    {{"out", "boxes.png", "draw the detections into a PNG"},
     {"set", "zero_shot.key=value", "set one key of [zero_shot]", "", true}},
    kModelsNote};

int train(const ParsedArgs& args) {
  const std::string models = args.positional("models.yaml"), bank_path = args.positional("bank");
  const rasm::Clock::time_point t0 = rasm::Clock::now();
  const ModelsSpec spec = loadModelsSpec(models);
  const TemplateBank bank =
      trainTemplateBank(spec, [&](std::size_t i, std::size_t n, std::size_t t) {
        std::fprintf(stderr, "\rtraining: model %zu/%zu (%s), %zu templates", i, n,
                     spec.models[i - 1].class_name.c_str(), t);
        std::fflush(stderr);
      });
  std::fprintf(stderr, "\n");
  saveTemplateBank(bank, bank_path);
  nlohmann::json j;
  j["bank"] = bank_path;
  j["templates"] = bank.size();
  j["descriptor_length"] = bank.descriptors.cols;
  for (int c = 0; c < int(bank.class_names.size()); ++c)
    j["templates_per_class"][bank.class_names[c]] = bank.templatesOfClass(c);
  j["seconds"] = rasm::msSince(t0) / 1000.0;
  std::cout << j.dump(2) << std::endl;
  return 0;
}

/// --set zero_shot.key=value overrides on top of the defaults, with the strict INI loader.
TZeroShotParams paramsFromOverrides(const std::vector<std::string>& sets) {
  mrpt::config::CConfigFileMemory ini;
  for (const std::string& s : sets) {
    const auto dot = s.find('.'), eq = s.find('=');
    if (dot == std::string::npos || eq == std::string::npos || eq < dot ||
        s.substr(0, dot) != "zero_shot")
      rasm::throwInputError("--set '" + s + "'", "expected zero_shot.key=value");
    ini.write("zero_shot", s.substr(dot + 1, eq - dot - 1), s.substr(eq + 1));
  }
  TZeroShotParams p;
  rasm::loadParamsStrict(ini, "zero_shot", p, "--set");
  return p;
}

void drawDetections(cv::Mat& image, const std::vector<Detection>& dets,
                    const std::vector<std::string>& names) {
  for (const Detection& d : dets) {
    const cv::Rect box(d.box);
    cv::rectangle(image, box, cv::Scalar(0, 255, 255), 2);
    char label[160];
    std::snprintf(label, sizeof(label), "%s %.2f az%.0f el%.0f", names[d.bestIndex()].c_str(),
                  d.bestScore(), d.pose.azimuth_deg, d.pose.elevation_deg);
    cv::putText(image, label, box.tl() + cv::Point(2, 14), cv::FONT_HERSHEY_SIMPLEX, 0.45,
                cv::Scalar(0, 255, 255), 1, cv::LINE_AA);
  }
}

int detect(const ParsedArgs& args) {
  const std::string bank = args.positional("bank"), image_path = args.positional("image"),
                    out = args.value("out");
  TZeroShotParams params = paramsFromOverrides(args.values("set"));
  ZeroShotDetector detector(loadTemplateBank(bank), params);
  cv::Mat image = cv::imread(image_path, cv::IMREAD_COLOR);
  if (image.empty()) rasm::throwInputError("image '" + image_path + "'", "missing or unreadable");
  DetectorInput in;
  in.bgr = image;
  const std::vector<Detection> dets = detector.detect(in);
  nlohmann::json j;
  j["image"] = image_path;
  j["proposal_ms"] = detector.lastProposalMs();
  j["match_ms"] = detector.lastMatchMs();
  j["detections"] = nlohmann::json::array();
  for (const Detection& d : dets) {
    nlohmann::json dj;
    dj["class"] = detector.classNames()[d.bestIndex()];
    dj["score"] = d.bestScore();
    dj["box"] = {d.box.x, d.box.y, d.box.width, d.box.height};
    dj["azimuth_deg"] = d.pose.azimuth_deg;
    dj["elevation_deg"] = d.pose.elevation_deg;
    dj["template"] = d.pose.template_index;
    const TemplateInfo& t = detector.bank().templates[d.pose.template_index];
    if (t.dimensions_m.maxCoeff() > 0.f)
      dj["dimensions_m"] = {t.dimensions_m.x(), t.dimensions_m.y(), t.dimensions_m.z()};
    j["detections"].push_back(dj);
  }
  std::cout << j.dump(2) << std::endl;
  if (!out.empty()) {
    drawDetections(image, dets, detector.classNames());
    try {
      rasm::pipeline::writeImageAtomically(out, image);
    } catch (const std::exception& e) {
      rasm::throwInputError("--out '" + out + "'", std::string("cannot write: ") + e.what());
    }
  }
  return 0;
}

const rasm::app::Registrar reg{
    {"zsc",
     "zero-shot classifier (IV-A): rasm zsc train <models.yaml> <bank> | detect <bank> <image>",
     {},
     {},
     kModelsNote}};
const rasm::app::Registrar reg_train{kTrainDecl, &train};
const rasm::app::Registrar reg_detect{kDetectDecl, &detect};

}  // namespace
#endif  // RASM_HAVE_MODULE_CLASSIFICATION
