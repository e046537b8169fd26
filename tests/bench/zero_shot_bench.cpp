// Benchmark of the zero-shot classifier (paper IV-A; issue 17, 3 and 6) on simulated frames with
// ground truth. Prints one JSON line:
//  - time per frame of ZeroShotDetector::detect (edge map + Edge Boxes, HOG + matching) with OpenCV
//    on one thread: wall-clock ms and the thread's CPU ms (robust to a loaded machine);
//  - proposal recall at 100 / 500 / 1000 boxes: the fraction of ground-truth objects (instances
//    of the gt_instance mask with >= --min-px pixels, structure excluded; the box is the bounding
//    box of their visible pixels) that some proposal among the first K overlaps by IoU >= 0.5 /
//    0.7, overall and for the bank's classes;
//  - per-frame precision / recall of the detections of each bank class that the simulator knows
//    (IoU >= 0.5 with a ground-truth instance of that class, each matched once, best score first),
//    at the configured similarity threshold and at higher ones (a detection passes threshold t
//    when its similarity is >= t; per-class NMS keeps the same boxes above t either way).
//   bench_zero_shot [--world office] [--trajectory office_handheld] [--every 10] [--frames 0]
//                   [--models PATH] [--min-px 400] [--set zero_shot.key=value ...]
// Real data (--tum-cabinet DIR, models default cabinet_box.yaml): on the TUM fr3/cabinet keyframes,
// how often the best 'cabinet' detection overlaps the projected ground-truth cuboid (IoU >= 0.5),
// and the proposal recall of that box (TumCabinet.h).
#include <mrpt/config/CConfigFileMemory.h>
#include <time.h>

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <map>
#include <nlohmann/json.hpp>
#include <opencv2/core.hpp>
#include <opencv2/imgcodecs.hpp>
#include <string>
#include <vector>

#include "classification/TumCabinet.h"
#include "rasm/classification/TemplateBank.h"
#include "rasm/classification/ZeroShotDetector.h"
#include "rasm/core/Params.h"
#include "rasm/core/Timing.h"
#include "rasm/models/ClassVocabulary.h"
#include "rasm/sim/SimulatedSequence.h"
#include "rasm/sim/Trajectory.h"
#include "rasm/sim/World.h"

using namespace rasm;
using namespace rasm::classification;

namespace {

double threadCpuMs() {
  timespec ts{};
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts);
  return 1e3 * double(ts.tv_sec) + 1e-6 * double(ts.tv_nsec);
}

double iou(const cv::Rect& a, const cv::Rect& b) {
  const double inter = (a & b).area();
  return inter <= 0 ? 0.0 : inter / (a.area() + b.area() - inter);
}

double percentile(std::vector<double> v, double q) {
  if (v.empty()) return 0.0;
  std::sort(v.begin(), v.end());
  return v[std::min(v.size() - 1, std::size_t(q * double(v.size())))];
}

double ratio(long a, long b) {
  return b > 0 ? double(a) / double(b) : 0.0;
}

struct BenchArgs {
  std::string world = "office", trajectory = "office_handheld", tum_cabinet;
  std::string models =
      std::string(RASM_SOURCE_DIR) + "/modules/classification/models/office_zero_shot.yaml";
  int every = 10, max_frames = 0, min_px = 400;
  TZeroShotParams params;
};

bool parseArgs(int argc, char** argv, BenchArgs& a) {
  mrpt::config::CConfigFileMemory ini;
  bool models_given = false;
  for (int i = 1; i + 1 < argc; i += 2) {
    const std::string k = argv[i], v = argv[i + 1];
    if (k == "--world")
      a.world = v;
    else if (k == "--trajectory")
      a.trajectory = v;
    else if (k == "--every")
      a.every = std::max(1, std::atoi(v.c_str()));
    else if (k == "--frames")
      a.max_frames = std::atoi(v.c_str());
    else if (k == "--models")
      a.models = v, models_given = true;
    else if (k == "--tum-cabinet")
      a.tum_cabinet = v;
    else if (k == "--min-px")
      a.min_px = std::atoi(v.c_str());
    else if (k == "--set" && v.rfind("zero_shot.", 0) == 0 && v.find('=') != std::string::npos)
      ini.write("zero_shot", v.substr(10, v.find('=') - 10), v.substr(v.find('=') + 1));
    else {
      std::fprintf(stderr, "unknown option %s (see the header of zero_shot_bench.cpp)\n", argv[i]);
      return false;
    }
  }
  if (!a.tum_cabinet.empty() && !models_given)
    a.models = std::string(RASM_SOURCE_DIR) + "/modules/classification/models/cabinet_box.yaml";
  loadParamsStrict(ini, "zero_shot", a.params, "--set");
  return true;
}

