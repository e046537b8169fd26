#include <algorithm>
#include <map>
#include <opencv2/dnn/dnn.hpp>

#include "rasm/classification/Detection.h"
#include "rasm/classification/Detector.h"

namespace rasm::classification {

std::vector<Detection> suppressPerClass(std::vector<Detection> detections, float score_threshold,
                                        float iou_threshold) {
  std::map<int, std::vector<int>> by_class;  // best class -> detection indices
  for (int i = 0; i < int(detections.size()); ++i)
    if (!detections[i].scores.empty() && detections[i].bestScore() >= score_threshold)
      by_class[detections[i].bestIndex()].push_back(i);
  std::vector<Detection> kept;
  for (const auto& [cls, idx] : by_class) {
    std::vector<cv::Rect2d> boxes;
    std::vector<float> scores;
    for (int i : idx) {
      const cv::Rect2f& b = detections[i].box;
      boxes.emplace_back(b.x, b.y, b.width, b.height);
      scores.push_back(detections[i].bestScore());
    }
    std::vector<int> keep;
    cv::dnn::NMSBoxes(boxes, scores, score_threshold, iou_threshold, keep);
    for (int k : keep) kept.push_back(std::move(detections[idx[k]]));
  }
  std::stable_sort(kept.begin(), kept.end(), [](const Detection& a, const Detection& b) {
    return a.bestScore() > b.bestScore();
  });
  return kept;
}

cv::Mat colourMat(const RgbdFrame& frame) {
  if (frame.colour.empty()) return {};
  return cv::Mat(frame.colour.height(), frame.colour.width(), CV_8UC3,
                 const_cast<Bgr8*>(frame.colour.row(0)), frame.colour.pitchBytes());
}

}  // namespace rasm::classification
