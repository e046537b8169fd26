// Section III in the Mapper on analytic scenes (noise-free depth, known first pose): labels
// survive a camera move, an object split by an occluder merges once seen whole, remapping leaves
// no gaps, and the segment table matches a brute-force recomputation after fusion's compaction.
#include <gtest/gtest.h>

#include <mrpt/config/CConfigFileMemory.h>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <functional>
#include <map>
#include <set>

#include "pipeline/AnalyticScene.h"
#include "rasm/pipeline/Mapper.h"
#include "rasm/pipeline/stages/SegmentationStage.h"

using namespace rasm;
using namespace rasm::pipeline;
using namespace rasm::pipeline::testing;

namespace {

std::unique_ptr<Mapper> mapperWith(const std::map<std::string, std::string>& seg) {
  mrpt::config::CConfigFileMemory ini;
  for (const auto& [k, v] : seg) ini.write("segmentation", k, v);
  auto m = std::make_unique<Mapper>(ini, "test");
  m->addStage(std::make_unique<GroundTruthPose>(), "index_map");
  return m;
}

/// Labels of the surfels inside a box (grown by 1 cm).
std::map<std::uint32_t, int> labelsIn(const maps::SurfelStore& store, const Box& b) {
  std::map<std::uint32_t, int> out;
  const maps::SurfelArrays a = store.arrays();
  for (int i = 0; i < a.size; ++i) {
    if (!a.alive(i)) continue;
    const Eigen::Vector3d p = a.position(i).cast<double>();
    if ((p.array() >= b.lo.array() - 0.01).all() && (p.array() <= b.hi.array() + 0.01).all())
      ++out[a.segment[i]];
  }
  return out;
}

}  // namespace

TEST(SegmentationStage, LabelsSurviveACameraMove) {
  const Box a{{-0.5, -0.2, 1.8}, {-0.1, 0.2, 2.2}}, b{{0.1, -0.2, 1.8}, {0.5, 0.2, 2.2}};
  std::unique_ptr<Mapper> mp = mapperWith({{"remap_every_n_frames", "1000"}});
  Mapper& mapper = *mp;
  std::uint32_t label_a = 0, label_b = 0;
  for (int k = 0; k < 30; ++k) {
    const Eigen::Isometry3d T = at(0.007 * k);  // 20 cm sideways in 1 s
    const FrameResult r = mapper.processFrame(render({a, b}, T, k));
    ASSERT_TRUE(r.fused) << "frame " << k << " " << tracking::toString(r.tracking.status);
    // L^p at the projection of each box's front-face centre.
    const Eigen::Vector3d ca = T.inverse() * Eigen::Vector3d(-0.3, 0, 1.8),
                          cb = T.inverse() * Eigen::Vector3d(0.3, 0, 1.8);
    const auto px = [](const Eigen::Vector3d& p) {
      return std::make_pair(int(std::lround(kK.cx + kK.fx * p.x() / p.z())),
                            int(std::lround(kK.cy + kK.fy * p.y() / p.z())));
    };
    const auto [xa, ya] = px(ca);
    const auto [xb, yb] = px(cb);
    const Image<std::uint32_t>& lp = mapper.lastContext().labels;
    ASSERT_FALSE(lp.empty());
    if (k == 0) {
      label_a = lp(xa, ya);
      label_b = lp(xb, yb);
      ASSERT_NE(label_a, 0u);
      ASSERT_NE(label_b, 0u);
      ASSERT_NE(label_a, label_b);
    } else {
      EXPECT_EQ(lp(xa, ya), label_a) << "frame " << k;
      EXPECT_EQ(lp(xb, yb), label_b) << "frame " << k;
    }
  }
  // Each box's surfels carry its label.
  for (const auto& [box, label] : {std::make_pair(a, label_a), std::make_pair(b, label_b)}) {
    const auto in = labelsIn(mapper.map().store(), box);
    int total = 0;
    for (const auto& [l, n] : in) total += n;
    ASSERT_GT(total, 1000);
    EXPECT_GE(in.count(label) ? in.at(label) : 0, 0.95 * total);
  }
}