// ---------------------------------------------------------------------------------------------
// Real data: TUM fr3/cabinet

int runTumCabinet(const std::string& dir, ZeroShotDetector& detector, nlohmann::json j) {
  const std::vector<test::CabinetKeyframe> frames = test::loadCabinetKeyframes(dir);
  const int cabinet = detector.bank().classIndex("cabinet");
  if (frames.empty() || cabinet < 0) {
    std::fprintf(stderr, "no keyframes in %s or no class 'cabinet' in the bank\n", dir.c_str());
    return 2;
  }
  long found = 0, any = 0, recalled = 0, with_detection = 0;
  std::vector<double> best_iou, cpu_ms;
  nlohmann::json per_frame = nlohmann::json::array();
  for (const auto& k : frames) {
    DetectorInput in;
    in.bgr = cv::imread(k.image_path, cv::IMREAD_COLOR);
    if (in.bgr.empty()) {
      std::fprintf(stderr, "cannot read %s\n", k.image_path.c_str());
      return 2;
    }
    const double c0 = threadCpuMs();
    const std::vector<Detection> dets = detector.detect(in);
    cpu_ms.push_back(threadCpuMs() - c0);
    double first = 0.0, best_any = 0.0;  // the best-scoring cabinet detection; any of them
    bool seen = false;
    for (const Detection& d : dets) {
      if (d.bestIndex() != cabinet) continue;
      const double v = iou(k.box, cv::Rect(d.box));
      if (!seen) first = v, seen = true;
      best_any = std::max(best_any, v);
    }
    double best_proposal = 0.0;
    for (const cv::Rect& b : detector.proposals(in.bgr, 1000))
      best_proposal = std::max(best_proposal, iou(k.box, b));
    with_detection += seen;
    found += first >= 0.5, any += best_any >= 0.5, recalled += best_proposal >= 0.5;
    best_iou.push_back(first);
    per_frame.push_back({{"image", k.image_path.substr(k.image_path.rfind('/') + 1)},
                         {"truth", {k.box.x, k.box.y, k.box.width, k.box.height}},
                         {"visible", k.visible},
                         {"best_cabinet_iou", first},
                         {"any_cabinet_iou", best_any},
                         {"best_proposal_iou", best_proposal}});
  }
  const long n = long(frames.size());
  j["bench"] = "zero_shot_tum_cabinet";
  j["frames"] = n;
  j["cpu_ms_per_frame_median"] = percentile(cpu_ms, 0.5);
  j["frames_with_cabinet_detection"] = with_detection;
  j["best_detection_iou_0.5"] = ratio(found, n);
  j["any_detection_iou_0.5"] = ratio(any, n);
  j["proposal_recall_1000_iou_0.5"] = ratio(recalled, n);
  j["best_detection_iou_median"] = percentile(best_iou, 0.5);
  j["per_frame"] = per_frame;
  std::printf("%s\n", j.dump().c_str());
  return 0;
}

// ---------------------------------------------------------------------------------------------
// Simulated frames

struct GtBox {
  cv::Rect box;
  int class_id = 0;
  int pixels = 0;
};

std::vector<GtBox> groundTruthBoxes(const RgbdFrame& f, int min_px) {
  std::map<int, GtBox> by_instance;
  std::map<int, cv::Point> lo, hi;
  for (int y = 0; y < f.height(); ++y)
    for (int x = 0; x < f.width(); ++x) {
      const int id = f.gt_instance(x, y);
      if (id == 0) continue;
      auto [it, fresh] = by_instance.try_emplace(id);
      if (fresh) lo[id] = {x, y}, hi[id] = {x, y}, it->second.class_id = f.gt_class(x, y);
      ++it->second.pixels;
      lo[id] = {std::min(lo[id].x, x), std::min(lo[id].y, y)};
      hi[id] = {std::max(hi[id].x, x), std::max(hi[id].y, y)};
    }
  std::vector<GtBox> out;
  for (auto& [id, g] : by_instance) {
    if (g.pixels < min_px || models::isStructureClass(g.class_id)) continue;
    g.box = cv::Rect(lo[id], hi[id] + cv::Point(1, 1));
    out.push_back(g);
  }
  return out;
}

