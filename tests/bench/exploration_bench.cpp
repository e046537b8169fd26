// Cost of the exploration predictions of section V on a map of the simulated office: the map is
// fused (SurfelFusion, ground-truth poses) and the octree filled from 48 frames of a robot that
// turns in place at two spots of the room (noise-free depth, 640x480). Prints one JSON line with
// medians over repetitions: entropy() of the workspace, one candidate's dH and dIC (one render of
// the surfel map + the octree ray cast + the bin sum) at 320x240 and 160x120, a whole IG plan and
// one plan of each planner (ig, ig_greedy, frontier, random, lawnmower) on the same octree, and
// "run_sized": an ig plan with as many candidates as a room's plans reach late in an exploring
// run (~270: the object views of every uncertain segment; docs/exploration.md "Costs") with the
// [exploration] defaults, against the 0.3 s a plan may take (issue 38's target: 2 M surfels,
// 2 cores; this map holds ~1.7 M).
//   bench_exploration
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <vector>

#include "rasm/core/FrameProcessing.h"
#include "rasm/exploration/ExplorationPlanners.h"
#include "rasm/exploration/ViewCandidates.h"
#include "rasm/exploration/ViewPlanner.h"
#include "rasm/fusion/SurfelFusion.h"
#include "rasm/segmentation/SegmentTable.h"
#include "rasm/sim/CameraPoses.h"
#include "rasm/sim/RayScene.h"
#include "rasm/sim/RgbdSensor.h"
#include "rasm/sim/SimulatedDiffDriveRobot.h"

using namespace rasm;

namespace {
double msSince(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
}
template <typename F>
double medianMs(int reps, F&& f) {
  std::vector<double> v;
  for (int k = 0; k < reps; ++k) {
    const auto t0 = std::chrono::steady_clock::now();
    f();
    v.push_back(msSince(t0));
  }
  std::sort(v.begin(), v.end());
  return v[v.size() / 2];
}

struct ThinnedAgreement {
  double rank_correlation = 0, rel_dh = 0, rel_dic = 0;
  bool same_best = false;
  int top10_kept = 0;  ///< of the whole plan's 10 best views, how many the other plan ranks
};

double medianOf(std::vector<double> v) {
  if (v.empty()) return 0.0;
  std::sort(v.begin(), v.end());
  return v[v.size() / 2];
}

/// Ranks of `values` (0 = smallest; ties in input order).
std::vector<double> ranksOf(const std::vector<double>& values) {
  std::vector<int> order(values.size());
  for (std::size_t i = 0; i < order.size(); ++i) order[i] = int(i);
  std::stable_sort(order.begin(), order.end(),
                   [&](int a, int b) { return values[std::size_t(a)] < values[std::size_t(b)]; });
  std::vector<double> rank(values.size());
  for (std::size_t r = 0; r < order.size(); ++r) rank[std::size_t(order[r])] = double(r);
  return rank;
}

/// The two plans' candidates matched by pose (same seed and grid: the same candidates).
ThinnedAgreement agreement(const exploration::Plan& full, const exploration::Plan& thin) {
  std::vector<double> g_full, g_thin, dh, dic;
  for (const auto& f : full.ranked)
    for (const auto& t : thin.ranked)
      if ((f.pose - t.pose).norm() < 1e-9) {
        g_full.push_back(f.gain);
        g_thin.push_back(t.gain);
        if (f.entropy_reduction > 0)
          dh.push_back(std::abs(t.entropy_reduction - f.entropy_reduction) / f.entropy_reduction);
        if (f.information > 0)
          dic.push_back(std::abs(t.information - f.information) / f.information);
      }
  ThinnedAgreement a;
  const std::size_t n = g_full.size();
  if (n >= 2) {
    const std::vector<double> rf = ranksOf(g_full), rt = ranksOf(g_thin);
    double d2 = 0;
    for (std::size_t i = 0; i < n; ++i) d2 += (rf[i] - rt[i]) * (rf[i] - rt[i]);
    a.rank_correlation = 1.0 - 6.0 * d2 / (double(n) * (double(n) * n - 1.0));
  }
  a.same_best = !full.ranked.empty() && !thin.ranked.empty() &&
                (full.ranked.front().pose - thin.ranked.front().pose).norm() < 1e-9;
  for (std::size_t k = 0; k < std::min<std::size_t>(10, full.ranked.size()); ++k)
    for (const auto& t : thin.ranked)
      if ((full.ranked[k].pose - t.pose).norm() < 1e-9) {
        ++a.top10_kept;
        break;
      }
  a.rel_dh = medianOf(dh);
  a.rel_dic = medianOf(dic);
  return a;
}
}  // namespace

