// The YOLO-family detector of section IV (DnnDetector) on real OpenCV dnn:
//  - real COCO models on Debian's dog.jpg (Yolo-Fastest 1.1 Darknet, NanoDet-m ONNX; skipped when
//    ../shared/data is absent) find the dog, the bicycle and the car/truck in the right places;
//  - tiny networks this test writes itself, a Darknet cfg + weights and two ONNX graphs (the
//    protobuf encoded by hand below: python3-onnx is not installed here, and the test then needs
//    nothing but OpenCV), with chosen weights so the box and classes are known exactly from the
//    formulas of each layout;
//  - the NanoDet decoder on output blobs with known distributions; the letterbox round trip;
//  - configuration errors and missing files named with their INI key.
#include "rasm/classification/DnnDetector.h"

#include <gtest/gtest.h>
#include <mrpt/config/CConfigFileMemory.h>
#include <unistd.h>

#include <cmath>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>
#include <sstream>
#include <string>
#include <type_traits>
#include <vector>

#include "rasm/core/Error.h"
#include "rasm/core/Params.h"

using namespace rasm;
using namespace rasm::classification;
namespace fs = std::filesystem;

namespace {

const std::string kDogJpg = "/usr/share/darknet/data/dog.jpg";
const fs::path kDetectors = fs::path(RASM_SHARED_DATA) / "detectors";

double sigmoid(double x) {
  return 1.0 / (1.0 + std::exp(-x));
}

double iou(const cv::Rect2f& a, const cv::Rect2f& b) {
  const double inter = (a & b).area();
  return inter / (double(a.area()) + double(b.area()) - inter);
}

/// A folder of its own per test process, removed at the end.
class TempDir {
 public:
  TempDir() : m_path(fs::temp_directory_path() / ("rasm_dnn_test_" + std::to_string(::getpid()))) {
    fs::create_directories(m_path);
  }
  ~TempDir() {
    std::error_code ec;
    fs::remove_all(m_path, ec);
  }
  std::string file(const std::string& name) const { return (m_path / name).string(); }

 private:
  fs::path m_path;
};

void writeText(const std::string& path, const std::string& text) {
  std::ofstream f(path, std::ios::binary);
  f << text;
  ASSERT_TRUE(f.good()) << path;
}

// ---- dog.jpg ---------------------------------------------------------------------------------

/// An object of dog.jpg (768x576) and the classes that name it. The boxes are the visible
/// extents read off the image at 2x zoom over a 10 px grid (+-5 px per edge): the dog from its
/// left flank (x 135) and ears (y 220) to its paw (x 307) and tail (y 535); the bicycle from the
/// rear wheel (x 125) and the saddle / handlebar tops (y 140) to the front wheel's right edge
/// (x 565) and bottom (y 420); the white pickup truck from its rear (x 471) and roof (y 75) to its
/// front (x 692) and front wheel (y 170).
struct TrueObject {
  const char* what;
  std::vector<std::string> classes;
  cv::Rect2f box;
};
const std::vector<TrueObject> kDogJpgObjects = {
    {"dog", {"dog"}, {135.f, 220.f, 172.f, 315.f}},
    {"bicycle", {"bicycle"}, {125.f, 140.f, 440.f, 280.f}},
    {"truck", {"car", "truck"}, {471.f, 75.f, 221.f, 95.f}},
};

/// Each object is found: a detection whose best class is one of its names, overlapping its true
/// box by IoU >= 0.5 (the PASCAL VOC criterion of a correct detection). The reading error of the
/// true boxes, +-5 px on each edge, moves the IoU of a box of their sizes by at most 0.10 (the
/// truck, the smallest) and 0.03 for the bicycle of Yolo-Fastest, the detection closest to 0.5.
void expectDogJpgObjects(const std::vector<Detection>& detections,
                         const std::vector<std::string>& names) {
  for (const TrueObject& o : kDogJpgObjects) {
    double best = 0.0;
    for (const Detection& d : detections)
      for (const std::string& cls : o.classes)
        if (names.at(d.bestIndex()) == cls) best = std::max(best, iou(d.box, o.box));
    EXPECT_GE(best, 0.5) << o.what << ": no detection of its class overlaps its true box enough";
  }
}

TEST(DnnDetector, YoloFastestFindsDogBicycleAndTruckInDogJpg) {
  const fs::path dir = kDetectors / "yolo-fastest-1.1-coco";
  if (!fs::exists(dir / "yolo-fastest-1.1.weights") || !fs::exists(kDogJpg))
    GTEST_SKIP() << "needs " << dir << " (../shared/data) and " << kDogJpg << " (package darknet)";
  auto p = TDnnDetectorParams::fromPreset("yolo_fastest");  // Darknet, 320x320 stretched, 1/255 RGB
  p.model = (dir / "yolo-fastest-1.1.cfg").string();
  p.weights = (dir / "yolo-fastest-1.1.weights").string();
  p.names = (dir / "coco.names").string();
  DnnDetector detector(p);
  ASSERT_EQ(detector.classNames().size(), 80u);
  DetectorInput input;
  input.bgr = cv::imread(kDogJpg);
  const auto detections = detector.detect(input);
  expectDogJpgObjects(detections, detector.classNames());
  for (const Detection& d : detections) {
    EXPECT_GE(d.bestScore(), p.confidence_threshold);
    EXPECT_LE(d.bestScore(), 1.f);
    for (std::size_t k = 1; k < d.scores.size(); ++k)
      EXPECT_LE(d.scores[k].score, d.scores[k - 1].score);
    EXPECT_TRUE(cv::Rect2f(0, 0, 768, 576).contains(d.box.tl()));
    EXPECT_LE(d.box.br().x, 768.f);
    EXPECT_LE(d.box.br().y, 576.f);
  }
}

TEST(DnnDetector, NanoDetFindsDogBicycleAndTruckInDogJpg) {
  const fs::path dir = kDetectors / "nanodet-m-320-onnx";
  if (!fs::exists(dir / "nanodet.onnx") || !fs::exists(kDogJpg))
    GTEST_SKIP() << "needs " << dir << " (../shared/data) and " << kDogJpg << " (package darknet)";
  // As the data README says: BGR, mean / std per channel, 320x320; letterboxed as NanoDet's own
  // demos feed it (keep_ratio); stretched, the dog only reaches 0.19.
  TDnnDetectorParams p;
  p.format = "onnx";
  p.layout = "nanodet";
  p.model = (dir / "nanodet.onnx").string();
  p.names = (dir / "coco.names").string();
  p.scale = 1.0;
  p.mean = "103.53 116.28 123.675";
  p.stddev = "57.375 57.12 58.395";
  p.swap_rb = false;
  p.letterbox = true;
  DnnDetector detector(p);
  DetectorInput input;
  input.bgr = cv::imread(kDogJpg);
  expectDogJpgObjects(detector.detect(input), detector.classNames());
}

// ---- a tiny Darknet network ------------------------------------------------------------------

/// A 64x32x3 input, one 1x1 convolution with stride 32 (a 2x1 grid: cells sample input pixels
/// (0, 0) and (32, 0)) into a [yolo] layer with one anchor (16 x 24 px) and 2 classes. Filter
/// outputs: tx, ty, tw, th, objectness, class 0, class 1; only the objectness depends on the
/// pixel (weight 2 per channel, bias -3: logit +3 on white, -3 on black).
struct TinyDarknet {
  static constexpr int kWidth = 64, kHeight = 32;
  static constexpr float kAnchorW = 16.f, kAnchorH = 24.f;
  static constexpr float kBias[7] = {0.5f, -0.25f, 0.2f, -0.1f, -3.f, 1.f, 2.f};
  static constexpr float kObjWeight = 2.f;