constexpr int kProposalCounts[3] = {100, 500, 1000};

struct RecallCounts {
  long gt = 0, hits[3][2] = {};  // [K][IoU 0.5, 0.7]
};

void countRecall(const std::vector<GtBox>& gt, const std::vector<cv::Rect>& boxes,
                 const std::vector<int>& only_classes, RecallCounts& r) {
  for (const GtBox& g : gt) {
    if (!only_classes.empty() &&
        std::find(only_classes.begin(), only_classes.end(), g.class_id) == only_classes.end())
      continue;
    ++r.gt;
    for (int k = 0; k < 3; ++k) {
      double best = 0.0;
      for (int j = 0; j < std::min<int>(kProposalCounts[k], int(boxes.size())); ++j)
        best = std::max(best, iou(g.box, boxes[j]));
      r.hits[k][0] += best >= 0.5, r.hits[k][1] += best >= 0.7;
    }
  }
}

nlohmann::json recallJson(const RecallCounts& r) {
  nlohmann::json j;
  j["gt_objects"] = r.gt;
  for (int k = 0; k < 3; ++k)
    j["at_" + std::to_string(kProposalCounts[k])] = {{"iou_0.5", ratio(r.hits[k][0], r.gt)},
                                                     {"iou_0.7", ratio(r.hits[k][1], r.gt)}};
  return j;
}

struct ClassCounts {
  long gt = 0, detections = 0, tp = 0, frames_visible = 0, frames_found = 0;
};

/// Detections of bank class `c` (ground-truth class id `class_id`) whose score is >= min_score,
/// matched greedily (best score first) to unmatched ground truth of that class at IoU >= 0.5.
void countClass(const std::vector<Detection>& dets, const std::vector<GtBox>& gt, int c,
                int class_id, float min_score, ClassCounts& n) {
  std::vector<bool> taken(gt.size(), false);
  long visible = 0, found = 0;
  for (const GtBox& g : gt) visible += g.class_id == class_id;
  for (const Detection& d : dets) {
    if (d.bestIndex() != c || d.bestScore() < min_score) continue;
    ++n.detections;
    int best_j = -1;
    double best = 0.5;
    for (std::size_t j = 0; j < gt.size(); ++j) {
      const double v = iou(gt[j].box, cv::Rect(d.box));
      if (!taken[j] && gt[j].class_id == class_id && v >= best) best = v, best_j = int(j);
    }
    if (best_j >= 0) taken[best_j] = true, ++n.tp, ++found;
  }
  n.gt += visible, n.frames_visible += visible > 0, n.frames_found += found > 0;
}

nlohmann::json classJson(const ClassCounts& n) {
  return {{"gt", n.gt},
          {"detections", n.detections},
          {"tp", n.tp},
          {"precision", ratio(n.tp, n.detections)},
          {"recall", ratio(n.tp, n.gt)},
          {"frames_visible", n.frames_visible},
          {"frames_found", n.frames_found}};
}

