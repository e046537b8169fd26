#pragma once
// The YOLO-family 2-D detector of section IV on OpenCV's dnn module: Darknet cfg + weights
// (YOLOv3, YOLOv3-tiny, YOLOv4, Yolo-Fastest) and ONNX models (NanoDet-m, YOLOv5 / YOLOv8 output
// layouts). The paper runs YOLO on the GPU beside the CPU zero-shot classifier (IV, VI); each box
// carries independent per-class probabilities p_{c,d} in [0, 1] that the map fuses with the Bayes
// rule of IV. docs/classification.md "DNN detector" lists models, layouts and keys (timings:
// docs/results.md and docs/history/classification.md).
//
// One call: image -> network input (stretch or letterbox, InputTransform) -> forward -> decode the
// layout into boxes in network-input pixels (decode* below, free functions so tests drive them on
// hand-made output blobs) -> back to image pixels, classes >= threshold, per-class NMS
// (finishDetections).

#include <mrpt/config/CLoadableOptions.h>

#include <memory>
#include <opencv2/core.hpp>
#include <opencv2/dnn/dnn.hpp>
#include <string>
#include <vector>

#include "rasm/classification/Detection.h"
#include "rasm/classification/Detector.h"

namespace rasm::classification {

/// [dnn_detector]. Relative paths are relative to the working directory (an INI's to its folder).
/// `preset` names a model of the shared data folder next to the source tree ("../shared/data/...",
/// which makeDnnDetector looks up in rasm::sharedDataFolders() when it is not there relative to
/// the working directory: the compiled-in folder, $RASM_SHARED_DATA) and fills in every key that
/// describes it (format, files, layout, input size and normalisation); keys given beside it
/// override it. The default is NanoDet-m, the best COCO detector the project has that runs on
/// 2 cores (docs/classification.md "Which detector").
struct TDnnDetectorParams : mrpt::config::CLoadableOptions {
  bool enabled = true;
  /// nanodet_m (NanoDet-m 320, ONNX) | yolo_fastest (Yolo-Fastest 1.1, Darknet).
  std::string preset = "nanodet_m";
  /// darknet: `model` is the .cfg and `weights` the .weights; onnx: `model` is the .onnx file
  /// (`weights` unused).
  std::string format = "onnx";
  std::string model = "../shared/data/detectors/nanodet-m-320-onnx/nanodet.onnx";
  std::string weights;
  /// Class names, one per line: line k names class index k.
  std::string names = "../shared/data/detectors/nanodet-m-320-onnx/coco.names";
  /// How to read the outputs: yolo (Darknet [yolo] layers through OpenCV: rows [cx cy w h] in
  /// 0..1 of the input, objectness, obj * class probability), yolov5 ([1 N 5+nc]: cx cy w h in
  /// input pixels, objectness, class probabilities), yolov8 ([1 4+nc N]: cx cy w h in input
  /// pixels, class probabilities), nanodet (NanoDet-m GFL heads: per level an nc-column score map
  /// and a 4*(reg_max+1)-column side distribution, matched by row count).
  std::string layout = "nanodet";
  int input_width = 320;
  int input_height = 320;
  /// true: keep the aspect ratio and pad (grey 114, centred; YOLOv5/v8, NanoDet-m: stretched,
  /// it gives a dog 0.19 instead of 0.50); false: stretch to the input size (Darknet YOLO).
  bool letterbox = true;
  /// A class is reported for a box when its score is >= this. Darknet [yolo] layers in OpenCV
  /// zero the scores at or below the cfg's `thresh` (0.2 unless set), so lower values see no more.
  double confidence_threshold = 0.25;
  /// Per-class NMS: a box is dropped when it overlaps a better one of the same class by IoU > this.
  double nms_threshold = 0.45;
  /// Input normalisation, per channel of the network's input (after swap_rb):
  /// (pixel - mean) * scale / stddev. Darknet / YOLOv5/v8: scale 1/255, mean 0, stddev 1, swap_rb;
  /// NanoDet-m: scale 1, mean "103.53 116.28 123.675", stddev "57.375 57.12 58.395", BGR.
  double scale = 1.0;
  std::string mean = "103.53 116.28 123.675";
  std::string stddev = "57.375 57.12 58.395";
  bool swap_rb = false;
  /// NanoDet: centre of cell (x, y) at ((x + offset) * stride, (y + offset) * stride): 0.5 for
  /// NanoDet-m (GFL head), 0 for NanoDet-Plus.
  double nanodet_cell_offset = 0.5;
  /// cpu (OpenCV's own backend) or cuda / cuda_fp16 (needs an OpenCV built with CUDA; Debian's
  /// is not: the detector then reports it).
  std::string backend = "cpu";
  /// A missing model, weights or names file: true = error; false = a warning and the run goes on
  /// without this detector (makeDnnDetector).
  bool required = false;

  /// The params of a preset (the other keys at their defaults); InputError naming
  /// "[section] preset" for an unknown name.
  static TDnnDetectorParams fromPreset(const std::string& name,
                                       const std::string& section = "dnn_detector");
  /// Sets the keys the preset describes (format, model, weights, names, layout, input size,
  /// letterbox, normalisation, NanoDet cell offset), leaving thresholds, backend and the rest.
  void applyPreset(const std::string& name, const std::string& section = "dnn_detector");

  /// `preset` first, then every other key given overrides it.
  void loadFromConfigFile(const mrpt::config::CConfigFileBase& c, const std::string& s) override;
  void saveToConfigFile(mrpt::config::CConfigFileBase& c, const std::string& s) const override;
  /// InputError naming "[section] key" for a bad value (not for missing files: modelFileProblem).
  void validate(const std::string& section = "dnn_detector") const;