  static void write(const std::string& cfg, const std::string& weights) {
    writeText(cfg,
              "[net]\nwidth=64\nheight=32\nchannels=3\n\n"
              "[convolutional]\nfilters=7\nsize=1\nstride=32\npad=0\nactivation=linear\n\n"
              "[yolo]\nmask=0\nanchors=16,24\nclasses=2\nnum=1\n");
    // Darknet weights: major, minor, revision (int32), images seen (uint64 from version 0.2),
    // then per convolution its biases and its weights [filter][channel][ky][kx].
    std::ofstream f(weights, std::ios::binary);
    const std::int32_t header[3] = {0, 2, 0};
    const std::uint64_t seen = 0;
    float w[7 * 3] = {};
    for (int c = 0; c < 3; ++c) w[4 * 3 + c] = kObjWeight;
    f.write(reinterpret_cast<const char*>(header), sizeof header);
    f.write(reinterpret_cast<const char*>(&seen), sizeof seen);
    f.write(reinterpret_cast<const char*>(kBias), sizeof kBias);
    f.write(reinterpret_cast<const char*>(w), sizeof w);
    ASSERT_TRUE(f.good());
  }
};

TEST(DnnDetector, TinyDarknetNetworkDecodesToTheKnownBoxAndClasses) {
  TempDir tmp;
  TinyDarknet::write(tmp.file("tiny.cfg"), tmp.file("tiny.weights"));
  writeText(tmp.file("tiny.names"), "zero\none\n");
  auto p = TDnnDetectorParams::fromPreset("yolo_fastest");  // Darknet, 320x320 stretched, 1/255 RGB
  p.model = tmp.file("tiny.cfg");
  p.weights = tmp.file("tiny.weights");
  p.names = tmp.file("tiny.names");
  p.input_width = TinyDarknet::kWidth;
  p.input_height = TinyDarknet::kHeight;
  p.confidence_threshold = 0.5;
  DnnDetector detector(p);
  ASSERT_EQ(detector.classNames(), (std::vector<std::string>{"zero", "one"}));

  // A 256x96 image stretched to 64x32 (scale 1/4 in x, 1/3 in y): its right half white, so grid
  // cell (1, 0) (input pixel (32, 0) <- image (129.5, 1)) sees white and cell (0, 0) black.
  cv::Mat image(96, 256, CV_8UC3, cv::Scalar::all(0));
  image.colRange(96, 256).setTo(cv::Scalar::all(255));
  DetectorInput input;
  input.bgr = image;
  const auto detections = detector.detect(input);
  ASSERT_EQ(detections.size(), 1u);
  const Detection& d = detections[0];

  // YOLOv3 decoding (cell x = 1 of 2, y = 0 of 1): centre ((x + sig(tx)) / 2, (y + sig(ty)) / 1)
  // of the input, size anchor * exp(t) / input size; scores obj * sig(class logit).
  const double obj = sigmoid(3.0);
  const double cx = (1 + sigmoid(0.5)) / 2 * 64, cy = (0 + sigmoid(-0.25)) * 32;
  const double w = std::exp(0.2) * 16, h = std::exp(-0.1) * 24;
  const double sx = 64.0 / 256, sy = 32.0 / 96;  // image -> input
  const double x0 = std::max(0.0, (cx - w / 2) / sx), y0 = std::max(0.0, (cy - h / 2) / sy);
  const double x1 = std::min(256.0, (cx + w / 2) / sx), y1 = std::min(96.0, (cy + h / 2) / sy);
  const double tol = 1e-3 * 256;  // float arithmetic in OpenCV's Region layer, in image pixels
  EXPECT_NEAR(d.box.x, x0, tol);
  EXPECT_NEAR(d.box.y, y0, tol);
  EXPECT_NEAR(d.box.width, x1 - x0, tol);
  EXPECT_NEAR(d.box.height, y1 - y0, tol);
  ASSERT_EQ(d.scores.size(), 2u);  // obj * sig(2) = 0.84 and obj * sig(1) = 0.70, both >= 0.5
  EXPECT_EQ(d.scores[0].class_index, 1);
  EXPECT_NEAR(d.scores[0].score, obj * sigmoid(2.0), 1e-5);
  EXPECT_EQ(d.scores[1].class_index, 0);
  EXPECT_NEAR(d.scores[1].score, obj * sigmoid(1.0), 1e-5);

  // Above sig(3) * sig(1) only class 1 is reported.
  p.confidence_threshold = 0.75;
  const auto fewer = DnnDetector(p).detect(input);
  ASSERT_EQ(fewer.size(), 1u);
  ASSERT_EQ(fewer[0].scores.size(), 1u);
  EXPECT_EQ(fewer[0].bestIndex(), 1);
}

TEST(DnnDetector, NamesFileWithTheWrongClassCountIsAnError) {
  TempDir tmp;
  TinyDarknet::write(tmp.file("tiny.cfg"), tmp.file("tiny.weights"));
  writeText(tmp.file("three.names"), "a\nb\nc\n");
  auto p = TDnnDetectorParams::fromPreset("yolo_fastest");  // Darknet, 320x320 stretched, 1/255 RGB
  p.model = tmp.file("tiny.cfg");
  p.weights = tmp.file("tiny.weights");
  p.names = tmp.file("three.names");
  p.input_width = TinyDarknet::kWidth;
  p.input_height = TinyDarknet::kHeight;
  try {
    DnnDetector detector(p);
    FAIL() << "expected InputError";
  } catch (const InputError& e) {
    const std::string msg = e.what();
    EXPECT_NE(msg.find("[dnn_detector] names"), std::string::npos) << msg;
    EXPECT_NE(msg.find("three.names"), std::string::npos) << msg;
    EXPECT_NE(msg.find("lists 3 classes"), std::string::npos) << msg;
    EXPECT_NE(msg.find("outputs 2"), std::string::npos) << msg;
  }
}

// ---- tiny ONNX networks ----------------------------------------------------------------------

/// The protocol-buffer wire format, just enough of it to write a small ONNX model.
class Proto {
 public:
  Proto& varint(int field, std::uint64_t v) {
    tag(field, 0);
    raw(v);
    return *this;
  }
  Proto& bytes(int field, const std::string& s) {
    tag(field, 2);
    raw(s.size());
    m_bytes += s;
    return *this;
  }
  Proto& message(int field, const Proto& m) { return bytes(field, m.m_bytes); }
  const std::string& str() const { return m_bytes; }