int runSimulated(const BenchArgs& a, ZeroShotDetector& detector, nlohmann::json j) {
  const TemplateBank& bank = detector.bank();
  const TZeroShotParams& p = a.params;
  std::vector<int> class_ids;  // simulator class id of each bank class (-1: unknown there)
  for (const auto& n : bank.class_names) class_ids.push_back(models::classIdFromName(n));
  // Similarity thresholds of the precision / recall table and the scores they map to.
  std::vector<double> thresholds;
  for (double t : {p.similarity_threshold, 0.8, 0.85, 0.9, 0.95})
    if (t >= p.similarity_threshold && (thresholds.empty() || t > thresholds.back()))
      thresholds.push_back(t);
  auto scoreAt = [&](double t) {
    return float(p.score_at_threshold + (p.score_at_one - p.score_at_threshold) *
                                            (t - p.similarity_threshold) /
                                            std::max(1e-9, 1.0 - p.similarity_threshold)) -
           1e-6f;
  };
  const sim::World world = sim::loadWorld(a.world);
  sim::SimulatedSequence seq(world, sim::loadTrajectorySpec(a.trajectory));
  RecallCounts all, of_bank;
  std::vector<double> wall_ms, cpu_ms, proposal_ms, match_ms;
  std::vector<std::vector<ClassCounts>> counts(bank.class_names.size(),
                                               std::vector<ClassCounts>(thresholds.size()));
  RgbdFrame frame;
  int used = 0;
  for (long i = 0; seq.next(frame) && (a.max_frames <= 0 || used < a.max_frames); ++i) {
    if (i % a.every != 0) continue;
    ++used;
    const cv::Mat bgr = colourMat(frame);
    const std::vector<GtBox> gt = groundTruthBoxes(frame, a.min_px);
    const std::vector<cv::Rect> boxes = detector.proposals(bgr, 1000);  // best first
    countRecall(gt, boxes, {}, all);
    std::vector<int> bank_ids;
    for (int id : class_ids)
      if (id > 0) bank_ids.push_back(id);
    if (!bank_ids.empty()) countRecall(gt, boxes, bank_ids, of_bank);
    DetectorInput in;
    in.bgr = bgr;
    const Clock::time_point t0 = Clock::now();
    const double c0 = threadCpuMs();
    const std::vector<Detection> dets = detector.detect(in);
    cpu_ms.push_back(threadCpuMs() - c0);
    wall_ms.push_back(msSince(t0));
    proposal_ms.push_back(detector.lastProposalMs());
    match_ms.push_back(detector.lastMatchMs());
    for (int c = 0; c < int(bank.class_names.size()); ++c)
      for (std::size_t t = 0; t < thresholds.size() && class_ids[c] > 0; ++t)
        countClass(dets, gt, c, class_ids[c], scoreAt(thresholds[t]), counts[c][t]);
  }
  j["world"] = a.world;
  j["trajectory"] = a.trajectory;
  j["frames"] = used;
  j["every"] = a.every;
  j["image"] = {frame.width(), frame.height()};
  j["ms_per_frame"] = {{"wall_median", percentile(wall_ms, 0.5)},
                       {"cpu_median", percentile(cpu_ms, 0.5)},
                       {"cpu_p90", percentile(cpu_ms, 0.9)},
                       {"proposals_wall_median", percentile(proposal_ms, 0.5)},
                       {"match_wall_median", percentile(match_ms, 0.5)}};
  j["recall"] = recallJson(all);
  j["recall_bank_classes"] = recallJson(of_bank);
  for (int c = 0; c < int(bank.class_names.size()); ++c) {
    if (class_ids[c] <= 0) continue;
    j["classifier"][bank.class_names[c]] = classJson(counts[c][0]);
    for (std::size_t t = 0; t < thresholds.size(); ++t) {
      nlohmann::json row = classJson(counts[c][t]);
      row["similarity_threshold"] = thresholds[t];
      j["classifier_by_threshold"][bank.class_names[c]].push_back(row);
    }
  }
  std::printf("%s\n", j.dump().c_str());
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  BenchArgs a;
  if (!parseArgs(argc, argv, a)) return 2;
  cv::setNumThreads(1);  // the detector on one core (paper VI: the ZSC runs on the CPU beside YOLO)
  const Clock::time_point t_train = Clock::now();
  ZeroShotDetector detector(trainTemplateBank(loadModelsSpec(a.models)), a.params);
  nlohmann::json j;
  j["bench"] = "zero_shot";
  j["models"] = a.models;
  j["train_s"] = msSince(t_train) / 1000.0;
  j["bank_templates"] = detector.bank().size();
  j["max_proposals"] = a.params.max_proposals;
  j["proposal_scale"] = a.params.proposal_scale;
  j["similarity_threshold"] = a.params.similarity_threshold;
  j["opencv_threads"] = cv::getNumThreads();
  return a.tum_cabinet.empty() ? runSimulated(a, detector, j)
                               : runTumCabinet(a.tum_cabinet, detector, j);
}
