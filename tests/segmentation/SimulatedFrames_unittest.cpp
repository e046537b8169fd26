// L_t on simulated frames (Kinect noise, dropouts) against the simulator's per-pixel ground-truth
// instances: objects visible with enough pixels are one segment (IoU > 0.5). Set
// RASM_SEG_DEBUG_DIR to write the edge, label and ground-truth images of each frame tested.
#include <gtest/gtest.h>

#include <mrpt/config/CConfigFileMemory.h>
#include <cstdio>
#include <cstdlib>
#include <map>
#include <opencv2/imgcodecs.hpp>
#include <sstream>

#include "rasm/core/FrameProcessing.h"
#include "rasm/models/ClassVocabulary.h"
#include "rasm/segmentation/GeometricSegmenter.h"
#include "rasm/segmentation/kernels/EdgeKernels.h"
#include "rasm/sim/SimulatedSequence.h"
#include "rasm/surfel_map/MapExport.h"

using namespace rasm;
using namespace rasm::segmentation;

namespace {

struct FrameScore {
  int objects = 0, recovered = 0;
  double interior_fraction = 0.0;
};

void writeDebug(const std::string& prefix, const FrameSegments& s, const RgbdFrame& f) {
  const int w = s.labels.width(), h = s.labels.height();
  cv::Mat lab(h, w, CV_8UC3), gt(h, w, CV_8UC3), edge(h, w, CV_8UC1);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      const Bgr8 c = maps::labelColour(s.labels(x, y)), g = maps::labelColour(f.gt_instance(x, y));
      lab.at<cv::Vec3b>(y, x) = {c.b, c.g, c.r};
      gt.at<cv::Vec3b>(y, x) = {g.b, g.g, g.r};
      const int sc = w / s.edges.width();
      const std::uint8_t e = s.edges(x / sc, y / sc);
      edge.at<std::uint8_t>(y, x) = e == kernels::kInterior ? 0 : e == kernels::kEdge ? 255 : 96;
    }
  cv::imwrite(prefix + "_labels.png", lab);
  cv::imwrite(prefix + "_gt.png", gt);
  cv::imwrite(prefix + "_edges.png", edge);
}

FrameScore score(const FrameSegments& s, const RgbdFrame& f, const sim::World& world, int min_px) {
  // Pixel counts per instance, per segment and per (instance, segment).
  std::map<int, int> inst, seg;
  std::map<std::pair<int, int>, int> both;
  const int w = s.labels.width(), h = s.labels.height();
  int valid = 0, interior = 0;
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      if (f.depth_m(x, y) <= 0) continue;
      ++valid;
      interior += s.labels(x, y) != 0;
      const int i = f.gt_instance(x, y), l = int(s.labels(x, y));
      ++inst[i];
      if (l) {
        ++seg[l];
        ++both[{i, l}];
      }
    }
  FrameScore sc;
  sc.interior_fraction = valid ? double(interior) / valid : 0.0;
  for (const auto& [i, n] : inst) {
    const int k = world.indexOfInstance(std::uint16_t(i));
    if (i == 0 || k < 0 || n < min_px ||
        models::isStructureClass(world.objects[std::size_t(k)].class_id))
      continue;
    ++sc.objects;
    double best = 0;
    for (const auto& [key, m] : both)
      if (key.first == i) best = std::max(best, double(m) / double(n + seg[key.second] - m));
    sc.recovered += best > 0.5;
  }
  return sc;
}

void scoreSequence(const char* world_name, const char* trajectory, int step, int frames,
                   double min_recovered) {
  const sim::World world = sim::loadWorld(world_name);
  sim::SequenceOptions opt;
  opt.seed = 3;
  opt.max_frames = step * frames;
  sim::SimulatedSequence seq(world, sim::loadTrajectorySpec(trajectory), opt);
  // RASM_SEG_SET="key=value;key=value" overrides [segmentation] keys (for measuring defaults).
  TSegmentationParams params;
  if (const char* set = std::getenv("RASM_SEG_SET")) {
    mrpt::config::CConfigFileMemory ini;
    std::string all(set), item;
    std::stringstream ss(all);
    while (std::getline(ss, item, ';'))
      if (item.find('=') != std::string::npos)
        ini.write("segmentation", item.substr(0, item.find('=')), item.substr(item.find('=') + 1));
    params.loadFromConfigFile(ini, "segmentation");
  }
  GeometricSegmenter seg(params);
  const char* debug = std::getenv("RASM_SEG_DEBUG_DIR");
  RgbdFrame f;
  Image<float> filtered;
  Image<Vec3f> vertex, normal;
  Image<float> half;
  int objects = 0, recovered = 0, k = 0;
  while (seq.next(f)) {
    if (k++ % step) continue;
    // The Mapper's preprocessing at its defaults (bilateral filter, depth range 0.3-4 m).
    bilateralFilterDepth(f.depth_m, filtered, 2, 4.5f, 0.03f);
    VertexMapOptions vo;
    vo.min_depth_m = 0.3f;
    vo.max_depth_m = 4.0f;
    const int level = seg.params().level;
    const Image<float>* depth = &filtered;
    for (int l = 0; l < level; ++l) {
      downsampleDepth(*depth, half);
      filtered = half;
    }
    computeVertexMap(*depth, f.intrinsics.level(level), vertex, vo);
    computeNormalMap(vertex, normal, 0.05f);
    const FrameSegments& s = seg.segment(vertex, normal, f.intrinsics.width, f.intrinsics.height);
    const FrameScore sc = score(s, f, world, 1500);
    std::printf(
        "%s frame %d: %d / %d objects one segment, %.0f%% of valid pixels in segments, %d segments "
        "(ms: normals %.2f edges %.2f components %.2f)\n",
        trajectory, k - 1, sc.recovered, sc.objects, 100 * sc.interior_fraction, s.count,
        s.ms_normals, s.ms_edges, s.ms_components);
    objects += sc.objects;
    recovered += sc.recovered;
    if (debug)
      writeDebug(std::string(debug) + "/" + trajectory + "_" + std::to_string(k - 1), s, f);
  }
  ASSERT_GT(objects, 5) << "too few visible objects to measure";
  EXPECT_GE(double(recovered) / objects, min_recovered) << recovered << " of " << objects;
}

}  // namespace

TEST(SimulatedFrames, OfficeObjectsAreSegments) {
  scoreSequence("office", "office_handheld", 40, 5, 0.7);
}
TEST(SimulatedFrames, ClutteredLabObjectsAreSegments) {
  scoreSequence("cluttered_lab", "cluttered_lab_handheld", 40, 5, 0.7);
}