 private:
  void tag(int field, int wire) { raw((std::uint64_t(field) << 3) | std::uint64_t(wire)); }
  void raw(std::uint64_t v) {
    for (; v >= 0x80; v >>= 7) m_bytes += char((v & 0x7f) | 0x80);
    m_bytes += char(v);
  }
  std::string m_bytes;
};

// Field numbers of onnx.proto: TensorProto dims 1, data_type 2, name 8, raw_data 9;
// AttributeProto name 1, ints 8, type 20; NodeProto input 1, output 2, name 3, op_type 4,
// attribute 5; ValueInfoProto name 1, type 2 (TypeProto.tensor_type 1: elem_type 1, shape 2,
// shape.dim 1, dim_value 1); GraphProto node 1, name 2, initializer 5, input 11, output 12;
// ModelProto ir_version 1, producer_name 2, graph 7, opset_import 8 (domain 1, version 2).
template <typename T>
Proto tensorProto(const std::string& name, const std::vector<std::int64_t>& dims,
                  const std::vector<T>& values) {
  Proto t;
  for (auto d : dims) t.varint(1, std::uint64_t(d));
  t.varint(2, std::is_same_v<T, float> ? 1 : 7);  // FLOAT or INT64
  t.bytes(8, name);
  t.bytes(9, std::string(reinterpret_cast<const char*>(values.data()), values.size() * sizeof(T)));
  return t;
}
Proto intsAttribute(const std::string& name, const std::vector<std::int64_t>& values) {
  Proto a;
  a.bytes(1, name);
  for (auto v : values) a.varint(8, std::uint64_t(v));
  a.varint(20, 7);  // INTS
  return a;
}
Proto nodeProto(const std::string& op, const std::vector<std::string>& inputs,
                const std::string& output, const std::vector<Proto>& attributes = {}) {
  Proto n;
  for (const auto& i : inputs) n.bytes(1, i);
  n.bytes(2, output).bytes(3, op + "_" + output).bytes(4, op);
  for (const auto& a : attributes) n.message(5, a);
  return n;
}
Proto floatTensorInfo(const std::string& name, const std::vector<std::int64_t>& dims) {
  Proto shape;
  for (auto d : dims) shape.message(1, Proto().varint(1, std::uint64_t(d)));
  Proto tensor_type;
  tensor_type.varint(1, 1).message(2, shape);
  return Proto().bytes(1, name).message(2, Proto().message(1, tensor_type));
}

/// [1, 3, 64, 64] -> Conv 1x1, stride 32, 7 filters -> [1, 7, 2, 2] -> Reshape [1, 7, 4]: the
/// YOLOv8 layout [1, 4 + nc, N] with nc = 3, candidate i = cell (i % 2, i / 2); with a Transpose
/// [0, 2, 1] after it, the YOLOv5 layout [1, N, 5 + nc] with nc = 2. Every filter f computes
/// bias_f + slope_f * (r + g + b) of the pixel its cell samples (input scaled to 0..1).
std::string tinyOnnxModel(bool yolov5) {
  const std::vector<float> bias = {40.f, 37.f, 20.f, 12.f, -0.6f, -0.1f, -0.2f};
  const std::vector<float> slope = {1.f, 1.f, 0.f, 0.f, 0.5f, 0.2f, 0.3f};
  std::vector<float> weights(7 * 3);
  for (int f = 0; f < 7; ++f)
    for (int c = 0; c < 3; ++c) weights[f * 3 + c] = slope[f];
  Proto graph;
  graph.message(
      1, nodeProto("Conv", {"images", "W", "B"}, "conv",
                   {intsAttribute("kernel_shape", {1, 1}), intsAttribute("strides", {32, 32})}));
  graph.message(1, nodeProto("Reshape", {"conv", "shape"}, yolov5 ? "grid" : "output"));
  if (yolov5)
    graph.message(1,
                  nodeProto("Transpose", {"grid"}, "output", {intsAttribute("perm", {0, 2, 1})}));
  graph.bytes(2, "tiny");
  graph.message(5, tensorProto<float>("W", {7, 3, 1, 1}, weights));
  graph.message(5, tensorProto<float>("B", {7}, bias));
  graph.message(5, tensorProto<std::int64_t>("shape", {3}, {1, 7, 4}));
  graph.message(11, floatTensorInfo("images", {1, 3, 64, 64}));
  graph.message(12, floatTensorInfo("output", yolov5 ? std::vector<std::int64_t>{1, 4, 7}
                                                     : std::vector<std::int64_t>{1, 7, 4}));
  Proto model;
  model.varint(1, 7).bytes(2, "rasm DnnDetector_unittest").message(7, graph);
  model.message(8, Proto().bytes(1, "").varint(2, 11));
  return model.str();
}

/// The image both ONNX tests feed: 128x64, letterboxed into 64x64 (scale 1/2, 16 px of grey 114
/// above and below). White where x >= 40 and y >= 20, black elsewhere, so of the four cells'
/// sample pixels (0, 0), (32, 0) (padding: grey), (0, 32) (image (0.5, 32.5): black) and
/// (32, 32) (image (64.5, 32.5): white) only candidate 3 sees white: r + g + b = 3 there,
/// 3 * 114 / 255 on grey, 0 on black.
cv::Mat tinyOnnxImage() {
  cv::Mat image(64, 128, CV_8UC3, cv::Scalar::all(0));
  image(cv::Rect(40, 20, 88, 44)).setTo(cv::Scalar::all(255));
  return image;
}

TDnnDetectorParams tinyOnnxParams(const std::string& model, const std::string& names,
                                  const std::string& layout) {
  // The YOLO input normalisation (1/255, no mean, RGB) on an ONNX model.
  auto p = TDnnDetectorParams::fromPreset("yolo_fastest");
  p.format = "onnx";
  p.weights.clear();
  p.layout = layout;
  p.model = model;
  p.names = names;
  p.input_width = p.input_height = 64;
  p.letterbox = true;
  return p;
}

/// Candidate 3's box: centre (40 + 3, 37 + 3), size 20 x 12 input pixels -> image pixels through
/// the letterbox (x / 0.5, (y - 16) / 0.5).
void expectTinyOnnxBox(const cv::Rect2f& box) {
  const double x0 = (43.0 - 10.0) / 0.5, y0 = (40.0 - 6.0 - 16.0) / 0.5;
  const double tol = 1e-3;  // float sums of exactly representable values
  EXPECT_NEAR(box.x, x0, tol);
  EXPECT_NEAR(box.y, y0, tol);
  EXPECT_NEAR(box.width, 20.0 / 0.5, tol);
  EXPECT_NEAR(box.height, 12.0 / 0.5, tol);
}

TEST(DnnDetector, TinyOnnxYoloV5NetworkDecodesToTheKnownBoxAndClasses) {
  TempDir tmp;
  writeText(tmp.file("v5.onnx"), tinyOnnxModel(true));
  writeText(tmp.file("two.names"), "zero\none\n");
  DnnDetector detector(tinyOnnxParams(tmp.file("v5.onnx"), tmp.file("two.names"), "yolov5"));
  DetectorInput input;
  input.bgr = tinyOnnxImage();
  const auto detections = detector.detect(input);
  ASSERT_EQ(detections.size(), 1u);
  expectTinyOnnxBox(detections[0].box);
  // White: objectness -0.6 + 0.5 * 3 = 0.9, class 0: -0.1 + 0.6 = 0.5, class 1: -0.2 + 0.9 = 0.7;
  // scores obj * p = 0.63 and 0.45 (grey: obj 0.07, black: obj < 0: below 0.25).
  ASSERT_EQ(detections[0].scores.size(), 2u);
  EXPECT_EQ(detections[0].scores[0].class_index, 1);
  EXPECT_NEAR(detections[0].scores[0].score, 0.9 * 0.7, 1e-5);
  EXPECT_EQ(detections[0].scores[1].class_index, 0);
  EXPECT_NEAR(detections[0].scores[1].score, 0.9 * 0.5, 1e-5);
}

TEST(DnnDetector, TinyOnnxYoloV8NetworkDecodesToTheKnownBoxAndClasses) {
  TempDir tmp;
  writeText(tmp.file("v8.onnx"), tinyOnnxModel(false));
  writeText(tmp.file("three.names"), "zero\none\ntwo\n");
  DnnDetector detector(tinyOnnxParams(tmp.file("v8.onnx"), tmp.file("three.names"), "yolov8"));
  DetectorInput input;
  input.bgr = tinyOnnxImage();
  const auto detections = detector.detect(input);
  ASSERT_EQ(detections.size(), 1u);
  expectTinyOnnxBox(detections[0].box);
  // White: class scores 0.9, 0.5, 0.7 (no objectness); grey at most 0.2 (class 2), black < 0.
  ASSERT_EQ(detections[0].scores.size(), 3u);
  const int order[3] = {0, 2, 1};
  const double score[3] = {0.9, 0.7, 0.5};
  for (int k = 0; k < 3; ++k) {
    EXPECT_EQ(detections[0].scores[k].class_index, order[k]);
    EXPECT_NEAR(detections[0].scores[k].score, score[k], 1e-5);
  }
}

// ---- decoders on hand-made output blobs ------------------------------------------------------

TEST(DnnDetector, NanoDetDecoderReadsDistributionsAndPairsLevelsByRowCount) {
  // 64x64 input, strides 8 / 16 / 32 -> 64 / 16 / 4 cells, 2 classes, reg_max 7 (8 bins).
  const cv::Size net(64, 64);
  std::vector<cv::Mat> outputs;
  for (int cells : {4, 64, 16}) outputs.push_back(cv::Mat::zeros(cells, 2, CV_32F));
  for (int cells : {16, 4, 64}) outputs.push_back(cv::Mat::zeros(cells, 32, CV_32F));
  // Stride 16, cell (x 2, y 1) = row 1 * 4 + 2: class 1 with 0.8, class 0 with 0.3.
  cv::Mat& scores16 = outputs[2];
  cv::Mat& dist16 = outputs[3];
  scores16.at<float>(6, 1) = 0.8f;
  scores16.at<float>(6, 0) = 0.3f;
  // Distributions (logits): left: bins 1 and 2 equal, the rest far below -> 1.5 bins; top: bin 1
  // -> 1; right: bin 2 -> 2; bottom: all equal -> 3.5. Distances = bins * stride 16.
  float* d = dist16.ptr<float>(6);
  for (int k = 0; k < 3; ++k)
    for (int j = 0; j < 8; ++j) d[k * 8 + j] = -60.f;
  d[0 * 8 + 1] = d[0 * 8 + 2] = 0.f;
  d[1 * 8 + 1] = 0.f;
  d[2 * 8 + 2] = 0.f;
  const auto dets = decodeNanoDet(outputs, net, 2, 0.5f, 0.25f);
  ASSERT_EQ(dets.size(), 1u);
  // Cell centre ((2 + 0.5) * 16, (1 + 0.5) * 16) = (40, 24).
  const double left = 1.5 * 16, top = 16, right = 2 * 16, bottom = 3.5 * 16;
  EXPECT_NEAR(dets[0].box.x, 40 - left, 1e-4);
  EXPECT_NEAR(dets[0].box.y, 24 - top, 1e-4);
  EXPECT_NEAR(dets[0].box.width, left + right, 1e-4);
  EXPECT_NEAR(dets[0].box.height, top + bottom, 1e-4);
  ASSERT_EQ(dets[0].scores.size(), 2u);
  EXPECT_EQ(dets[0].scores[0].class_index, 1);
  EXPECT_FLOAT_EQ(dets[0].scores[0].score, 0.8f);
  EXPECT_FLOAT_EQ(dets[0].scores[1].score, 0.3f);
  // NanoDet-Plus puts the centre on the cell corner: 8 px to the upper left.
  const auto plus = decodeNanoDet(outputs, net, 2, 0.f, 0.25f);
  ASSERT_EQ(plus.size(), 1u);
  EXPECT_NEAR(plus[0].box.x, 40 - 8 - left, 1e-4);
  EXPECT_NEAR(plus[0].box.y, 24 - 8 - top, 1e-4);
}

TEST(DnnDetector, FinishDetectionsUndoesTheTransformClipsAndSuppresses) {
  const InputTransform t = makeInputTransform({640, 480}, {320, 320}, true);  // 1/2, pad_y 40
  std::vector<Detection> net(3);
  net[0].box = {10.f, 50.f, 100.f, 60.f};  // image (20, 20, 200, 120)
  net[0].scores = {{2, 0.9f}};
  net[1].box = {12.f, 52.f, 100.f, 60.f};  // the same object, weaker: suppressed
  net[1].scores = {{2, 0.6f}};
  net[2].box = {300.f, 20.f, 40.f, 40.f};  // image (600, -40, 80, 80) -> clipped (600, 0, 40, 40)
  net[2].scores = {{5, 0.5f}};
  const auto out = finishDetections(net, t, {640, 480}, 0.25f, 0.45f);
  ASSERT_EQ(out.size(), 2u);
  EXPECT_EQ(out[0].bestIndex(), 2);
  EXPECT_NEAR(out[0].box.x, 20.f, 1e-4);
  EXPECT_NEAR(out[0].box.y, 20.f, 1e-4);
  EXPECT_NEAR(out[0].box.width, 200.f, 1e-4);
  EXPECT_NEAR(out[0].box.height, 120.f, 1e-4);
  EXPECT_EQ(out[1].bestIndex(), 5);
  EXPECT_NEAR(out[1].box.x, 600.f, 1e-4);
  EXPECT_NEAR(out[1].box.y, 0.f, 1e-4);
  EXPECT_NEAR(out[1].box.width, 40.f, 1e-4);
  EXPECT_NEAR(out[1].box.height, 40.f, 1e-4);
}

// ---- the letterbox ---------------------------------------------------------------------------

TEST(DnnDetector, LetterboxRoundTripIsExactAndMatchesTheResizedPixels) {
  struct Case {
    cv::Size image, net;
    bool letterbox;
  };
  for (const Case& c : {Case{{640, 480}, {320, 320}, true}, Case{{333, 250}, {320, 320}, true},
                        Case{{250, 333}, {416, 320}, true}, Case{{768, 576}, {320, 320}, false}}) {
    const InputTransform t = makeInputTransform(c.image, c.net, c.letterbox);
    // The image fills the input (letterbox: along one axis) and sits centred.
    if (c.letterbox) {
      EXPECT_TRUE(t.resized.width == c.net.width || t.resized.height == c.net.height);
      EXPECT_NEAR(t.pad_x, (c.net.width - t.resized.width) / 2, 0.0);
      EXPECT_NEAR(t.pad_y, (c.net.height - t.resized.height) / 2, 0.0);
    } else {
      EXPECT_EQ(t.resized, c.net);
    }
    for (const cv::Point2f p : {cv::Point2f(0, 0), cv::Point2f(17.25f, 99.5f),
                                cv::Point2f(float(c.image.width), float(c.image.height))}) {
      const cv::Point2f back = t.toImage(t.toNet(p));
      EXPECT_NEAR(back.x, p.x, 1e-3);
      EXPECT_NEAR(back.y, p.y, 1e-3);
    }
    // The image's corners land on the resized area's corners.
    EXPECT_NEAR(t.toNet({0, 0}).x, t.pad_x, 1e-4);
    EXPECT_NEAR(t.toNet(cv::Point2f(float(c.image.width), float(c.image.height))).x,
                t.pad_x + t.resized.width, 1e-3);
    EXPECT_NEAR(t.toNet(cv::Point2f(float(c.image.width), float(c.image.height))).y,
                t.pad_y + t.resized.height, 1e-3);

    // A white rectangle (image pixels [60, 140) x [40, 120)) appears in the input where toNet
    // puts it, to within the one pixel of bilinear blur at its edges.
    cv::Mat image(c.image, CV_8UC3, cv::Scalar::all(0));
    const cv::Rect2f rect(60.f, 40.f, 80.f, 80.f);
    image(cv::Rect(rect)).setTo(cv::Scalar::all(255));
    const cv::Mat input = applyInputTransform(image, t);
    ASSERT_EQ(input.size(), c.net);
    cv::Mat white;
    cv::inRange(input, cv::Scalar::all(128), cv::Scalar::all(255), white);
    const cv::Rect found = cv::boundingRect(white);
    const cv::Point2f tl = t.toNet(rect.tl()), br = t.toNet(rect.br());
    EXPECT_NEAR(found.x, tl.x, 1.0);
    EXPECT_NEAR(found.y, tl.y, 1.0);
    EXPECT_NEAR(found.x + found.width, br.x, 1.0);
    EXPECT_NEAR(found.y + found.height, br.y, 1.0);
    if (c.letterbox && t.pad_y >= 1) {
      EXPECT_EQ(input.at<cv::Vec3b>(0, c.net.width / 2), cv::Vec3b(114, 114, 114));
    }
  }
}

// ---- configuration and files -----------------------------------------------------------------

TEST(DnnDetector, MissingWeightsAreNamedWithTheirKeyAndHowToGetThem) {
  TempDir tmp;
  TinyDarknet::write(tmp.file("yolov3.cfg"), tmp.file("unused.weights"));
  writeText(tmp.file("two.names"), "zero\none\n");
  auto p = TDnnDetectorParams::fromPreset("yolo_fastest");  // Darknet, 320x320 stretched, 1/255 RGB
  p.model = tmp.file("yolov3.cfg");
  p.weights = tmp.file("missing/yolov3.weights");
  p.names = tmp.file("two.names");
  p.input_width = TinyDarknet::kWidth;
  p.input_height = TinyDarknet::kHeight;

  p.required = true;
  try {
    makeDnnDetector(p, nullptr);
    FAIL() << "expected InputError";
  } catch (const InputError& e) {
    const std::string msg = e.what();
    EXPECT_NE(msg.find("[dnn_detector] weights"), std::string::npos) << msg;
    EXPECT_NE(msg.find(p.weights), std::string::npos) << msg;
    EXPECT_NE(msg.find("user supplied"), std::string::npos) << msg;
    EXPECT_EQ(msg.find("[dnn_detector] model"), std::string::npos) << msg;  // the cfg exists
  }
  EXPECT_THROW(DnnDetector{p}, InputError);

  p.required = false;
  std::string warning;
  EXPECT_EQ(makeDnnDetector(p, &warning), nullptr);
  EXPECT_NE(warning.find("[dnn_detector] weights"), std::string::npos) << warning;
  EXPECT_NE(warning.find(p.weights), std::string::npos) << warning;
  EXPECT_NE(warning.find("running without this detector"), std::string::npos) << warning;

  // A missing Yolo-Fastest file points at the shared data folder.
  p.weights = tmp.file("yolo-fastest-1.1.weights");
  EXPECT_NE(modelFileProblem(p).find("../shared/data/detectors/yolo-fastest-1.1-coco/"),
            std::string::npos);

  // A model file OpenCV cannot parse is an error naming the key and the file.
  writeText(tmp.file("garbage.onnx"), "not a protobuf");
  TDnnDetectorParams onnx = tinyOnnxParams(tmp.file("garbage.onnx"), p.names, "yolov5");
  try {
    DnnDetector detector(onnx);
    FAIL() << "expected InputError";
  } catch (const InputError& e) {
    const std::string msg = e.what();
    EXPECT_NE(msg.find("[dnn_detector] model"), std::string::npos) << msg;
    EXPECT_NE(msg.find("garbage.onnx"), std::string::npos) << msg;
  }

  // Disabled: no detector and no warning.
  p.enabled = false;
  EXPECT_EQ(makeDnnDetector(p, &warning), nullptr);
  EXPECT_TRUE(warning.empty());
}

std::string loadError(const std::string& ini) {
  mrpt::config::CConfigFileMemory cfg;
  cfg.setContent(ini);
  TDnnDetectorParams p;
  try {
    loadParamsStrict(cfg, "dnn_detector", p, "test.ini");
  } catch (const InputError& e) {
    return e.what();
  }
  return {};
}

TEST(DnnDetector, IniKeysAreLoadedStrictlyAndValidated) {
  mrpt::config::CConfigFileMemory cfg;
  cfg.setContent(
      "[dnn_detector]\nformat = onnx\nlayout = nanodet\nmodel = a.onnx\nnames = a.names\n"
      "input_width = 416\nletterbox = true\nmean = 103.53, 116.28, 123.675\nstddev = 57.4\n"
      "swap_rb = false\nscale = 1\n");
  TDnnDetectorParams p;
  loadParamsStrict(cfg, "dnn_detector", p, "test.ini");
  EXPECT_EQ(p.layout, "nanodet");
  EXPECT_EQ(p.input_width, 416);
  EXPECT_EQ(p.input_height, 320);
  EXPECT_TRUE(p.letterbox);
  EXPECT_EQ(p.meanValues(), cv::Scalar(103.53, 116.28, 123.675));
  EXPECT_EQ(p.stddevValues(), cv::Scalar(57.4, 57.4, 57.4));

  const std::string unknown = loadError("[dnn_detector]\nconfidence = 0.3\n");
  EXPECT_NE(unknown.find("[dnn_detector] confidence"), std::string::npos) << unknown;
  const std::string layout = loadError("[dnn_detector]\nlayout = yolox\n");
  EXPECT_NE(layout.find("[dnn_detector] layout"), std::string::npos) << layout;
  EXPECT_NE(layout.find("yolox"), std::string::npos) << layout;
  const std::string mismatch = loadError("[dnn_detector]\nformat = darknet\n");  // layout nanodet
  EXPECT_NE(mismatch.find("[dnn_detector] layout"), std::string::npos) << mismatch;
  const std::string size = loadError("[dnn_detector]\ninput_width = 300\n");
  EXPECT_NE(size.find("[dnn_detector] input_width"), std::string::npos) << size;
  EXPECT_NE(size.find("multiple of 32"), std::string::npos) << size;
  const std::string thr = loadError("[dnn_detector]\nconfidence_threshold = 1.5\n");
  EXPECT_NE(thr.find("[dnn_detector] confidence_threshold"), std::string::npos) << thr;
  const std::string stddev = loadError("[dnn_detector]\nstddev = 1 0 1\n");
  EXPECT_NE(stddev.find("[dnn_detector] stddev"), std::string::npos) << stddev;
  const std::string backend = loadError("[dnn_detector]\nbackend = gpu\n");
  EXPECT_NE(backend.find("[dnn_detector] backend"), std::string::npos) << backend;
}

TEST(DnnDetector, PresetFillsTheModelKeysAndKeysBesideItOverrideIt) {
  TDnnDetectorParams by_default;  // NanoDet-m, the default for real data
  EXPECT_EQ(by_default.preset, "nanodet_m");
  EXPECT_EQ(by_default.format, "onnx");
  EXPECT_EQ(by_default.layout, "nanodet");
  EXPECT_TRUE(by_default.letterbox);
  EXPECT_NE(by_default.model.find("nanodet-m-320-onnx/nanodet.onnx"), std::string::npos);
  EXPECT_NO_THROW(by_default.validate());

  mrpt::config::CConfigFileMemory cfg;
  cfg.setContent("[dnn_detector]\npreset = yolo_fastest\nconfidence_threshold = 0.3\n");
  TDnnDetectorParams yolo;
  loadParamsStrict(cfg, "dnn_detector", yolo, "test.ini");
  const auto reference = TDnnDetectorParams::fromPreset("yolo_fastest");
  EXPECT_EQ(yolo.format, "darknet");
  EXPECT_EQ(yolo.layout, "yolo");
  EXPECT_FALSE(yolo.letterbox);
  EXPECT_TRUE(yolo.swap_rb);
  EXPECT_DOUBLE_EQ(yolo.scale, 1.0 / 255.0);
  EXPECT_EQ(yolo.model, reference.model);
  EXPECT_EQ(yolo.weights, reference.weights);
  EXPECT_DOUBLE_EQ(yolo.confidence_threshold, 0.3);  // not a preset key: kept

  // A key beside the preset wins; the saved section reloads to the same params.
  cfg.setContent("[dnn_detector]\npreset = yolo_fastest\ninput_width = 416\n");
  TDnnDetectorParams wider;
  loadParamsStrict(cfg, "dnn_detector", wider, "test.ini");
  EXPECT_EQ(wider.input_width, 416);
  mrpt::config::CConfigFileMemory saved;
  wider.saveToConfigFile(saved, "dnn_detector");
  TDnnDetectorParams reloaded;
  reloaded.loadFromConfigFile(saved, "dnn_detector");
  EXPECT_EQ(reloaded.input_width, 416);
  EXPECT_EQ(reloaded.format, "darknet");
  EXPECT_EQ(reloaded.model, wider.model);

  const std::string unknown = loadError("[dnn_detector]\npreset = yolov9\n");
  EXPECT_NE(unknown.find("[dnn_detector] preset"), std::string::npos) << unknown;
  EXPECT_NE(unknown.find("yolov9"), std::string::npos) << unknown;
  // A Darknet cfg under the default (ONNX) preset is named, with the preset that fits it.
  const std::string cfg_file = loadError("[dnn_detector]\nmodel = my.cfg\n");
  EXPECT_NE(cfg_file.find("[dnn_detector] model = my.cfg"), std::string::npos) << cfg_file;
  EXPECT_NE(cfg_file.find("yolo_fastest"), std::string::npos) << cfg_file;
}

TEST(DnnDetector, CudaBackendWithoutCudaInOpenCvIsAnErrorThatSaysSo) {
  const std::string why = cudaUnavailableReason();
  if (why.empty()) GTEST_SKIP() << "this OpenCV has a CUDA dnn backend";
  TempDir tmp;
  TinyDarknet::write(tmp.file("tiny.cfg"), tmp.file("tiny.weights"));
  writeText(tmp.file("two.names"), "zero\none\n");
  auto p = TDnnDetectorParams::fromPreset("yolo_fastest");  // Darknet, 320x320 stretched, 1/255 RGB
  p.model = tmp.file("tiny.cfg");
  p.weights = tmp.file("tiny.weights");
  p.names = tmp.file("two.names");
  p.input_width = TinyDarknet::kWidth;
  p.input_height = TinyDarknet::kHeight;
  p.backend = "cuda";
  try {
    DnnDetector detector(p);
    FAIL() << "expected InputError";
  } catch (const InputError& e) {
    const std::string msg = e.what();
    EXPECT_NE(msg.find("[dnn_detector] backend"), std::string::npos) << msg;
    EXPECT_NE(msg.find("no CUDA backend"), std::string::npos) << msg;
  }
}

}  // namespace

