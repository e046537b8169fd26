#include "rasm/autonomy/ExplorationLoop.h"

#include <mrpt/math/wrap2pi.h>
#include <mrpt/poses/CPose2D.h>

#include <cmath>
#include <cstdio>

#include "rasm/autonomy/StableSurfels.h"
#include "rasm/classification/ClassificationMetrics.h"
#include "rasm/core/Error.h"
#include "rasm/core/Timing.h"
#include "rasm/exploration/ExplorationPlanner.h"
#include "rasm/exploration/PlanningGrid.h"
#include "rasm/exploration/ViewPlanner.h"
#include "rasm/models/ClassVocabulary.h"
#include "rasm/pipeline/OutputFiles.h"
#include "rasm/pipeline/stages/ClassificationStage.h"
#include "rasm/pipeline/stages/FusionStages.h"
#include "rasm/pipeline/stages/TrackingStage.h"
#ifdef RASM_HAVE_SIM
#include "rasm/autonomy/OraclePlanner.h"
#include "rasm/autonomy/SimObjectScore.h"
#include "rasm/sim/SimulatedSequence.h"
#include "rasm/sim/SurfaceCoverage.h"
#endif

namespace rasm::autonomy {

using namespace rasm::pipeline;

namespace {
mrpt::poses::CPose2D pose2D(const Eigen::Vector3d& p) {
  return {p.x(), p.y(), p.z()};
}

nlohmann::json poseJson(const Eigen::Vector3d& p) {
  return {p.x(), p.y(), p.z()};
}

const char* sourceName(exploration::ViewCandidate::Source s) {
  using S = exploration::ViewCandidate::Source;
  switch (s) {
    case S::Object:
      return "object";
    case S::Frontier:
      return "frontier";
    case S::Sweep:
      return "sweep";
    case S::Oracle:
      return "oracle";
    case S::Random:
      break;
  }
  return "random";
}
}  // namespace

#ifdef RASM_HAVE_SIM
namespace {
/// The simulated robot stepped in the sequence's substeps between frames (RobotDriver.h), on the
/// mapping thread at simulated times.
class SimulatedRobotDriver : public RobotDriver {
 public:
  explicit SimulatedRobotDriver(sim::SimulatedSequence& seq) : m_seq(seq) {}
  robot::IRobot& robot() override { return *m_seq.robot(); }
  void start(std::function<void()> navigation_step) override {
    m_seq.setSubstepHook(std::move(navigation_step));
  }
  void stop() override { m_seq.setSubstepHook({}); }
  void endFrames() override { m_seq.finish(); }
  const char* stepping() const override { return "substeps"; }