int main() {
  const sim::RayScene scene(sim::loadWorld("office"));
  sim::TSensorParams sp;
  sp.noise = false;
  sim::RgbdSensor sensor(scene, sp);
  const CameraIntrinsics K = sensor.intrinsics();
  const Eigen::AlignedBox3f box = scene.world().bounds();
  const Eigen::Vector3f c = box.center();
  const Eigen::Isometry3d mount = sim::TRobotParams().T_base_cam();

  exploration::TExplorationParams ep;
  ep.workspace_min_x_m = box.min().x(), ep.workspace_max_x_m = box.max().x();
  ep.workspace_min_y_m = box.min().y(), ep.workspace_max_y_m = box.max().y();
  ep.workspace_min_z_m = 0.0, ep.workspace_max_z_m = std::min(3.0f, box.max().z());
  exploration::OccupancyOctree octree(ep);
  fusion::SurfelFusion fusion;
  maps::SurfelStore store;
  double insert_ms = 0.0;
  int frame = 0;
  for (const double dx : {-1.0, 1.0})
    for (int k = 0; k < 24; ++k, ++frame) {
      const Eigen::Vector3d pose(c.x() + dx, c.y(), k * M_PI / 12);
      const Eigen::Isometry3d T = exploration::cameraPoseOf(pose, mount);
      const RgbdFrame f = sensor.render(T, 0, std::size_t(frame));
      Image<Vec3f> v, n;
      computeVertexMap(f.depth_m, K, v);
      computeNormalMap(v, n);
      fusion.fuse(store, fusion::makeFusionInput(f, v, n, T));
      const auto t0 = std::chrono::steady_clock::now();
      octree.insertDepthFrame(f.depth_m, K, T);
      insert_ms += msSince(t0);
    }
  segmentation::SegmentTable table;
  table.compute(store.arrays());
  const exploration::ViewInfoModel model =
      exploration::ViewInfoModel::of(fusion.params(), store.options());

  const double entropy_ms = medianMs(5, [&] { (void)octree.entropy(); });
  std::printf(
      "{\"bench\":\"exploration\",\"surfels\":%d,\"octree_leaves\":%zu,"
      "\"insert_frame_ms\":%.2f,\"entropy_ms\":%.2f",
      store.size(), octree.tree().getNumLeafNodes(), insert_ms / frame, entropy_ms);
  for (const int w : {320, 160}) {
    ep.predict_width = w, ep.predict_height = w * 3 / 4;
    exploration::ViewPredictor predictor(ep, model);
    const Eigen::Isometry3d T =
        exploration::cameraPoseOf(Eigen::Vector3d(c.x(), c.y() + 0.5, 0.7), mount);
    const CameraIntrinsics Kp = K.resized(ep.predict_width, ep.predict_height);
    maps::SurfelRenderer renderer;
    maps::RenderedMaps maps;
    maps::RenderOptions ro;
    ro.cull_back_faces = true;
    ro.outputs = maps::kRenderDepth;
    const double render_ms = medianMs(5, [&] { renderer.render(store, T, Kp, ro, maps); });
    const double dh_ms =
        medianMs(5, [&] { (void)octree.predictedEntropyReduction(T, Kp, maps.depth_m); });
    const double dic_ms = medianMs(5, [&] {
      (void)exploration::predictedInformationGain(store, maps.index, T, model, 0.25f);
    });
    const double both_ms = medianMs(5, [&] { (void)predictor.predict(store, octree, T, K); });
    std::printf(
        ",\"%dx%d\":{\"render_ms\":%.2f,\"dH_ms\":%.2f,\"dIC_ms\":%.2f,\"predict_ms\":%.2f}",
        ep.predict_width, ep.predict_height, render_ms, dh_ms, dic_ms, both_ms);
  }
  ep.predict_width = 160, ep.predict_height = 120;
  exploration::PlannerInputs in;
  in.store = &store;
  in.segments = &table.segments();
  in.octree = &octree;
  in.robot_pose = Eigen::Vector3d(c.x() - 1.0, c.y(), 0.0);  // the first spin spot
  in.T_base_cam = mount;
  in.K = K;
  in.model = model;
  std::size_t ranked = 0, pruned = 0;
  const double plan_ms = medianMs(3, [&] {
    const exploration::Plan plan = exploration::ViewPlanner(ep).plan(in);
    ranked = plan.ranked.size(), pruned = plan.unreachable.size();
  });
  std::printf(",\"plan_160x120_ms\":%.1f,\"plan_candidates\":%zu,\"plan_pruned\":%zu", plan_ms,
              ranked, pruned);
  // Of which the paths to every candidate (planPaths on the plan's grid).
  {
    const exploration::Plan plan = exploration::ViewPlanner(ep).plan(in);
    std::vector<exploration::ViewCandidate> all = plan.ranked;
    all.insert(all.end(), plan.unreachable.begin(), plan.unreachable.end());
    std::size_t reachable = 0;
    const double paths_ms = medianMs(3, [&] {
      exploration::planPaths(plan.grid, in.robot_pose, ep, all);
      reachable = std::size_t(
          std::count_if(all.begin(), all.end(), [](const auto& v) { return v.reachable; }));
    });
    std::printf(",\"paths_ms\":%.1f,\"paths_candidates\":%zu,\"paths_reachable\":%zu", paths_ms,
                all.size(), reachable);
  }
  // The same plan on a thinned map ([exploration] predict_max_surfels) and with the coarse
  // screen (predict_screen_keep): its cost, and how far
  // its predictions are from the whole map's (Spearman rank correlation of the candidates'
  // gains, the best view kept, median relative difference of dH and of dIC).
  {
    const exploration::Plan full = exploration::ViewPlanner(ep).plan(in);
    std::printf(",\"thinned\":[");
    struct Config {
      int width, max_surfels, screen_keep;
    };
    const Config configs[] = {{160, 400000, 0}, {160, 200000, 0}, {160, 100000, 0},
                              {80, 200000, 0},  {160, 0, 20},     {160, 200000, 20},
                              {160, 200000, 12}};
    for (const Config& cfg : configs) {
      exploration::TExplorationParams tp = ep;
      tp.predict_width = cfg.width, tp.predict_height = cfg.width * 3 / 4;
      tp.predict_max_surfels = cfg.max_surfels;
      tp.predict_screen_keep = cfg.screen_keep;
      exploration::Plan thin;
      const double ms = medianMs(3, [&] { thin = exploration::ViewPlanner(tp).plan(in); });
      const ThinnedAgreement a = agreement(full, thin);
      std::printf(
          "%s{\"predict\":\"%dx%d\",\"max_surfels\":%d,\"screen_keep\":%d,"
          "\"plan_ms\":%.1f,\"ranked\":%zu,\"rank_correlation\":%.3f,\"same_best\":%s,"
          "\"top10_kept\":%d,\"median_rel_diff_dH\":%.3f,\"median_rel_diff_dIC\":%.3f}",
          &cfg == &configs[0] ? "" : ",", tp.predict_width, tp.predict_height, cfg.max_surfels,
          cfg.screen_keep, ms, thin.ranked.size(), a.rank_correlation,
          a.same_best ? "true" : "false", a.top10_kept, a.rel_dh, a.rel_dic);
    }
    std::printf("]");
  }
  // Every planner through makePlanner on the same octree and robot pose ("ig": the views of the
  // plan above plus the clusters and the tour).
  for (const char* name : {"ig", "ig_greedy", "frontier", "random", "lawnmower"}) {
    ep.planner = name;
    const auto planner = exploration::makePlanner(ep);
    std::size_t offered = 0, grid_cells = 0;
    const bool predicts = planner->scoresInformation();
    const double ms = medianMs(predicts ? 3 : 5, [&] {
      const exploration::Plan plan = planner->plan(in);
      offered = plan.ranked.size(), grid_cells = plan.grid.getSizeX() * plan.grid.getSizeY();
    });
    std::printf(",\"%s\":{\"plan_ms\":%.2f,\"offered\":%zu,\"grid_cells\":%zu}", name, ms, offered,
                grid_cells);
  }
  {
    // The defaults on this map's workspace, then the whole map and no screen for comparison.
    exploration::TExplorationParams rp;
    rp.workspace_min_x_m = ep.workspace_min_x_m, rp.workspace_max_x_m = ep.workspace_max_x_m;
    rp.workspace_min_y_m = ep.workspace_min_y_m, rp.workspace_max_y_m = ep.workspace_max_y_m;
    rp.workspace_min_z_m = ep.workspace_min_z_m, rp.workspace_max_z_m = ep.workspace_max_z_m;
    rp.random_candidates = 270;
    const double target_ms = 300.0;
    const int defaults[2] = {rp.predict_max_surfels, rp.predict_screen_keep};
    const int configs[][2] = {{defaults[0], defaults[1]}, {0, 0}, {200000, 0}, {200000, 40}};
    std::printf(
        ",\"run_sized\":{\"planner\":\"%s\",\"candidates\":%d,\"target_ms\":%.0f,"
        "\"plans\":[",
        rp.planner.c_str(), rp.random_candidates, target_ms);
    // Agreement with the whole map's greedy ranking of every candidate (ig_greedy, no screen).
    exploration::TExplorationParams whole = rp;
    whole.planner = "ig_greedy", whole.predict_max_surfels = 0, whole.predict_screen_keep = 0;
    const exploration::Plan reference = exploration::makePlanner(whole)->plan(in);
    double default_ms = 0.0;
    for (const auto& cfg : configs) {
      rp.predict_max_surfels = cfg[0], rp.predict_screen_keep = cfg[1];
      const auto planner = exploration::makePlanner(rp);
      std::size_t offered = 0, screened_out = 0;
      const double ms = medianMs(3, [&] {
        const exploration::Plan plan = planner->plan(in);
        offered = plan.ranked.size(), screened_out = plan.screened_out;
      });
      exploration::TExplorationParams greedy = rp;
      greedy.planner = "ig_greedy";
      const ThinnedAgreement a = agreement(reference, exploration::makePlanner(greedy)->plan(in));
      if (&cfg == &configs[0]) default_ms = ms;
      std::printf(
          "%s{\"predict_max_surfels\":%d,\"predict_screen_keep\":%d,\"default\":%s,"
          "\"plan_ms\":%.1f,\"offered\":%zu,\"screened_out\":%zu,\"same_best\":%s,"
          "\"top10_kept\":%d}",
          &cfg == &configs[0] ? "" : ",", cfg[0], cfg[1], &cfg == &configs[0] ? "true" : "false",
          ms, offered, screened_out, a.same_best ? "true" : "false", a.top10_kept);
    }
    // Of a plan's cost, the part that grows with the map: thinning it to 200 k surfels (copy and
    // spatial index).
    exploration::TExplorationParams thin = rp;
    thin.predict_max_surfels = 200000;
    const double thin_ms = medianMs(3, [&] {
      maps::SurfelStore thinned;
      (void)exploration::predictionStore(store, thin, thinned);
    });
    std::printf("],\"thin_to_200k_ms\":%.1f,\"default_met\":%s}", thin_ms,
                default_ms <= target_ms ? "true" : "false");
  }
  std::printf("}\n");
  return 0;
}
