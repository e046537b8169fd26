// Benchmark of the zero-shot classifier (paper IV-A; issue 17, 3 and 6) on simulated frames with
// ground truth. Prints one JSON line:
//  - ms per frame of ZeroShotDetector::detect (edge map + Edge Boxes, HOG + matching) with OpenCV
//    on one thread, for the configured number of proposals;
//  - proposal recall at 100 / 500 / 1000 boxes: the fraction of ground-truth objects (instances
//    of the gt_instance mask with >= --min-px pixels, structure excluded; the box is the bounding
//    box of their visible pixels) that some proposal among the first K overlaps by IoU >= 0.5 /
//    0.7, overall and for the bank's classes;
//  - per-frame precision / recall of the detections of each bank class that the simulator knows
//    (IoU >= 0.5 with a ground-truth instance of that class, each matched once, best score first).
//   bench_zero_shot [--world office] [--trajectory office_handheld] [--every 10] [--frames 0]
//                   [--models PATH] [--min-px 400] [--set zero_shot.key=value ...]
// Real data (--tum-cabinet DIR, models default cabinet_box.yaml): on the TUM fr3/cabinet keyframes,
// how often the best 'cabinet' detection overlaps the projected ground-truth cuboid (IoU >= 0.5),
// and the proposal recall of that box (TumCabinet.h).
#include <mrpt/config/CConfigFileMemory.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <map>
#include <nlohmann/json.hpp>
#include <opencv2/core.hpp>
#include <opencv2/imgcodecs.hpp>
#include <string>
#include <vector>

#include "rasm/classification/TemplateBank.h"
#include "rasm/classification/ZeroShotDetector.h"
#include "rasm/core/Params.h"
#include "rasm/core/Timing.h"
#include "rasm/sim/SimClasses.h"
#include "rasm/sim/SimulatedSequence.h"
#include "rasm/sim/Trajectory.h"
#include "rasm/sim/World.h"
#include "classification/TumCabinet.h"

using namespace rasm;
using namespace rasm::classification;