 private:
  sim::SimulatedSequence& m_seq;
};
}  // namespace

ExplorationLoop::ExplorationLoop(Mapper& mapper, sim::SimulatedSequence& seq,
                                 const navigation::TNavigationParams& nav_params)
    : m_mapper(mapper), m_stage(mapper.stage<ExplorationStage>()), m_seq(&seq) {
  if (!seq.robot())
    throwInputError("[exploration] enabled",
                    "needs a simulated robot ([sim] trajectory: a robot spec)");
  if (m_stage.loopParams().workspace_from_world) {
    const Eigen::AlignedBox3f b = seq.scene().world().bounds();
    const auto& p = m_stage.params();
    m_stage.setWorkspace(
        Eigen::AlignedBox3d(Eigen::Vector3d(b.min().x(), b.min().y(), p.workspace_min_z_m),
                            Eigen::Vector3d(b.max().x(), b.max().y(),
                                            std::min<double>(b.max().z(), p.workspace_max_z_m))));
  }
  m_driver = std::make_unique<SimulatedRobotDriver>(seq);
  const sim::SimulatedDiffDriveRobot& robot = *seq.robot();
  // Coverage counts the surface this robot's camera could see (its height, pitch, field of view
  // and the mapper's depth range), not the ceiling or the undersides of desks.
  m_coverage = std::make_shared<sim::SurfaceCoverage>(
      seq.scene().world(), seq.scene(),
      sim::coverageOptionsForRobot(robot.params(), seq.sensor().intrinsics(),
                                   mapper.mapperParams().max_depth_m));
  m_object_score = std::make_shared<SimObjectScore>(seq.scene());
  if (m_stage.params().planner == "oracle")  // the ground truth's planner (start() builds others)
    m_planner = std::make_unique<OraclePlanner>(
        *m_coverage, seq.scene(), m_stage.params(),
        mapper.stage<TrackingStage>().robotParams().T_base_cam(), seq.sensor().intrinsics());
  start(robot.params().footprintPolygon(), nav_params);
}
#endif  // RASM_HAVE_SIM

ExplorationLoop::ExplorationLoop(Mapper& mapper, std::unique_ptr<RobotDriver> driver,
                                 const std::vector<Eigen::Vector2f>& footprint,
                                 const navigation::TNavigationParams& nav_params)
    : m_mapper(mapper), m_stage(mapper.stage<ExplorationStage>()), m_driver(std::move(driver)) {
  start(footprint, nav_params);  // the workspace is [exploration] workspace_* as loaded
}

/// What both robots share: the planner, the navigator on the driver's robot, the driver's
/// stepping, the planner thread.
void ExplorationLoop::start(const std::vector<Eigen::Vector2f>& footprint,
                            const navigation::TNavigationParams& nav_params) {
  m_T_base_cam = m_mapper.stage<TrackingStage>().robotParams().T_base_cam();
  if (!m_planner) m_planner = exploration::makePlanner(m_stage.params());
  m_robot = &m_driver->robot();
  m_nav = std::make_unique<navigation::Navigator>(*m_robot, nav_params, footprint,
                                                  [this] { return estimatedBasePose(); });
  m_driver->start([this] {
    std::lock_guard<std::mutex> lock(m_nav_mx);
    if (m_nav) m_nav->update();
  });
  m_fusion_params = m_mapper.stage<FusionStage>().params();
  if (m_stage.loopParams().planner_thread) m_worker = std::thread([this] { plannerThread(); });
}

ExplorationLoop::~ExplorationLoop() {
  release();
}

void ExplorationLoop::release() {
  if (m_worker.joinable()) {
    {
      std::lock_guard<std::mutex> lock(m_mx);
      m_quit = true;
    }
    m_cv.notify_all();
    m_worker.join();
  }
  if (!m_nav) return;
  m_driver->stop();  // no step after this (the navigation thread has ended)
  std::lock_guard<std::mutex> lock(m_nav_mx);
  m_nav_final = m_nav->state();
  m_nav.reset();  // MRPT's navigator stops the robot when destroyed: the robot must still exist
}

navigation::NavState ExplorationLoop::navState() const {
  std::lock_guard<std::mutex> lock(m_nav_mx);
  return m_nav ? m_nav->state() : m_nav_final;
}

std::string ExplorationLoop::navFailureReason() const {
  std::lock_guard<std::mutex> lock(m_nav_mx);
  return m_nav ? m_nav->failureReason() : std::string();
}

void ExplorationLoop::navSetGoal(const Eigen::Vector3d& goal,
                                 const std::vector<Eigen::Vector2d>& via) {
  std::lock_guard<std::mutex> lock(m_nav_mx);
  if (m_nav) m_nav->setGoal(goal, via);
}

void ExplorationLoop::navCancel() {
  std::lock_guard<std::mutex> lock(m_nav_mx);
  if (m_nav) m_nav->cancel();
}

Eigen::Vector3d ExplorationLoop::estimatedBasePose() const {
  const Eigen::Vector3d odo = m_robot->odometry();
  std::lock_guard<std::mutex> lock(m_loc_mx);
  if (!m_have_est) return odo;  // before the first frame: the odometry starts at the true pose
  // The estimate at the last frame composed with the odometry increment since it (SE(2)).
  const mrpt::poses::CPose2D p = pose2D(m_est_base) + (pose2D(odo) - pose2D(m_odo_at_est));
  return {p.x(), p.y(), p.phi()};
}

void ExplorationLoop::afterFrame(const RgbdFrame& frame, const FrameResult& r) {
  ++m_frames;
  if (!m_t0) {
    m_t0 = r.timestamp_s;  // a simulated run starts at 0; a live camera's at UNIX time
    m_wall_t0 = Clock::now();
  }
  m_t = r.timestamp_s - *m_t0;
  m_driver->frameArrived(frame);
  m_K = frame.intrinsics;
  const std::string driver_error = m_driver->error();
  if (!driver_error.empty()) throw std::runtime_error("navigation: " + driver_error);
  // Localisation: the estimated camera pose of this frame, as a base pose on the floor.
  const Eigen::Isometry3d T_base = r.T_world_cam * m_T_base_cam.inverse();
  const Eigen::Matrix3d R = T_base.linear();
  const Eigen::Vector3d base(T_base.translation().x(), T_base.translation().y(),
                             std::atan2(R(1, 0), R(0, 0)));
  if (m_have_est) m_path_m += (base.head<2>() - m_last_base.head<2>()).norm();
  m_last_base = base;
  {
    const Eigen::Vector3d odo = frame.odometry_xyyaw.value_or(m_robot->odometry());
    std::lock_guard<std::mutex> lock(m_loc_mx);
    m_est_base = base;
    m_odo_at_est = odo;
    m_have_est = true;
  }
  if (finished()) return;

  const TExplorationLoopParams& xp = m_stage.loopParams();
  if (xp.metrics_period_s > 0 && m_t - m_last_metrics_t >= xp.metrics_period_s) measure(m_t);
  if (xp.time_budget_s > 0 && m_t >= xp.time_budget_s) return stop("time_budget");
  if (xp.path_budget_m > 0 && m_path_m >= xp.path_budget_m) return stop("path_budget");
  if (xp.wall_budget_s > 0 &&
      std::chrono::duration<double>(Clock::now() - m_wall_t0).count() >= xp.wall_budget_s)
    return stop("wall_budget");

  const navigation::NavState s = navState();
  if (s == navigation::NavState::Reached || s == navigation::NavState::Failed) {
    const bool ok = s == navigation::NavState::Reached;
    if (m_goal) {
      reportOutcome(m_goal->goal, ok);
      endGoal(m_t, ok ? "reached" : navFailureReason());
    }
    navCancel();
  }
  if (xp.planner_thread) {
    takeThreadedPlan();
    if (finished()) return;
  }
  if (navState() == navigation::NavState::Idle) {
    if (m_spin_goals_left > 0) {  // the initial turn in place, a third at a time
      --m_spin_goals_left;
      Eigen::Vector3d g = estimatedBasePose();
      g.z() = mrpt::math::wrapToPi(g.z() + 2.0 * M_PI / 3.0);
      navSetGoal(g);
      return;
    }
    plan(m_t, false);
  } else if (xp.replan_period_s > 0 && m_t - m_last_plan_t >= xp.replan_period_s && m_goal &&
             m_spin_goals_left == 0) {
    plan(m_t, true);
  }
}

void ExplorationLoop::plan(double t, bool driving) {
  m_last_plan_t = t;
  PlanRequest req;
  req.t = t;
  req.driving = driving;
  req.robot = estimatedBasePose();
  req.K = m_K;  // the camera of the frames (set in afterFrame before any plan)
  if (m_goal && driving) req.goal = m_goal->goal;
  if (!m_stage.loopParams().planner_thread) {
    req.octree = &m_stage.octree();  // the mapping thread plans between frames: no copy
    return applyPlan(computePlan(req));
  }
  std::lock_guard<std::mutex> lock(m_mx);
  if (m_request || m_busy) return;  // one plan at a time; the robot waits or drives on
  req.octree_copy = std::make_unique<exploration::OccupancyOctree>(m_stage.octree());
  req.octree = req.octree_copy.get();
  m_request = std::move(req);
  m_cv.notify_one();
}

/// Snapshot, planner and (while driving) the current goal's score in this plan's units; on the
/// mapping thread (deterministic mode) or the planner thread.
ExplorationLoop::PlanOutput ExplorationLoop::computePlan(const PlanRequest& req) {
  const auto t0 = Clock::now();
  m_mapper.snapshotInto(m_snapshot);  // reuses the memory of the last plan's copy
  exploration::PlannerInputs in;
  in.store = &m_snapshot.store;
  in.segments = &m_snapshot.segments;
  in.octree = req.octree;
  in.robot_pose = req.robot;
  in.T_base_cam = m_T_base_cam;
  in.K = req.K;
  in.model = exploration::ViewInfoModel::of(m_fusion_params, m_snapshot.store.options());
  if (m_planner->scoresInformation()) in.current_goal = req.goal;
  PlanOutput out;
  out.t = req.t;
  out.driving = req.driving;
  out.robot = req.robot;
  out.goal = req.goal;
  out.plan = m_planner->plan(in);
  const exploration::Plan& p = out.plan;
  // Is the new best view clearly better than finishing the current goal? The planner scored the
  // goal in this plan, with the same IG and normalisation (Plan::current_goal).
  if (p.current_goal)
    out.current_goal_score = exploration::rankingKey(m_stage.params(), *p.current_goal);
  if (!p.ranked.empty())
    out.route = p.route ? *p.route : routeToBest(out.plan, *req.octree, req.robot);
  out.snapshot_ms = m_snapshot.copy_ms + m_snapshot.index_ms;
  out.ms = msSince(t0);
  return out;
}

/// The way to the plan's best view on the grid it planned on (the oracle plans on the world's
/// free space and leaves Plan::grid empty: then the octree's planning grid, as the others use).
std::vector<Eigen::Vector2d> ExplorationLoop::routeToBest(
    const exploration::Plan& p, const exploration::OccupancyOctree& octree,
    const Eigen::Vector3d& robot) const {
  const double radius_m = m_stage.params().footprint_radius_m;
  mrpt::maps::COccupancyGridMap2D own;
  const bool planned_on_grid = p.grid.getSizeX() > 1 && p.grid.getSizeY() > 1;
  if (!planned_on_grid) exploration::planningGrid(octree, robot, radius_m, own);
  const mrpt::maps::COccupancyGridMap2D& grid = planned_on_grid ? p.grid : own;
  const exploration::ReachableCells reach = exploration::reachableCells(grid, robot, radius_m);
  return exploration::routeTo(grid, reach, robot.head<2>(), p.ranked.front().pose.head<2>());
}

/// The decisions of a plan, on the mapping thread: log, stopping rule, the next goal or a switch.
void ExplorationLoop::applyPlan(const PlanOutput& out) {
  ++m_plans;
  const exploration::Plan& p = out.plan;
  const double best_dH = p.best_entropy_reduction, best_dIC = p.best_information;
  nlohmann::json log = {{"t", out.t},
                        {"applied_t", m_t},
                        {"robot", poseJson(out.robot)},
                        {"reachable", p.ranked.size()},
                        {"unreachable", p.unreachable.size()},
                        {"blacklisted", p.blacklisted.size()},
                        {"best_entropy_reduction", best_dH},
                        {"best_information", best_dIC},
                        {"ms", out.ms},
                        {"snapshot_ms", out.snapshot_ms},
                        {"tour_clusters", p.tour_clusters},
                        {"screened_out", p.screened_out},
                        {"while_driving", out.driving}};
  if (!p.ranked.empty()) {
    const auto& b = p.ranked.front();
    log["best"] = {{"pose", poseJson(b.pose)},
                   {"source", sourceName(b.source)},
                   {"gain", b.gain},
                   {"rate", b.rate},
                   {"path_length_m", b.path_length_m}};
  }
  if (out.current_goal_score >= 0) log["current_goal_score"] = out.current_goal_score;
  if (!p.frontiers.empty()) {
    nlohmann::json frontiers = nlohmann::json::array();
    for (const exploration::FrontierSummary& f : p.frontiers)
      frontiers.push_back(
          {{"centroid", {f.centroid.x(), f.centroid.y()}}, {"cells", f.cells}, {"found", f.found}});
    log["frontiers"] = frontiers;
  }
  if (p.tour_clusters > 0) {  // "ig": the clusters' views in tour order
    nlohmann::json tour = nlohmann::json::array();
    for (std::size_t k = 0; k < p.tour_clusters && k < p.ranked.size(); ++k)
      tour.push_back({{"pose", poseJson(p.ranked[k].pose)},
                      {"source", sourceName(p.ranked[k].source)},
                      {"gain", p.ranked[k].gain},
                      {"entropy_reduction", p.ranked[k].entropy_reduction},
                      {"information", p.ranked[k].information},
                      {"entropy_behind", p.ranked[k].entropy_behind},
                      {"weight", k < p.tour_weights.size() ? p.tour_weights[k] : 0.0},
                      {"travel_time_s", p.ranked[k].travel_time_s}});
    log["tour"] = tour;
  }
  if (!p.ranked.empty()) m_last_views = candidateViews(p);

  // Stopping rule (V): over stop_plans consecutive plans, too little left to gain (ig) or nothing
  // offered (every planner; the robot turns a quarter between them, so a view hidden behind it
  // or a frontier the obstacle growth hid for a moment gets another chance).
  const TExplorationLoopParams& xp = m_stage.loopParams();
  const bool ig = m_planner->scoresInformation();
  const bool low =
      p.ranked.empty() || (ig && best_dH < xp.stop_entropy_nats && best_dIC < xp.stop_information);
  m_low_plans = low ? m_low_plans + 1 : 0;
  log["low"] = low;
  m_plan_log.push_back(log);
  // What the robot does now (with the planner thread it may have arrived since the request).
  const bool idle = navState() == navigation::NavState::Idle;
  if (idle && m_low_plans >= xp.stop_plans) {
    stop(p.ranked.empty() ? (ig ? "no_reachable_views" : "planner_done")
                          : "information_gain_below_threshold");
    return;
  }
  if (p.ranked.empty()) {
    if (idle) {  // nothing reachable now: turn a little and look again
      Eigen::Vector3d g = estimatedBasePose();
      g.z() = mrpt::math::wrapToPi(g.z() + M_PI / 2.0);
      navSetGoal(g);
    }
    return;
  }
  const exploration::ViewCandidate& best = p.ranked.front();
  if (idle) return startGoal(best, out.route, m_t);
  // Mid-way switch: only for the goal this plan scored, and only when clearly better.
  if (!ig || !m_goal || !out.goal || *out.goal != m_goal->goal || out.current_goal_score < 0)
    return;
  const double best_score = exploration::rankingKey(m_stage.params(), best);
  if (best_score > xp.switch_ratio * out.current_goal_score) {
    reportOutcome(m_goal->goal, false);
    endGoal(m_t, "switched");
    startGoal(best, out.route, m_t);
  }
}

void ExplorationLoop::reportOutcome(const Eigen::Vector3d& goal, bool reached) {
  if (!m_stage.loopParams().planner_thread) return m_planner->goalOutcome(goal, reached);
  std::lock_guard<std::mutex> lock(m_mx);  // the planner thread applies it before its next plan
  m_outcomes.emplace_back(goal, reached);
}

/// The planner thread ([exploration] planner_thread): waits for a request, plans on a snapshot and
/// the octree copy of the request, leaves the result for the mapping thread.
void ExplorationLoop::plannerThread() {
  for (;;) {
    PlanRequest req;
    {
      std::unique_lock<std::mutex> lock(m_mx);
      m_cv.wait(lock, [&] { return m_quit || m_request.has_value(); });
      if (m_quit) return;
      req = std::move(*m_request);
      m_request.reset();
      m_busy = true;
      for (const auto& [g, ok] : m_outcomes) m_planner->goalOutcome(g, ok);
      m_outcomes.clear();
    }
    PlanOutput out;
    try {
      out = computePlan(req);
    } catch (const std::exception& e) {
      out.error = e.what();
    }
    std::lock_guard<std::mutex> lock(m_mx);
    m_ready = std::move(out);
    m_busy = false;
  }
}

/// A result of the planner thread, if one is waiting (mapping thread).
void ExplorationLoop::takeThreadedPlan() {
  std::optional<PlanOutput> out;
  {
    std::lock_guard<std::mutex> lock(m_mx);
    out.swap(m_ready);
  }
  if (!out) return;
  if (!out->error.empty()) throw std::runtime_error("exploration planner: " + out->error);
  applyPlan(*out);
}

void ExplorationLoop::startGoal(const exploration::ViewCandidate& c,
                                const std::vector<Eigen::Vector2d>& route, double t) {
  GoalRecord g;
  g.goal = c.pose;
  g.t_start = t;
  g.source = sourceName(c.source);
  g.gain = c.gain;
  g.entropy_reduction = c.entropy_reduction;
  g.information = c.information;
  g.route = route;
  m_goal = g;
  navSetGoal(c.pose, route);
}

void ExplorationLoop::endGoal(double t, const std::string& outcome) {
  if (!m_goal) return;
  m_goal->t_end = t;
  m_goal->outcome = outcome;
  m_goals.push_back(*m_goal);
  m_goal.reset();
}

void ExplorationLoop::measure(double t) {
  m_last_metrics_t = t;
  ExplorationMetricsRow row;
  row.t = t;
  row.path_m = m_path_m;
  row.frames = m_frames;
  row.entropy = m_stage.octree().entropy();
  const StableSurfels stable = stableSurfels(m_mapper.map());
  row.surfels = stable.positions.size();
  if (!groundTruth()) {  // a real robot: no world to compare with
    m_metrics.push_back(row);
    return;
  }
#ifdef RASM_HAVE_SIM
  row.coverage = m_coverage->evaluate(stable.positions).fraction;
  const SimObjectScore::Score objects = m_object_score->score(
      stable.positions, stable.segment,
      m_mapper.stage<ClassificationStage>().segmentClassNames(m_mapper.map()));
  row.objects_total = objects.detectable;
  row.objects_ok = objects.correct;
  row.objects_correct = objects.fraction();
#endif
  m_metrics.push_back(row);
}

std::optional<std::pair<std::size_t, std::size_t>> ExplorationLoop::objectsMeasuredThisFrame()
    const {
  if (!groundTruth() || m_metrics.empty() || m_metrics.back().frames != m_frames) return {};
  return std::make_pair(m_metrics.back().objects_ok, m_metrics.back().objects_total);
}

void ExplorationLoop::stop(const std::string& reason) {
  if (!m_stop_reason.empty()) return;
  m_stop_reason = reason;
  if (m_goal) endGoal(m_t, "stopped");
  navCancel();
  m_driver->endFrames();
}

void ExplorationLoop::finish(const std::string& reason) {
  if (m_stop_reason.empty()) stop(reason);
  release();  // first: the navigation thread ends even if the metrics below throw
  if (m_metrics.empty() || m_metrics.back().t < m_t || m_metrics.back().frames < m_frames)
    measure(m_t);
}

std::string ExplorationLoop::progressText() const {
  char buf[160];
  const ExplorationMetricsRow last = m_metrics.empty() ? ExplorationMetricsRow{} : m_metrics.back();
  const std::size_t goals = m_goals.size() + (m_goal ? 1 : 0);
  const char* nav = navigation::toString(navState());
  if (groundTruth())  // (coverage and objects carrying their class: the last metrics sample)
    std::snprintf(buf, sizeof buf, "t %.0fs path %.1fm coverage %.2f objects %zu/%zu goals %zu %s",
                  m_t, m_path_m, last.coverage, last.objects_ok, last.objects_total, goals, nav);
  else  // a real robot: nothing to measure coverage against
    std::snprintf(buf, sizeof buf, "t %.0fs path %.1fm goals %zu %s", m_t, m_path_m, goals, nav);
  return buf;
}

void ExplorationLoop::report(nlohmann::json& rep) const {
  const ExplorationMetricsRow last = m_metrics.empty() ? ExplorationMetricsRow{} : m_metrics.back();
  const bool gt = groundTruth();  // a real robot: null, nothing to measure against
  rep["coverage_fraction"] = gt ? nlohmann::json(last.coverage) : nlohmann::json();
  rep["objects_correct_fraction"] = gt ? nlohmann::json(last.objects_correct) : nlohmann::json();
  rep["path_length_m"] = m_path_m;
  rep["sim_time_s"] = m_t;
  rep["stop_reason"] = m_stop_reason;
  double t90 = -1;
  for (const ExplorationMetricsRow& r : m_metrics)
    if (r.coverage >= 0.9) {
      t90 = r.t;
      break;
    }
  int reached = 0, failed = 0;
  for (const GoalRecord& g : m_goals) (g.outcome == "reached" ? reached : failed) += 1;
  rep["exploration"] = {
      {"planner", m_planner->name()},
      {"plans", m_plans},
      {"goals", m_goals.size()},
      {"goals_reached", reached},
      {"goals_not_reached", failed},
      {"objects_correct", last.objects_ok},
      {"objects_detectable", last.objects_total},
      {"time_to_90_coverage_s", t90 < 0 ? nlohmann::json() : nlohmann::json(t90)},
      {"ground_truth", gt},
      {"navigation",
       {{"stepping", m_driver->stepping()},
        {"steps", m_driver->steps()},
        {"rate_hz",
         m_driver->seconds() > 0 ? double(m_driver->steps()) / m_driver->seconds() : 0.0}}},
      {"metrics_cover",
       gt ? "coverage: fraction of the world's observable surface within 2 cm of a stable "
            "surfel; objects: detectable (COCO) objects of the world carrying their "
            "class, unseen ones included"
          : "none: no ground truth on a real robot (coverage and objects are not measured; "
            "exploration.json metrics carry time, path, entropy and surfels)"}};
#ifdef RASM_HAVE_SIM
  if (const auto* oracle = dynamic_cast<const OraclePlanner*>(m_planner.get()))
    rep["exploration"]["oracle_reachable_fraction"] = oracle->reachableFraction();
#endif
}

void ExplorationLoop::writeOutputs(OutputFolder& folder) const {
  nlohmann::json goals = nlohmann::json::array();
  for (const GoalRecord& g : m_goals) {
    nlohmann::json route = nlohmann::json::array();
    for (const Eigen::Vector2d& w : g.route) route.push_back({w.x(), w.y()});
    goals.push_back({{"goal", poseJson(g.goal)},
                     {"t_start", g.t_start},
                     {"t_end", g.t_end},
                     {"source", g.source},
                     {"outcome", g.outcome},
                     {"gain", g.gain},
                     {"entropy_reduction", g.entropy_reduction},
                     {"information", g.information},
                     {"route", route}});
  }
  nlohmann::json metrics = nlohmann::json::array();
  for (const ExplorationMetricsRow& r : m_metrics) {
    nlohmann::json row = {{"t", r.t},
                          {"frames", r.frames},
                          {"path_m", r.path_m},
                          {"entropy_nats", r.entropy},
                          {"surfels", r.surfels}};
    if (groundTruth()) {
      row["coverage"] = r.coverage;
      row["objects_correct_fraction"] = r.objects_correct;
      row["objects_correct"] = r.objects_ok;
      row["objects_detectable"] = r.objects_total;
    }
    metrics.push_back(row);
  }
  nlohmann::json out = {{"comment",
                         "rasm exploration (V, VI): plans (t: s since the first frame, simulated "
                         "time on the simulator; poses x, y, yaw rad in the map frame), goals "
                         "driven to and their outcome, metrics over time (ground truth on the "
                         "simulator)"},
                        {"planner", m_planner->name()},
                        {"stop_reason", m_stop_reason},
                        {"plans", m_plan_log},
                        {"goals", goals},
                        {"metrics", metrics},
                        {"candidate_views", sceneViewsJson(sceneViews())}};
  folder.writeText("exploration.json", out.dump(1) + "\n");
}

std::vector<SceneView> ExplorationLoop::candidateViews(const exploration::Plan& p) {
  std::vector<SceneView> views;
  auto add = [&](const exploration::ViewCandidate& c, bool reachable) {
    SceneView v;
    v.position = c.T_world_cam.translation();
    v.direction = c.T_world_cam.linear().col(2);  // the optical axis
    v.gain = c.gain;
    v.reachable = reachable;
    views.push_back(v);
  };
  for (const auto& c : p.ranked) add(c, true);
  for (const auto& c : p.unreachable) add(c, false);
  return views;
}

std::vector<SceneView> ExplorationLoop::sceneViews() const {
  std::vector<SceneView> views = m_last_views;
  std::vector<GoalRecord> goals = m_goals;
  if (m_goal) goals.push_back(*m_goal);  // the one being driven to (the live view's)
  for (const GoalRecord& g : goals) {
    const Eigen::Isometry3d T = exploration::cameraPoseOf(g.goal, m_T_base_cam);
    SceneView v;
    v.position = T.translation();
    v.direction = T.linear().col(2);
    v.gain = g.gain;
    v.goal = true;
    views.push_back(v);
  }
  return views;
}

}  // namespace rasm::autonomy