  cv::Scalar meanValues() const;    ///< `mean` parsed (validate() checks it)
  cv::Scalar stddevValues() const;  ///< `stddev` parsed
};

enum class OutputLayout { kDarknetYolo, kYoloV5, kYoloV8, kNanoDet };
OutputLayout parseLayout(const std::string& text);  ///< InputError for an unknown name

/// The map from image pixels to network-input pixels: net = image * scale + pad (continuous
/// pixel coordinates, pixel i covering [i, i + 1)). Stretching has pad 0 and independent x / y
/// scales; letterboxing one scale (as rounded into the resized size) and centred padding.
struct InputTransform {
  float scale_x = 1.f, scale_y = 1.f;
  float pad_x = 0.f, pad_y = 0.f;
  cv::Size resized;  ///< the image's size inside the network input
  cv::Size net;      ///< the network input size

  cv::Point2f toNet(cv::Point2f image_px) const;
  cv::Point2f toImage(cv::Point2f net_px) const;
  cv::Rect2f boxToImage(const cv::Rect2f& net_box) const;
};

InputTransform makeInputTransform(cv::Size image, cv::Size net, bool letterbox);
/// The image resized (INTER_LINEAR) into the network input as `transform` says, padded with 114.
cv::Mat applyInputTransform(const cv::Mat& bgr, const InputTransform& transform);

// ---- decoders: raw output blobs -> boxes in network-input pixels, the classes whose score is
// >= score_threshold (sorted by decreasing score); rows with none are dropped ----

/// Darknet [yolo] layers as OpenCV's Region layer emits them: per output a [rows, 5 + nc] matrix
/// of [cx, cy, w, h] (fractions of the input size), objectness, obj * class probability.
std::vector<Detection> decodeDarknetYolo(const std::vector<cv::Mat>& outputs, cv::Size net,
                                         float score_threshold);
/// YOLOv5 export: [1, N, 5 + nc] (or [N, 5 + nc]), [cx, cy, w, h] in input pixels, objectness
/// and class probabilities (sigmoid applied); score = objectness * class probability.
std::vector<Detection> decodeYoloV5(const cv::Mat& output, float score_threshold);
/// YOLOv8 export: [1, 4 + nc, N] (or [4 + nc, N]), [cx, cy, w, h] in input pixels and class
/// probabilities (no objectness).
std::vector<Detection> decodeYoloV8(const cv::Mat& output, float score_threshold);
/// NanoDet-m: per stride level a score map [h*w, nc] (sigmoid applied) and a distribution map
/// [h*w, 4*(reg_max+1)] (left, top, right, bottom; softmax over the bins, expectation x stride
/// is the distance from the cell centre), rows in row-major cell order. Outputs are paired by
/// row count, whatever their names; the stride is sqrt(net area / rows).
std::vector<Detection> decodeNanoDet(const std::vector<cv::Mat>& outputs, cv::Size net,
                                     int num_classes, float cell_offset, float score_threshold);

/// Network-input boxes -> image pixels (undoing `transform`), clipped to the image; boxes with
/// no area left are dropped; then per-class NMS (suppressPerClass).
std::vector<Detection> finishDetections(std::vector<Detection> net_detections,
                                        const InputTransform& transform, cv::Size image,
                                        float score_threshold, float nms_threshold);

/// Reads a names file (one class per line, blank trailing lines ignored); InputError naming the
/// file and `key` when it cannot be read or is empty.
std::vector<std::string> readClassNames(const std::string& path, const std::string& key);

/// "" when every file the params name exists, else which file, its INI key and how to obtain it.
std::string modelFileProblem(const TDnnDetectorParams& params,
                             const std::string& section = "dnn_detector");

/// Whether OpenCV's dnn has a CUDA target in this build ("" if it has, else why not).
std::string cudaUnavailableReason();

class DnnDetector : public Detector {
 public:
  /// Loads the network and the names and runs one forward pass on a blank image to check that
  /// the outputs match the layout and the names file. InputError (naming the INI key) on missing
  /// files, unreadable models, a layout that does not fit or an unavailable backend.
  explicit DnnDetector(const TDnnDetectorParams& params, std::string section = "dnn_detector");

  std::string name() const override { return m_section; }
  const std::vector<std::string>& classNames() const override { return m_class_names; }
  std::vector<Detection> detect(const DetectorInput& input) override;

  const TDnnDetectorParams& params() const { return m_params; }
  /// The network's raw outputs for an image (for tests and tools), and the transform used.
  std::vector<cv::Mat> forward(const cv::Mat& bgr, InputTransform* transform);
  /// Milliseconds of the last detect(): input preparation + forward + decoding + NMS.
  double lastMs() const { return m_last_ms; }

 private:
  std::vector<Detection> decode(const std::vector<cv::Mat>& outputs) const;
  int outputClassCount(const std::vector<cv::Mat>& outputs) const;

  TDnnDetectorParams m_params;
  std::string m_section;
  OutputLayout m_layout = OutputLayout::kDarknetYolo;
  cv::dnn::Net m_net;
  std::vector<std::string> m_output_names;
  std::vector<std::string> m_class_names;
  cv::Scalar m_mean, m_stddev;
  double m_last_ms = 0.0;
};

/// The factory of the pipeline and of `rasm detect`: null when disabled (warning left empty) or
/// when a model file is missing and `required` is false (warning = modelFileProblem); InputError
/// when a file is missing and `required` is true, or on any other problem.
std::unique_ptr<DnnDetector> makeDnnDetector(const TDnnDetectorParams& params, std::string* warning,
                                             const std::string& section = "dnn_detector");

}  // namespace rasm::classification
