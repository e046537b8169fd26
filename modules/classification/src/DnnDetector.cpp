#include "rasm/classification/DnnDetector.h"

#include <mrpt/config/CConfigFileBase.h>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <map>
#include <opencv2/core/version.hpp>
#include <opencv2/imgproc.hpp>
#include <set>
#include <sstream>

#include "rasm/core/Error.h"
#include "rasm/core/Params.h"
#include "rasm/core/SharedData.h"
#include "rasm/core/Timing.h"

namespace rasm::classification {

namespace {

namespace fs = std::filesystem;

std::string keyName(const std::string& section, const std::string& key) {
  return "[" + section + "] " + key;
}

/// "a b c" or "a, b, c" (or one number for all three channels); false if not numbers.
bool parseTriple(const std::string& text, cv::Scalar& out) {
  std::string t = text;
  std::replace(t.begin(), t.end(), ',', ' ');
  std::istringstream in(t);
  std::vector<double> v;
  std::string word;
  while (in >> word) {
    char* end = nullptr;
    const double x = std::strtod(word.c_str(), &end);
    if (end == word.c_str() || *end != '\0' || !std::isfinite(x)) return false;
    v.push_back(x);
  }
  if (v.size() == 1) v.assign(3, v[0]);
  if (v.size() != 3) return false;
  out = cv::Scalar(v[0], v[1], v[2]);
  return true;
}

std::string lower(std::string s) {
  for (auto& ch : s) ch = char(std::tolower(static_cast<unsigned char>(ch)));
  return s;
}

/// Where a missing model file can be found, from its name (README of ../shared/data).
std::string howToObtain(const std::string& path, const std::string& key) {
  const std::string name = lower(fs::path(path).filename().string());
  if (name.find("fastest") != std::string::npos)
    return "Yolo-Fastest 1.1 (cfg, weights, coco.names) is in "
           "../shared/data/detectors/yolo-fastest-1.1-coco/ (the project's shared data folder "
           "next to the source tree, looked up there from any working directory; "
           "$RASM_SHARED_DATA names another); or give absolute paths";
  if (name.find("nanodet") != std::string::npos)
    return "NanoDet-m is ../shared/data/detectors/nanodet-m-320-onnx/nanodet.onnx (the "
           "project's shared data folder next to the source tree)";
  if (key == "names")
    return "coco.names is installed by Debian's darknet package as "
           "/usr/share/darknet/data/coco.names and lies next to each model in "
           "../shared/data/detectors/";
  if (key == "weights" && name.find("yolo") != std::string::npos)
    return "the official Darknet weights (yolov3.weights, yolov3-tiny.weights, yolov4.weights, "
           "from the Darknet authors' releases) are user supplied: Debian's darknet package ships "
           "only the .cfg files (/usr/share/darknet/cfg), no weights";
  if (key == "model" && name.find("yolo") != std::string::npos)
    return "Debian's darknet package (scripts/install-deps.sh) installs yolov3.cfg and "
           "yolov3-tiny.cfg under /usr/share/darknet/cfg";
  return "set it to the file's path";
}

/// A 2-D float view [rows, cols] of an output blob whose last dimension is `cols` (any leading
/// batch dimensions of size 1).
cv::Mat rowsOf(const cv::Mat& blob, int cols) {
  CV_Assert(blob.type() == CV_32F && blob.isContinuous() && cols > 0 && blob.total() % cols == 0);
  return cv::Mat(int(blob.total() / cols), cols, CV_32F, const_cast<float*>(blob.ptr<float>()));
}
int lastDim(const cv::Mat& blob) {
  return blob.dims <= 2 ? blob.cols : blob.size[blob.dims - 1];
}
int secondLastDim(const cv::Mat& blob) {
  return blob.dims <= 2 ? blob.rows : blob.size[blob.dims - 2];
}

/// The classes of one output row whose score (factor * class_probs[c]) is >= threshold, sorted
/// by decreasing score; empty when none.
std::vector<ClassScore> classesAbove(const float* class_probs, int num_classes, int step,
                                     float factor, float threshold) {
  std::vector<ClassScore> out;
  for (int c = 0; c < num_classes; ++c) {
    const float score = factor * class_probs[c * step];
    if (score >= threshold) out.push_back({c, std::min(score, 1.f)});
  }
  std::sort(out.begin(), out.end(), [](const ClassScore& a, const ClassScore& b) {
    return a.score > b.score || (a.score == b.score && a.class_index < b.class_index);
  });
  return out;
}

Detection centreBox(float cx, float cy, float w, float h, std::vector<ClassScore> scores) {
  Detection d;
  d.box = cv::Rect2f(cx - 0.5f * w, cy - 0.5f * h, w, h);
  d.scores = std::move(scores);
  return d;
}

/// The stride s of a NanoDet level with `rows` cells on a net-sized input (ceil(W/s)*ceil(H/s)).
int nanodetStride(int rows, cv::Size net) {
  for (int s : {4, 8, 16, 32, 64, 128})
    if (((net.width + s - 1) / s) * ((net.height + s - 1) / s) == rows) return s;
  throw std::runtime_error("NanoDet output with " + std::to_string(rows) +
                           " rows matches no stride of a " + std::to_string(net.width) + "x" +
                           std::to_string(net.height) + " input");
}

/// Expected distance (in bins) of one side's distribution: softmax over the bins, then sum j p_j
/// (the integral of the GFL head, NanoDet).
float distributionExpectation(const float* logits, int bins) {
  const float top = *std::max_element(logits, logits + bins);
  float sum = 0.f, weighted = 0.f;
  for (int j = 0; j < bins; ++j) {
    const float e = std::exp(logits[j] - top);
    sum += e;
    weighted += e * float(j);
  }
  return weighted / sum;
}

/// key = value // comment, without MRPT's name padding (padded names would become part of the
/// keys that rasm::knownKeys reads back).
template <typename T>
void put(mrpt::config::CConfigFileBase& c, const std::string& s, const std::string& key,
         const T& value, const std::string& comment) {
  c.write(s, key, value, -1, -1, comment);
}

/// "" when a Darknet .weights file holds exactly the parameters of `net` (read from its .cfg),
/// else what is wrong. OpenCV reads a truncated file, or the weights of another network, without
/// a word and the detector then finds nothing: the file size is the check. The file is a header
/// (major, minor, revision as int32, then the images seen: uint64 from version 0.2, else
/// int32) and one float per parameter of the convolution and batch-norm layers (the [yolo]
/// layers' anchors, which OpenCV also holds as blobs, come from the .cfg).
std::string darknetWeightsProblem(cv::dnn::Net& net, const std::string& weights) {
  std::ifstream f(weights, std::ios::binary | std::ios::ate);
  const std::streamoff bytes = f ? std::streamoff(f.tellg()) : std::streamoff(-1);
  std::int32_t version[3] = {0, 0, 0};
  f.seekg(0);
  if (bytes < 12 || !f.read(reinterpret_cast<char*>(version), sizeof version))
    return "holds " + std::to_string(bytes) + " bytes: too short for a Darknet weights header";
  const bool long_seen =
      version[0] * 10 + version[1] >= 2 && version[0] < 1000 && version[1] < 1000;
  const std::streamoff header = long_seen ? 20 : 16;
  std::streamoff params = 0;
  for (const std::string& name : net.getLayerNames()) {
    const cv::Ptr<cv::dnn::Layer> layer = net.getLayer(name);
    if (layer->type == "Region") continue;
    for (const cv::Mat& b : layer->blobs) params += std::streamoff(b.total());
  }
  const std::streamoff expected = header + 4 * params;
  if (bytes == expected) return "";
  return "holds " + std::to_string(bytes) + " bytes, but the network of the model needs " +
         std::to_string(expected) + " (" + std::to_string(params) + " parameters): " +
         (bytes < expected ? "a truncated file" : "the weights of another network");
}

std::string shapeText(const cv::Mat& m) {
  std::string s;
  for (int i = 0; i < m.dims; ++i) s += (i ? "x" : "") + std::to_string(m.size[i]);
  return s;
}

}  // namespace

// ---------------------------------------------------------------------------------------------
// [dnn_detector]

TDnnDetectorParams TDnnDetectorParams::fromPreset(const std::string& name,
                                                  const std::string& section) {
  TDnnDetectorParams p;
  p.applyPreset(name, section);
  return p;
}

void TDnnDetectorParams::applyPreset(const std::string& name, const std::string& section) {
  requireOneOf(name, {"nanodet_m", "yolo_fastest"}, section, "preset");
  preset = name;
  input_width = input_height = 320;
  nanodet_cell_offset = 0.5;
  if (name == "nanodet_m") {
    const std::string dir = "../shared/data/detectors/nanodet-m-320-onnx/";
    format = "onnx";
    model = dir + "nanodet.onnx";
    weights.clear();
    names = dir + "coco.names";
    layout = "nanodet";
    letterbox = true;
    scale = 1.0;
    mean = "103.53 116.28 123.675";
    stddev = "57.375 57.12 58.395";
    swap_rb = false;
  } else {
    const std::string dir = "../shared/data/detectors/yolo-fastest-1.1-coco/";
    format = "darknet";
    model = dir + "yolo-fastest-1.1.cfg";
    weights = dir + "yolo-fastest-1.1.weights";
    names = dir + "coco.names";
    layout = "yolo";
    letterbox = false;
    scale = 1.0 / 255.0;
    mean = "0 0 0";
    stddev = "1 1 1";
    swap_rb = true;
  }
}

void TDnnDetectorParams::loadFromConfigFile(const mrpt::config::CConfigFileBase& c,
                                            const std::string& s) {
  MRPT_LOAD_CONFIG_VAR_CS(enabled, bool);
  applyPreset(c.read_string(s, "preset", preset), s);
  MRPT_LOAD_CONFIG_VAR_CS(format, string);
  MRPT_LOAD_CONFIG_VAR_CS(model, string);
  MRPT_LOAD_CONFIG_VAR_CS(weights, string);
  MRPT_LOAD_CONFIG_VAR_CS(names, string);
  MRPT_LOAD_CONFIG_VAR_CS(layout, string);
  MRPT_LOAD_CONFIG_VAR_CS(input_width, int);
  MRPT_LOAD_CONFIG_VAR_CS(input_height, int);
  MRPT_LOAD_CONFIG_VAR_CS(letterbox, bool);
  MRPT_LOAD_CONFIG_VAR_CS(confidence_threshold, double);
  MRPT_LOAD_CONFIG_VAR_CS(nms_threshold, double);
  MRPT_LOAD_CONFIG_VAR_CS(scale, double);
  MRPT_LOAD_CONFIG_VAR_CS(mean, string);
  MRPT_LOAD_CONFIG_VAR_CS(stddev, string);
  MRPT_LOAD_CONFIG_VAR_CS(swap_rb, bool);
  MRPT_LOAD_CONFIG_VAR_CS(nanodet_cell_offset, double);
  MRPT_LOAD_CONFIG_VAR_CS(backend, string);
  MRPT_LOAD_CONFIG_VAR_CS(required, bool);
  validate(s);
}

void TDnnDetectorParams::saveToConfigFile(mrpt::config::CConfigFileBase& c,
                                          const std::string& s) const {
  put(c, s, "enabled", enabled, "false: no DNN detector");
  put(c, s, "preset", preset, "nanodet_m | yolo_fastest: the model keys below, overridable");
  put(c, s, "format", format, "darknet (model = .cfg, weights = .weights) | onnx");
  put(c, s, "model", model, "Darknet .cfg or .onnx file");
  put(c, s, "weights", weights, "Darknet .weights file (format = darknet)");
  put(c, s, "names", names, "class names, one per line");
  put(c, s, "layout", layout, "yolo (Darknet) | yolov5 | yolov8 | nanodet (ONNX)");
  put(c, s, "input_width", input_width, "network input width (px, multiple of 32)");
  put(c, s, "input_height", input_height, "network input height (px, multiple of 32)");
  put(c, s, "letterbox", letterbox, "keep aspect ratio and pad (true) or stretch");
  put(c, s, "confidence_threshold", confidence_threshold, "report classes with score >= this");
  put(c, s, "nms_threshold", nms_threshold, "per-class NMS IoU threshold");
  put(c, s, "scale", scale, "input = (pixel - mean) * scale / stddev");
  put(c, s, "mean", mean, "per input channel (after swap_rb)");
  put(c, s, "stddev", stddev, "per input channel (after swap_rb)");
  put(c, s, "swap_rb", swap_rb, "feed RGB (true) or BGR (false)");
  put(c, s, "nanodet_cell_offset", nanodet_cell_offset,
      "NanoDet cell centre offset (0.5 NanoDet-m)");
  put(c, s, "backend", backend, "cpu | cuda | cuda_fp16 (OpenCV built with CUDA)");
  put(c, s, "required", required, "missing model files: error (true) or warning");
}

void TDnnDetectorParams::validate(const std::string& s) const {
  requireOneOf(format, {"darknet", "onnx"}, s, "format");
  requireOneOf(layout, {"yolo", "yolov5", "yolov8", "nanodet"}, s, "layout");
  if ((format == "darknet") != (layout == "yolo"))
    throwInputError(keyName(s, "layout"),
                    "'" + layout + "' does not fit format = " + format +
                        " (Darknet models use layout yolo; ONNX models yolov5, yolov8 or nanodet)");
  if (model.empty()) throwInputError(keyName(s, "model"), "empty: expected a model file");
  const std::string extension = lower(fs::path(model).extension().string());
  if ((extension == ".cfg" && format != "darknet") || (extension == ".onnx" && format != "onnx"))
    throwInputError(keyName(s, "model") + " = " + model,
                    "a " + extension + " file does not fit format = " + format +
                        " (preset = " + preset +
                        "; preset = yolo_fastest sets format, layout and input keys for Darknet "
                        "models, nanodet_m for NanoDet-m's ONNX)");
  if (names.empty()) throwInputError(keyName(s, "names"), "empty: expected a class-names file");
  if (format == "darknet" && weights.empty())
    throwInputError(keyName(s, "weights"), "empty: a Darknet model needs its .weights file");
  requireInRange(input_width, 32, 4096, s, "input_width");
  requireInRange(input_height, 32, 4096, s, "input_height");
  if (input_width % 32 || input_height % 32)
    throwInputError(keyName(s, input_width % 32 ? "input_width" : "input_height"),
                    "must be a multiple of 32 (the coarsest stride of these networks)");
  requireInRange(confidence_threshold, 1e-3, 1.0, s, "confidence_threshold");
  requireInRange(nms_threshold, 0.0, 1.0, s, "nms_threshold");
  requireInRange(scale, 1e-9, 1e3, s, "scale");
  cv::Scalar v;
  if (!parseTriple(mean, v))
    throwInputError(keyName(s, "mean"), "'" + mean + "' is not one or three numbers");
  if (!parseTriple(stddev, v) || v[0] <= 0 || v[1] <= 0 || v[2] <= 0)
    throwInputError(keyName(s, "stddev"), "'" + stddev + "' is not one or three positive numbers");
  requireInRange(nanodet_cell_offset, 0.0, 1.0, s, "nanodet_cell_offset");
  requireOneOf(backend, {"cpu", "cuda", "cuda_fp16"}, s, "backend");
}

cv::Scalar TDnnDetectorParams::meanValues() const {
  cv::Scalar v(0, 0, 0);
  parseTriple(mean, v);
  return v;
}
cv::Scalar TDnnDetectorParams::stddevValues() const {
  cv::Scalar v(1, 1, 1);
  parseTriple(stddev, v);
  return v;
}

OutputLayout parseLayout(const std::string& text) {
  if (text == "yolo") return OutputLayout::kDarknetYolo;
  if (text == "yolov5") return OutputLayout::kYoloV5;
  if (text == "yolov8") return OutputLayout::kYoloV8;
  if (text == "nanodet") return OutputLayout::kNanoDet;
  throwInputError("layout '" + text + "'", "unknown, expected yolo, yolov5, yolov8 or nanodet");
}

// ---------------------------------------------------------------------------------------------
// Input transform

cv::Point2f InputTransform::toNet(cv::Point2f p) const {
  return {p.x * scale_x + pad_x, p.y * scale_y + pad_y};
}
cv::Point2f InputTransform::toImage(cv::Point2f p) const {
  return {(p.x - pad_x) / scale_x, (p.y - pad_y) / scale_y};
}
cv::Rect2f InputTransform::boxToImage(const cv::Rect2f& b) const {
  const cv::Point2f tl = toImage(b.tl()), br = toImage(b.br());
  return {tl.x, tl.y, br.x - tl.x, br.y - tl.y};
}

InputTransform makeInputTransform(cv::Size image, cv::Size net, bool letterbox) {
  CV_Assert(image.area() > 0 && net.area() > 0);
  InputTransform t;
  t.net = net;
  if (!letterbox) {
    t.resized = net;
  } else {
    const double r = std::min(double(net.width) / image.width, double(net.height) / image.height);
    t.resized = cv::Size(std::clamp(int(std::lround(image.width * r)), 1, net.width),
                         std::clamp(int(std::lround(image.height * r)), 1, net.height));
    t.pad_x = float((net.width - t.resized.width) / 2);
    t.pad_y = float((net.height - t.resized.height) / 2);
  }
  // The scales the resize really applies (the rounded size over the original).
  t.scale_x = float(t.resized.width) / float(image.width);
  t.scale_y = float(t.resized.height) / float(image.height);
  return t;
}

cv::Mat applyInputTransform(const cv::Mat& bgr, const InputTransform& t) {
  cv::Mat resized = bgr;
  if (bgr.size() != t.resized) cv::resize(bgr, resized, t.resized, 0, 0, cv::INTER_LINEAR);
  if (t.resized == t.net) return resized;
  const int left = int(t.pad_x), top = int(t.pad_y);
  cv::Mat out;
  cv::copyMakeBorder(resized, out, top, t.net.height - t.resized.height - top, left,
                     t.net.width - t.resized.width - left, cv::BORDER_CONSTANT,
                     cv::Scalar(114, 114, 114));
  return out;
}

// ---------------------------------------------------------------------------------------------
// Decoders (IV: each box's independent class probabilities p_{c,d})

std::vector<Detection> decodeDarknetYolo(const std::vector<cv::Mat>& outputs, cv::Size net,
                                         float score_threshold) {
  std::vector<Detection> out;
  for (const cv::Mat& blob : outputs) {
    const int cols = lastDim(blob);
    if (cols < 6) throw std::runtime_error("a Darknet YOLO output has " + shapeText(blob));
    const cv::Mat rows = rowsOf(blob, cols);
    for (int r = 0; r < rows.rows; ++r) {
      const float* p = rows.ptr<float>(r);
      // Columns 5.. already hold objectness * class probability (OpenCV's Region layer).
      auto scores = classesAbove(p + 5, cols - 5, 1, 1.f, score_threshold);
      if (scores.empty()) continue;
      out.push_back(centreBox(p[0] * float(net.width), p[1] * float(net.height),
                              p[2] * float(net.width), p[3] * float(net.height),
                              std::move(scores)));
    }
  }
  return out;
}

std::vector<Detection> decodeYoloV5(const cv::Mat& output, float score_threshold) {
  const int cols = lastDim(output);
  if (cols < 6) throw std::runtime_error("a YOLOv5 output has " + shapeText(output));
  const cv::Mat rows = rowsOf(output, cols);
  std::vector<Detection> out;
  for (int r = 0; r < rows.rows; ++r) {
    const float* p = rows.ptr<float>(r);
    if (p[4] < score_threshold) continue;  // obj * p_c <= obj
    auto scores = classesAbove(p + 5, cols - 5, 1, p[4], score_threshold);
    if (!scores.empty()) out.push_back(centreBox(p[0], p[1], p[2], p[3], std::move(scores)));
  }
  return out;
}

std::vector<Detection> decodeYoloV8(const cv::Mat& output, float score_threshold) {
  const int channels = secondLastDim(output), n = lastDim(output);
  if (channels < 5 || output.total() != std::size_t(channels) * n)
    throw std::runtime_error("a YOLOv8 output has " + shapeText(output));
  const cv::Mat m = rowsOf(output, n);  // [4 + nc, N]: column i is candidate i
  std::vector<Detection> out;
  for (int i = 0; i < n; ++i) {
    const float* col = m.ptr<float>(0) + i;
    auto scores = classesAbove(col + 4 * n, channels - 4, n, 1.f, score_threshold);
    if (!scores.empty())
      out.push_back(centreBox(col[0], col[n], col[2 * n], col[3 * n], std::move(scores)));
  }
  return out;
}

std::vector<Detection> decodeNanoDet(const std::vector<cv::Mat>& outputs, cv::Size net,
                                     int num_classes, float cell_offset, float score_threshold) {
  std::map<int, cv::Mat> scores_by_rows, boxes_by_rows;
  for (const cv::Mat& blob : outputs) {
    const int cols = lastDim(blob);
    const cv::Mat rows = rowsOf(blob, cols);
    if (cols == num_classes)
      scores_by_rows[rows.rows] = rows;
    else if (cols % 4 == 0 && cols >= 8)
      boxes_by_rows[rows.rows] = rows;
    else
      throw std::runtime_error("a NanoDet output has " + shapeText(blob) + " (expected " +
                               std::to_string(num_classes) + " or 4*(reg_max+1) columns)");
  }
  if (scores_by_rows.size() != boxes_by_rows.size() || scores_by_rows.empty())
    throw std::runtime_error("NanoDet outputs do not pair into score and box maps per level");
  std::vector<Detection> out;
  for (const auto& [n_cells, scores] : scores_by_rows) {
    const auto it = boxes_by_rows.find(n_cells);
    if (it == boxes_by_rows.end())
      throw std::runtime_error("no NanoDet box map with " + std::to_string(n_cells) + " rows");
    const cv::Mat& dist = it->second;
    const int bins = dist.cols / 4, stride = nanodetStride(n_cells, net);
    const int grid_w = (net.width + stride - 1) / stride;
    for (int i = 0; i < n_cells; ++i) {
      auto cls = classesAbove(scores.ptr<float>(i), num_classes, 1, 1.f, score_threshold);
      if (cls.empty()) continue;
      const float cx = (float(i % grid_w) + cell_offset) * float(stride);
      const float cy = (float(i / grid_w) + cell_offset) * float(stride);
      const float* d = dist.ptr<float>(i);
      float side[4];  // left, top, right, bottom
      for (int k = 0; k < 4; ++k) side[k] = distributionExpectation(d + k * bins, bins) * stride;
      Detection det;
      det.box = cv::Rect2f(cx - side[0], cy - side[1], side[0] + side[2], side[1] + side[3]);
      det.scores = std::move(cls);
      out.push_back(std::move(det));
    }
  }
  return out;
}

std::vector<Detection> finishDetections(std::vector<Detection> net_detections,
                                        const InputTransform& transform, cv::Size image,
                                        float score_threshold, float nms_threshold) {
  std::vector<Detection> in_image;
  in_image.reserve(net_detections.size());
  for (Detection& d : net_detections) {
    const cv::Rect2f b = transform.boxToImage(d.box);
    const float x0 = std::max(0.f, b.x), y0 = std::max(0.f, b.y);
    const float x1 = std::min(float(image.width), b.x + b.width);
    const float y1 = std::min(float(image.height), b.y + b.height);
    if (!(x1 > x0 && y1 > y0)) continue;
    d.box = cv::Rect2f(x0, y0, x1 - x0, y1 - y0);
    in_image.push_back(std::move(d));
  }
  return suppressPerClass(std::move(in_image), score_threshold, nms_threshold);
}

// ---------------------------------------------------------------------------------------------
// Files and backend

std::vector<std::string> readClassNames(const std::string& path, const std::string& key) {
  std::ifstream f(path);
  if (!f) throwInputError(key + " '" + path + "'", "cannot be opened (expected a names file)");
  std::vector<std::string> names;
  std::string line;
  while (std::getline(f, line)) {
    while (!line.empty() && (line.back() == '\r' || line.back() == ' ')) line.pop_back();
    names.push_back(line);
  }
  while (!names.empty() && names.back().empty()) names.pop_back();
  if (names.empty()) throwInputError(key + " '" + path + "'", "lists no class names");
  return names;
}

std::string modelFileProblem(const TDnnDetectorParams& p, const std::string& section) {
  std::vector<std::pair<std::string, std::string>> files = {{"model", p.model}};
  if (p.format == "darknet") files.emplace_back("weights", p.weights);
  files.emplace_back("names", p.names);
  std::string problems;
  for (const auto& [key, path] : files) {
    std::error_code ec;
    if (fs::is_regular_file(path, ec)) continue;
    std::string what = fs::exists(path, ec) ? "is not a regular file" : "not found";
    if (fs::path(path).is_relative())
      what += " (relative to the working directory " + fs::current_path(ec).string() + ")";
    problems += (problems.empty() ? "" : "; ") + keyName(section, key) + ": file '" + path + "' " +
                what + ": " + howToObtain(path, key);
  }
  return problems;
}

std::string cudaUnavailableReason() {
  if (!cv::dnn::getAvailableTargets(cv::dnn::DNN_BACKEND_CUDA).empty()) return {};
  return std::string("this OpenCV (") + CV_VERSION +
         ") has no CUDA backend in its dnn module (Debian's OpenCV packages are built without "
         "it); use backend = cpu, or build OpenCV with CUDA and cuDNN";
}

// ---------------------------------------------------------------------------------------------
// DnnDetector

DnnDetector::DnnDetector(const TDnnDetectorParams& params, std::string section)
    : m_params(params), m_section(std::move(section)) {
  m_params.validate(m_section);
  if (const std::string problem = modelFileProblem(m_params, m_section); !problem.empty())
    throw InputError(problem);
  m_layout = parseLayout(m_params.layout);
  m_class_names = readClassNames(m_params.names, keyName(m_section, "names"));
  m_mean = m_params.meanValues();
  m_stddev = m_params.stddevValues();
  try {
    m_net = m_params.format == "darknet"
                ? cv::dnn::readNetFromDarknet(m_params.model, m_params.weights)
                : cv::dnn::readNetFromONNX(m_params.model);
  } catch (const cv::Exception& e) {
    throwInputError(keyName(m_section, "model") + " '" + m_params.model + "'",
                    "OpenCV cannot load it as a " + m_params.format + " model: " + e.err);
  }
  if (m_net.empty())
    throwInputError(keyName(m_section, "model") + " '" + m_params.model + "'", "empty network");
  if (m_params.format == "darknet")
    if (const std::string problem = darknetWeightsProblem(m_net, m_params.weights);
        !problem.empty())
      throwInputError(keyName(m_section, "weights") + " '" + m_params.weights + "'",
                      problem + " for the model '" + m_params.model + "'");
  if (m_params.backend == "cpu") {
    m_net.setPreferableBackend(cv::dnn::DNN_BACKEND_OPENCV);
    m_net.setPreferableTarget(cv::dnn::DNN_TARGET_CPU);
  } else {
    if (const std::string why = cudaUnavailableReason(); !why.empty())
      throwInputError(keyName(m_section, "backend") + " = " + m_params.backend, why);
    m_net.setPreferableBackend(cv::dnn::DNN_BACKEND_CUDA);
    m_net.setPreferableTarget(m_params.backend == "cuda" ? cv::dnn::DNN_TARGET_CUDA
                                                         : cv::dnn::DNN_TARGET_CUDA_FP16);
  }
  m_output_names = m_net.getUnconnectedOutLayersNames();

  // One pass on a grey image: allocates the layers and checks the outputs against the layout
  // and the names file, so a mismatch is a configuration error now, not a worker failure later.
  const cv::Size net(m_params.input_width, m_params.input_height);
  std::vector<cv::Mat> outputs;
  auto layoutError = [&](const std::exception& e) {
    std::string shapes;
    for (const auto& o : outputs) shapes += " " + shapeText(o);
    throwInputError(keyName(m_section, "layout") + " = " + m_params.layout,
                    "the model '" + m_params.model + "' (input " + std::to_string(net.width) + "x" +
                        std::to_string(net.height) + ", outputs" + shapes +
                        ") does not run or does not fit this layout: " + e.what());
  };
  int n_classes = 0;
  try {
    outputs = forward(cv::Mat(net, CV_8UC3, cv::Scalar::all(114)), nullptr);
    for (const cv::Mat& o : outputs)
      if (!cv::checkRange(o))
        throw std::runtime_error(
            "the network outputs NaN or infinite numbers on a grey image "
            "(corrupt weights?)");
    n_classes = outputClassCount(outputs);
  } catch (const std::exception& e) {
    layoutError(e);
  }
  if (n_classes != int(m_class_names.size()))
    throwInputError(keyName(m_section, "names") + " '" + m_params.names + "'",
                    "lists " + std::to_string(m_class_names.size()) + " classes but the model '" +
                        m_params.model + "' outputs " + std::to_string(n_classes) +
                        " (read with layout = " + m_params.layout + ")");
  try {
    decode(outputs);
  } catch (const std::exception& e) {
    layoutError(e);
  }
}

int DnnDetector::outputClassCount(const std::vector<cv::Mat>& outputs) const {
  if (outputs.empty()) throw std::runtime_error("the network has no outputs");
  switch (m_layout) {
    case OutputLayout::kDarknetYolo:
    case OutputLayout::kYoloV5:
      return lastDim(outputs.front()) - 5;
    case OutputLayout::kYoloV8:
      return secondLastDim(outputs.front()) - 4;
    case OutputLayout::kNanoDet: {
      // Two column counts: nc (score maps) and 4*(reg_max+1) (distributions, 32 for every
      // released NanoDet). The names file's count when it is one of them, else the other one.
      std::set<int> cols;
      for (const auto& o : outputs) cols.insert(lastDim(o));
      if (cols.size() != 2)
        throw std::runtime_error("expected score maps and distributions (two column counts)");
      if (cols.count(int(m_class_names.size()))) return int(m_class_names.size());
      return *cols.begin() == 32 ? *cols.rbegin() : *cols.begin();
    }
  }
  return 0;
}

std::vector<cv::Mat> DnnDetector::forward(const cv::Mat& bgr, InputTransform* transform) {
  const cv::Size net(m_params.input_width, m_params.input_height);
  const InputTransform t = makeInputTransform(bgr.size(), net, m_params.letterbox);
  const cv::Mat input = applyInputTransform(bgr, t);
  const bool same_factor = m_stddev[0] == m_stddev[1] && m_stddev[1] == m_stddev[2];
  // blobFromImage: (pixel - mean) * factor, channels swapped first when swap_rb.
  cv::Mat blob = cv::dnn::blobFromImage(input, same_factor ? m_params.scale / m_stddev[0] : 1.0,
                                        cv::Size(), m_mean, m_params.swap_rb, false, CV_32F);
  if (!same_factor)
    for (int c = 0; c < 3; ++c) {
      cv::Mat plane(net, CV_32F, blob.ptr<float>(0, c));
      plane *= m_params.scale / m_stddev[c];
    }
  m_net.setInput(blob);
  std::vector<cv::Mat> outputs;
  m_net.forward(outputs, m_output_names);
  if (transform) *transform = t;
  return outputs;
}

std::vector<Detection> DnnDetector::decode(const std::vector<cv::Mat>& outputs) const {
  const float thr = float(m_params.confidence_threshold);
  const cv::Size net(m_params.input_width, m_params.input_height);
  switch (m_layout) {
    case OutputLayout::kDarknetYolo:
      return decodeDarknetYolo(outputs, net, thr);
    case OutputLayout::kYoloV5:
      return decodeYoloV5(outputs.front(), thr);
    case OutputLayout::kYoloV8:
      return decodeYoloV8(outputs.front(), thr);
    case OutputLayout::kNanoDet:
      return decodeNanoDet(outputs, net, int(m_class_names.size()),
                           float(m_params.nanodet_cell_offset), thr);
  }
  return {};
}

std::vector<Detection> DnnDetector::detect(const DetectorInput& input) {
  if (input.bgr.empty() || input.bgr.type() != CV_8UC3)
    throw std::invalid_argument(m_section + ": expected an 8-bit 3-channel BGR image");
  const Clock::time_point t0 = Clock::now();
  InputTransform t;
  const std::vector<cv::Mat> outputs = forward(input.bgr, &t);
  std::vector<Detection> out =
      finishDetections(decode(outputs), t, input.bgr.size(), float(m_params.confidence_threshold),
                       float(m_params.nms_threshold));
  m_last_ms = msSince(t0);
  return out;
}

std::unique_ptr<DnnDetector> makeDnnDetector(const TDnnDetectorParams& given, std::string* warning,
                                             const std::string& section) {
  if (warning) warning->clear();
  if (!given.enabled) return nullptr;
  // The compiled-in defaults ("../shared/data/...") from any working directory.
  TDnnDetectorParams params = given;
  for (std::string* p : {&params.model, &params.weights, &params.names}) *p = resolveSharedData(*p);
  params.validate(section);
  if (const std::string problem = modelFileProblem(params, section); !problem.empty()) {
    if (params.required) throw InputError(problem);
    if (warning)
      *warning = problem + " -- running without this detector (" + keyName(section, "required") +
                 " = false)";
    return nullptr;
  }
  return std::make_unique<DnnDetector>(params, section);
}

}  // namespace rasm::classification