TEST(SegmentationStage, ObjectSplitByAnOccluderMergesOnceSeenWhole) {
  // A pole 1 m in front of a wide box splits it in two segments for 10 frames, then is taken
  // away: the box, seen whole, joins its two labels (Psi over merge_threshold frames).
  const Box box{{-0.4, -0.25, 1.8}, {0.4, 0.25, 2.2}}, pole{{-0.06, -1.0, 1.0}, {0.06, 1.0, 1.1}};
  std::unique_ptr<Mapper> mp = mapperWith({});
  Mapper& mapper = *mp;
  SegmentationStage& seg = mapper.stage<SegmentationStage>();
  int removed = 0;
  for (int k = 0; k < 10; ++k) mapper.processFrame(render({box, pole}, at(0.0), k));
  {
    const auto in = labelsIn(mapper.map().store(), box);
    int big = 0;
    for (const auto& [l, n] : in) big += l != 0 && n > 500;
    ASSERT_GE(big, 2) << "the pole splits the box in the first frames";
  }
  for (int k = 10; k < 40; ++k) {
    const FrameResult r = mapper.processFrame(render({box}, at(0.0), k));
    removed += r.fusion.removed_carved + r.fusion.removed_unstable + r.fusion.demoted_carved;
    if (std::getenv("SEG_DEBUG")) {
      std::printf(
          "frame %d: %s L_t %d matched %d created %d psi %zu cosegmented %zu visible %zu carved %d "
          "demoted %d\n",
          k, tracking::toString(r.tracking.status), seg.lastSegments().count,
          seg.lastPropagation().matched, seg.lastPropagation().created,
          seg.mergeConfidence().size(), seg.lastPropagation().cosegmented.size(),
          seg.lastPropagation().visible.size(), r.fusion.removed_carved, r.fusion.demoted_carved);
      for (const auto& [l, n] : labelsIn(mapper.map().store(), box))
        std::printf("  label %u: %d\n", l, n);
    }
  }
  EXPECT_GT(removed, 0) << "the pole's surfels are carved";
  EXPECT_GE(seg.lastSegments().count, 1);
  const auto in = labelsIn(mapper.map().store(), box);
  int total = 0, best = 0;
  for (const auto& [l, n] : in) {
    total += n;
    if (l) best = std::max(best, n);
  }
  EXPECT_GE(best, 0.95 * total) << "one label holds the box";
  nlohmann::json rep;
  mapper.report(rep);
  EXPECT_GE(rep["segmentation"]["merges"].get<int>(), 1);
}

/// The label holding most surfels in a box, and its share.
std::pair<std::uint32_t, double> majorityLabel(const maps::SurfelStore& store, const Box& b) {
  std::uint32_t best = 0;
  int best_n = 0, total = 0;
  for (const auto& [l, n] : labelsIn(store, b)) {
    total += n;
    if (n > best_n) {
      best_n = n;
      best = l;
    }
  }
  return {best, total ? double(best_n) / total : 0.0};
}

TEST(SegmentationStage, AnObjectFusedIntoItsSupportFromAfarGetsItsOwnLabelWhenSeenClose) {
  // A 2 cm thick plate on the back wall. From 3 m its step is below delta_Gamma (1 cm + 1 cm/m^2
  // z^2 = 10 cm) and below the concave margin (0.003 z^2 = 2.7 cm): plate and wall are one
  // segment and the plate's surfels take the wall's label. From 0.7 m the step exceeds both
  // (1.5 cm, 0.15 cm) and the plate holds 16% of the wall label's pixels in view: the split
  // rule (split_max_share) gives it a label of its own, which its surfels take over.
  const Box plate{{-0.15, -0.35, 2.98}, {0.15, -0.05, 3.0}};
  const Box wall_patch{{0.3, -0.35, 2.99}, {0.6, -0.05, 3.01}};
  for (const double share : {0.3, 0.0}) {
    std::unique_ptr<Mapper> mp =
        mapperWith({{"split_max_share", std::to_string(share)}, {"remap_every_n_frames", "1000"}});
    Mapper& mapper = *mp;
    Eigen::Isometry3d near = at(0.0);
    near.translation().z() = 2.28;
    for (int k = 0; k < 10; ++k) mapper.processFrame(render({plate}, at(0.0), k));
    const auto [far_plate, far_share] = majorityLabel(mapper.map().store(), plate);
    const auto [far_wall, far_wall_share] = majorityLabel(mapper.map().store(), wall_patch);
    ASSERT_NE(far_wall, 0u);
    ASSERT_EQ(far_plate, far_wall) << "from 3 m the plate is part of the wall's segment";
    for (int k = 10; k < 35; ++k) mapper.processFrame(render({plate}, near, k));
    const auto [plate_label, plate_share] = majorityLabel(mapper.map().store(), plate);
    const auto [wall_label, wall_share] = majorityLabel(mapper.map().store(), wall_patch);
    EXPECT_EQ(wall_label, far_wall) << "the wall keeps its label";
    if (share > 0.0) {
      EXPECT_NE(plate_label, wall_label) << "the plate has a label of its own";
      EXPECT_NE(plate_label, 0u);
      EXPECT_GE(plate_share, 0.9) << "and its surfels carry it";
    } else {
      EXPECT_EQ(plate_label, wall_label) << "without the rule the plate keeps the wall's label";
    }
  }
}