namespace {

struct GtBox {
  cv::Rect box;
  int class_id = 0;
  int pixels = 0;
};

std::vector<GtBox> groundTruthBoxes(const RgbdFrame& f, const sim::World& world, int min_px) {
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
    if (g.pixels < min_px || sim::isStructureClass(g.class_id)) continue;
    g.box = cv::Rect(lo[id], hi[id] + cv::Point(1, 1));
    out.push_back(g);
  }
  return out;
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

/// The --tum-cabinet mode: one JSON line about the cabinet keyframes.
int runTumCabinet(const std::string& dir, ZeroShotDetector& detector, double train_s) {
  const std::vector<test::CabinetKeyframe> frames = test::loadCabinetKeyframes(dir);
  const int cabinet = detector.bank().classIndex("cabinet");
  if (frames.empty() || cabinet < 0) {
    std::fprintf(stderr, "no keyframes in %s or no class 'cabinet' in the bank\n", dir.c_str());
    return 2;
  }
  long found = 0, any = 0, recalled = 0, with_detection = 0;
  std::vector<double> best_iou, ms;
  nlohmann::json per_frame = nlohmann::json::array();
  for (const auto& k : frames) {
    DetectorInput in;
    in.bgr = cv::imread(k.image_path, cv::IMREAD_COLOR);
    if (in.bgr.empty()) {
      std::fprintf(stderr, "cannot read %s\n", k.image_path.c_str());
      return 2;
    }
    const Clock::time_point t0 = Clock::now();
    const std::vector<Detection> dets = detector.detect(in);
    ms.push_back(msSince(t0));
    double first = 0.0, best_any = 0.0;
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
  const double n = double(frames.size());
  nlohmann::json j;
  j["bench"] = "zero_shot_tum_cabinet";
  j["frames"] = frames.size();
  j["bank_templates"] = detector.bank().size();
  j["train_s"] = train_s;
  j["ms_per_frame_median"] = percentile(ms, 0.5);
  j["frames_with_cabinet_detection"] = with_detection;
  j["best_detection_iou_0.5"] = double(found) / n;
  j["any_detection_iou_0.5"] = double(any) / n;
  j["proposal_recall_1000_iou_0.5"] = double(recalled) / n;
  j["best_detection_iou_median"] = percentile(best_iou, 0.5);
  j["per_frame"] = per_frame;
  std::printf("%s\n", j.dump().c_str());
  return 0;
}

struct Counts {
  long gt = 0, detections = 0, tp = 0, frames_visible = 0, frames_found = 0;
};

}  // namespace

int main(int argc, char** argv) {
  std::string world_name = "office", trajectory = "office_handheld";
  std::string models = std::string(RASM_SOURCE_DIR) +
                       "/modules/classification/models/office_zero_shot.yaml";
  std::string tum_cabinet;
  int every = 10, max_frames = 0, min_px = 400;
  mrpt::config::CConfigFileMemory ini;
  for (int i = 1; i + 1 < argc; i += 2) {
    const std::string a = argv[i], v = argv[i + 1];
    if (a == "--world") world_name = v;
    else if (a == "--trajectory") trajectory = v;
    else if (a == "--every") every = std::max(1, std::atoi(v.c_str()));
    else if (a == "--frames") max_frames = std::atoi(v.c_str());
    else if (a == "--models") models = v;
    else if (a == "--tum-cabinet") tum_cabinet = v;
    else if (a == "--min-px") min_px = std::atoi(v.c_str());
    else if (a == "--set" && v.rfind("zero_shot.", 0) == 0 && v.find('=') != std::string::npos)
      ini.write("zero_shot", v.substr(10, v.find('=') - 10), v.substr(v.find('=') + 1));
    else {
      std::fprintf(stderr, "unknown option %s (see the header of zero_shot_bench.cpp)\n", argv[i]);
      return 2;
    }
  }
  cv::setNumThreads(1);  // the detector on one core (paper VI: the ZSC runs on the CPU beside YOLO)
  if (!tum_cabinet.empty() && models.find("office_zero_shot") != std::string::npos)
    models = std::string(RASM_SOURCE_DIR) + "/modules/classification/models/cabinet_box.yaml";
  TZeroShotParams params;
  loadParamsStrict(ini, "zero_shot", params, "--set");
  const Clock::time_point t_train = Clock::now();
  ZeroShotDetector detector(trainTemplateBank(loadModelsSpec(models)), params);
  const double train_s = msSince(t_train) / 1000.0;
  if (!tum_cabinet.empty()) return runTumCabinet(tum_cabinet, detector, train_s);
  const TemplateBank& bank = detector.bank();
  std::vector<int> bank_class_ids;
  for (const auto& n : bank.class_names) bank_class_ids.push_back(sim::classIdFromName(n));

  const sim::World world = sim::loadWorld(world_name);
  sim::SimulatedSequence seq(world, sim::loadTrajectorySpec(trajectory));
  const int ks[3] = {100, 500, 1000};
  long gt_all = 0, gt_bank = 0;
  long hit[3][2] = {}, hit_bank[3][2] = {};
  std::vector<double> detect_ms, proposal_ms, match_ms;
  std::vector<Counts> counts(bank.class_names.size());
  RgbdFrame frame;
  int used = 0;
  for (long i = 0; seq.next(frame); ++i) {
    if (i % every != 0) continue;
    if (max_frames > 0 && used >= max_frames) break;
    ++used;
    const cv::Mat bgr = colourMat(frame);
    const std::vector<GtBox> gt = groundTruthBoxes(frame, world, min_px);
    // Proposal recall at 100 / 500 / 1000 (Edge Boxes returns them best first).
    const std::vector<cv::Rect> boxes = detector.proposals(bgr, 1000);
    for (const GtBox& g : gt) {
      const bool of_bank = std::count(bank_class_ids.begin(), bank_class_ids.end(), g.class_id) > 0;
      ++gt_all, gt_bank += of_bank;
      for (int k = 0; k < 3; ++k) {
        double best = 0.0;
        for (int j = 0; j < std::min<int>(ks[k], int(boxes.size())); ++j)
          best = std::max(best, iou(g.box, boxes[j]));
        for (int t = 0; t < 2; ++t)
          if (best >= (t == 0 ? 0.5 : 0.7)) ++hit[k][t], hit_bank[k][t] += of_bank;
      }
    }
    // The classifier as configured, timed.
    DetectorInput in;
    in.bgr = bgr;
    const Clock::time_point t0 = Clock::now();
    const std::vector<Detection> dets = detector.detect(in);
    detect_ms.push_back(msSince(t0));
    proposal_ms.push_back(detector.lastProposalMs());
    match_ms.push_back(detector.lastMatchMs());
    for (int c = 0; c < int(bank.class_names.size()); ++c) {
      if (bank_class_ids[c] <= 0) continue;
      Counts& n = counts[c];
      std::vector<bool> taken(gt.size(), false);
      long visible = 0, found = 0;
      for (const GtBox& g : gt) visible += g.class_id == bank_class_ids[c];
      for (const Detection& d : dets) {  // best score first
        if (d.bestIndex() != c) continue;
        ++n.detections;
        int best_j = -1;
        double best = 0.5;
        for (std::size_t j = 0; j < gt.size(); ++j)
          if (!taken[j] && gt[j].class_id == bank_class_ids[c] && iou(gt[j].box, cv::Rect(d.box)) >= best)
            best = iou(gt[j].box, cv::Rect(d.box)), best_j = int(j);
        if (best_j >= 0) taken[best_j] = true, ++n.tp, ++found;
      }
      n.gt += visible;
      n.frames_visible += visible > 0;
      n.frames_found += found > 0;
    }
  }
  auto ratio = [](long a, long b) { return b > 0 ? double(a) / double(b) : 0.0; };
  nlohmann::json j;
  j["bench"] = "zero_shot";
  j["world"] = world_name;
  j["trajectory"] = trajectory;
  j["frames"] = used;
  j["every"] = every;
  j["image"] = {frame.width(), frame.height()};
  j["bank_templates"] = bank.size();
  j["train_s"] = train_s;
  j["max_proposals"] = params.max_proposals;
  j["proposal_scale"] = params.proposal_scale;
  j["opencv_threads"] = cv::getNumThreads();
  j["ms_per_frame"] = {{"median", percentile(detect_ms, 0.5)},
                       {"p90", percentile(detect_ms, 0.9)},
                       {"proposals_median", percentile(proposal_ms, 0.5)},
                       {"match_median", percentile(match_ms, 0.5)}};
  j["recall"]["gt_objects"] = gt_all;
  j["recall"]["gt_objects_of_bank_classes"] = gt_bank;
  for (int k = 0; k < 3; ++k) {
    const std::string key = "at_" + std::to_string(ks[k]);
    j["recall"][key] = {{"iou_0.5", ratio(hit[k][0], gt_all)}, {"iou_0.7", ratio(hit[k][1], gt_all)}};
    j["recall"]["bank_classes_" + key] = {{"iou_0.5", ratio(hit_bank[k][0], gt_bank)},
                                          {"iou_0.7", ratio(hit_bank[k][1], gt_bank)}};
  }
  for (int c = 0; c < int(bank.class_names.size()); ++c) {
    if (bank_class_ids[c] <= 0) continue;
    const Counts& n = counts[c];
    j["classifier"][bank.class_names[c]] = {
        {"gt", n.gt},
        {"detections", n.detections},
        {"tp", n.tp},
        {"precision", ratio(n.tp, n.detections)},
        {"recall", ratio(n.tp, n.gt)},
        {"frames_visible", n.frames_visible},
        {"frames_found", n.frames_found}};
  }
  std::printf("%s\n", j.dump().c_str());
  return 0;
}