// ---- weights that do not fit the network ------------------------------------------------------

/// OpenCV reads a truncated .weights file, or the weights of another network, without a word;
/// the detector then found nothing, with exit 0, even with required = true. The file size is
/// checked against the network of the .cfg.
TEST(DnnDetector, TruncatedOrForeignDarknetWeightsAreAnError) {
  TempDir tmp;
  TinyDarknet::write(tmp.file("tiny.cfg"), tmp.file("tiny.weights"));
  writeText(tmp.file("tiny.names"), "zero\none\n");
  std::string bytes;
  {
    std::ifstream f(tmp.file("tiny.weights"), std::ios::binary);
    std::stringstream ss;
    ss << f.rdbuf();
    bytes = ss.str();
  }
  ASSERT_EQ(bytes.size(), 20u + 4u * 28u);
  auto p = TDnnDetectorParams::fromPreset("yolo_fastest");  // Darknet, 320x320 stretched, 1/255 RGB
  p.model = tmp.file("tiny.cfg");
  p.names = tmp.file("tiny.names");
  p.input_width = TinyDarknet::kWidth;
  p.input_height = TinyDarknet::kHeight;
  p.required = true;
  const auto expectError = [&](const std::string& weights, const std::string& what) {
    p.weights = tmp.file(weights);
    try {
      DnnDetector detector(p);
      ADD_FAILURE() << weights << ": no error";
    } catch (const InputError& e) {
      const std::string msg = e.what();
      EXPECT_NE(msg.find("[dnn_detector] weights '" + p.weights + "'"), std::string::npos) << msg;
      EXPECT_NE(msg.find("needs 132"), std::string::npos) << msg;
      EXPECT_NE(msg.find(what), std::string::npos) << msg;
    }
  };
  writeText(tmp.file("truncated.weights"), bytes.substr(0, bytes.size() - 16));
  expectError("truncated.weights", "a truncated file");
  writeText(tmp.file("foreign.weights"), bytes + std::string(64, '\0'));
  expectError("foreign.weights", "the weights of another network");
  p.weights = tmp.file("tiny.weights");
  EXPECT_NO_THROW(DnnDetector{p});
}

TEST(DnnDetector, YoloFastestWithTheXlWeightsIsAnError) {
  const fs::path dir = fs::path(RASM_SHARED_DATA) / "detectors/yolo-fastest-1.1-coco";
  if (!fs::exists(dir / "yolo-fastest-1.1-xl.weights")) GTEST_SKIP() << "no " << dir;
  auto p = TDnnDetectorParams::fromPreset("yolo_fastest");  // Darknet, 320x320 stretched, 1/255 RGB
  p.model = (dir / "yolo-fastest-1.1.cfg").string();
  p.weights = (dir / "yolo-fastest-1.1-xl.weights").string();
  p.names = (dir / "coco.names").string();
  try {
    DnnDetector detector(p);
    FAIL() << "no error";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("the weights of another network"), std::string::npos)
        << e.what();
  }
  p.weights = (dir / "yolo-fastest-1.1.weights").string();
  EXPECT_NO_THROW(DnnDetector{p});
}