TEST(SegmentationStage, RemappingLeavesNoGapsAndTheTableMatchesBruteForce) {
  const Box a{{-0.5, -0.2, 1.8}, {-0.1, 0.2, 1.82}}, b{{0.1, -0.2, 1.8}, {0.5, 0.2, 2.2}},
      pole{{-0.06, -1.0, 1.0}, {0.06, 1.0, 1.1}};
  std::unique_ptr<Mapper> mp = mapperWith({{"remap_every_n_frames", "5"}});
  Mapper& mapper = *mp;
  SegmentationStage& seg = mapper.stage<SegmentationStage>();
  int removed = 0;
  for (int k = 0; k < 23; ++k) {
    // The pole comes and goes (labels are created and vanish); the camera moves.
    std::vector<Box> scene = {a, b};
    if (k % 8 < 4) scene.push_back(pole);
    const FrameResult r = mapper.processFrame(render(scene, at(0.004 * k), k));
    removed += r.fusion.removed_carved + r.fusion.removed_unstable + r.fusion.merged;
  }
  ASSERT_GT(removed, 0) << "fusion compacted the map";
  seg.refreshTable(mapper.map());
  // No gaps: the labels in the map are exactly 1..K.
  const maps::SurfelArrays s = static_cast<const maps::CSurfelMap&>(mapper.map()).store().arrays();
  std::set<std::uint32_t> used;
  for (int i = 0; i < s.size; ++i)
    if (s.alive(i) && s.segment[i]) used.insert(s.segment[i]);
  ASSERT_FALSE(used.empty());
  EXPECT_EQ(*used.rbegin(), used.size());
  // Brute force: count, centroid, bounding box per label.
  std::map<std::uint32_t, std::pair<int, Eigen::Vector3d>> sums;
  std::map<std::uint32_t, std::pair<Eigen::Vector3d, Eigen::Vector3d>> box;
  for (int i = 0; i < s.size; ++i) {
    if (!s.alive(i) || !s.segment[i]) continue;
    const Eigen::Vector3d p = s.position(i).cast<double>();
    auto& [n, sum] = sums[s.segment[i]];
    if (n == 0) {
      sum.setZero();
      box[s.segment[i]] = {p, p};
    }
    ++n;
    sum += p;
    box[s.segment[i]].first = box[s.segment[i]].first.cwiseMin(p);
    box[s.segment[i]].second = box[s.segment[i]].second.cwiseMax(p);
  }
  ASSERT_EQ(seg.table().segments().size(), sums.size());
  for (const auto& st : seg.table().segments()) {
    ASSERT_TRUE(sums.count(st.id)) << st.id;
    EXPECT_EQ(st.surfels, sums[st.id].first);
    EXPECT_LT((st.centroid - sums[st.id].second / sums[st.id].first).norm(), 1e-9);
    EXPECT_EQ(st.bbox_min, box[st.id].first);
    EXPECT_EQ(st.bbox_max, box[st.id].second);
    // No extent along a PCA axis exceeds the bounding box's diagonal.
    EXPECT_LE(st.extents.maxCoeff(), (st.bbox_max - st.bbox_min).norm() + 1e-9);
  }
  // Box a is a 0.4 x 0.4 x 0.02 m plate: its two largest PCA extents are 0.4 m.
  const auto la = labelsIn(mapper.map().store(), a);
  std::uint32_t label_a = 0;
  int best = 0;
  for (const auto& [l, n] : la)
    if (l && n > best) best = n, label_a = l;
  const segmentation::SegmentStats* sa = seg.table().find(label_a);
  ASSERT_NE(sa, nullptr);
  EXPECT_NEAR(sa->extents[0], 0.4, 0.03);
  EXPECT_NEAR(sa->extents[1], 0.4, 0.03);
}
