#pragma once
// The closed loop of an exploring run (sections V and VI): after each frame the Mapper processed,
//   localisation  the robot base's pose in the map: the last frame's estimated camera pose
//                 (T_world_cam T_base_cam^-1, on the floor) carried on by the odometry since it;
//   planning      the exploration planner ([exploration] planner: information gain, or a
//                 baseline) on a map snapshot and the occupancy octree of ExplorationStage, when
//                 the robot has arrived or given up, and every replan_period_s while it drives
//                 (a mid-way switch only when the new view is clearly better);
//   navigation    MRPT's reactive navigator drives the robot to the chosen SE(2) view; a
//                 RobotDriver steps it (RobotDriver.h, VI): in the simulator's substeps
//                 (SimulatedSequence::setSubstepHook), or in a thread of its own at [navigation]
//                 period_s of wall time on a real robot (WallClockRobotDriver);
//   stopping      [exploration]'s rule: the best view gains too little for stop_plans plans, the
//                 planner has nothing left, or a time / path budget is spent;
//   metrics       with the simulator's ground truth: surface coverage and the fraction of the
//                 world's detectable objects carrying their right class, over time. A real robot
//                 has none: its metrics rows carry time, path, entropy and surfels only, and the
//                 report's coverage fields are null.
// Workspace (V-A): the simulated world's bounds ([exploration] workspace_from_world), else (a real
// robot) [exploration] workspace_*. Times are seconds since the first frame.
// Threads ([exploration] planner_thread): true, the planner runs in a thread of its own on map
// snapshots and a copy of the octree while mapping goes on, and its plan is applied on a later
// frame (a robot); false, it runs on the mapping thread between frames at simulated times, so a
// seed gives one run (the simulated embedded default, the evaluation, the tests).
// It starts with one turn in place (the map of one frame has no free space to plan in).

#include <chrono>
#include <condition_variable>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <thread>
#include <utility>
#include <vector>

#include <nlohmann/json.hpp>

#include "rasm/autonomy/ExplorationMetrics.h"
#include "rasm/autonomy/RobotDriver.h"
#include "rasm/autonomy/SceneView.h"
#include "rasm/exploration/ExplorationPlanner.h"
#include "rasm/exploration/ViewCandidates.h"
#include "rasm/fusion/TFusionParams.h"
#include "rasm/navigation/Navigator.h"
#include "rasm/pipeline/Mapper.h"
#include "rasm/pipeline/stages/ExplorationStage.h"

namespace rasm::sim {
class SimulatedSequence;
class SurfaceCoverage;
}  // namespace rasm::sim

namespace rasm::autonomy {

class SimObjectScore;

class ExplorationLoop {
 public:
  /// `seq`: the commanded simulated sequence the frames come from (its robot is driven in its
  /// substeps; ground-truth metrics).
  ExplorationLoop(pipeline::Mapper& mapper, sim::SimulatedSequence& seq,
                  const navigation::TNavigationParams& nav_params);
  /// Any robot (a real one): `driver` steps the navigator (WallClockRobotDriver); `footprint`:
  /// the robot's polygon (robot frame); no ground truth.
  ExplorationLoop(pipeline::Mapper& mapper, std::unique_ptr<RobotDriver> driver,
                  const std::vector<Eigen::Vector2f>& footprint,
                  const navigation::TNavigationParams& nav_params);
  ~ExplorationLoop();

  /// After the Mapper processed `frame` (result `r`): localisation, planning, stopping, metrics.
  void afterFrame(const RgbdFrame& frame, const pipeline::FrameResult& r);
  /// Why the run should end (empty while exploring).
  const std::string& stopReason() const { return m_stop_reason; }
  bool finished() const { return !m_stop_reason.empty(); }
  /// End of the run (after Mapper::finishRun): the final metrics; `reason` when no stopping rule
  /// ended it (the source ended, an error). Releases the navigator and its driver (the
  /// substep hook, the navigation thread): call it while the source (which owns the robot) still
  /// exists; the destructor does the same if not.
  void finish(const std::string& reason);

  /// One-line state for the progress line.
  std::string progressText() const;
  /// The objects measured against the simulator's truth in the last afterFrame() (every
  /// [exploration] metrics_period_s): (correct, detectable); nothing when it measured none.
  std::optional<std::pair<std::size_t, std::size_t>> objectsMeasuredThisFrame() const;
  /// Top-level report fields (coverage_fraction, objects_correct_fraction, path_length_m,
  /// sim_time_s, stop_reason) and the "exploration" block.
  void report(nlohmann::json& rep) const;
  /// exploration.json (plans, goals, metrics over time).
  void writeOutputs(pipeline::OutputFolder& out) const;
  /// The metrics over time (every [exploration] metrics_period_s, and at the end), as
  /// exploration.json "metrics" holds them; the run draws exploration.png from them.
  const std::vector<ExplorationMetricsRow>& metrics() const { return m_metrics; }
  /// Whether the metrics carry the simulator's truth (coverage, objects); a real robot's do not.
  bool groundTruth() const { return m_coverage != nullptr; }
  /// The views to draw over the map (RunScene.h, exploration.json "candidate_views"): the
  /// candidates of the last plan that offered any (reachable ones with their gain, unreachable
  /// ones), then every goal driven to, the current one included.
  std::vector<SceneView> sceneViews() const;

 private:
  struct GoalRecord {
    Eigen::Vector3d goal;
    double t_start = 0, t_end = -1;
    std::string source, outcome;
    double gain = 0, entropy_reduction = 0, information = 0;
    std::vector<Eigen::Vector2d> route;  ///< the waypoints given to the navigator before it
  };
  /// What a plan is computed from (taken on the mapping thread).
  struct PlanRequest {
    double t = 0;
    bool driving = false;
    Eigen::Vector3d robot = Eigen::Vector3d::Zero();
    CameraIntrinsics K;
    std::optional<Eigen::Vector3d> goal;  ///< the goal being driven to (for a switch)
    const exploration::OccupancyOctree* octree = nullptr;
    std::unique_ptr<exploration::OccupancyOctree> octree_copy;  ///< planner thread: a copy
  };
  struct PlanOutput {
    exploration::Plan plan;
    double t = 0, ms = 0;
    double snapshot_ms = 0;  ///< of ms: copying the map and indexing the copy
    bool driving = false;
    Eigen::Vector3d robot = Eigen::Vector3d::Zero();
    std::optional<Eigen::Vector3d> goal;
    double current_goal_score = -1;  ///< the goal's score in this plan's units (-1: none)
    /// The way to the plan's best view around walls (exploration::routeTo on the plan's grid):
    /// the navigator's waypoints before it.
    std::vector<Eigen::Vector2d> route;
    std::string error;  ///< the planner thread's exception
  };
  void start(const std::vector<Eigen::Vector2f>& footprint,
             const navigation::TNavigationParams& nav_params);
  Eigen::Vector3d estimatedBasePose() const;
  // The navigator's calls from the mapping thread, serialised with the driver's stepping.
  navigation::NavState navState() const;
  std::string navFailureReason() const;
  void navSetGoal(const Eigen::Vector3d& goal, const std::vector<Eigen::Vector2d>& via = {});
  void navCancel();
  /// Plans now (deterministic mode) or asks the planner thread to ([exploration] planner_thread).
  void plan(double t, bool driving);
  PlanOutput computePlan(const PlanRequest& req);
  std::vector<Eigen::Vector2d> routeToBest(const exploration::Plan& p,
                                           const exploration::OccupancyOctree& octree,
                                           const Eigen::Vector3d& robot) const;
  void applyPlan(const PlanOutput& out);
  void plannerThread();
  void takeThreadedPlan();
  /// A goal's outcome to the planner (queued for the planner thread when it runs).
  void reportOutcome(const Eigen::Vector3d& goal, bool reached);
  void startGoal(const exploration::ViewCandidate& c, const std::vector<Eigen::Vector2d>& route,
                 double t);
  void endGoal(double t, const std::string& outcome);
  void measure(double t);
  static std::vector<SceneView> candidateViews(const exploration::Plan& p);
  void stop(const std::string& reason);
  void release();

  pipeline::Mapper& m_mapper;
  pipeline::ExplorationStage& m_stage;
  sim::SimulatedSequence* m_seq = nullptr;  ///< the simulated sequence (ground truth), or null
  std::unique_ptr<RobotDriver> m_driver;
  robot::IRobot* m_robot = nullptr;  ///< the driver's robot
  Eigen::Isometry3d m_T_base_cam;
  CameraIntrinsics
      m_K;  ///< the intrinsics of the frames the run receives (planning predicts with them)
  mutable std::mutex m_nav_mx;  ///< the navigator: driver stepping vs the mapping thread
  mutable std::mutex m_loc_mx;  ///< the localisation estimate (read by the navigator)
  std::unique_ptr<navigation::Navigator> m_nav;  ///< null once released (finish())
  navigation::NavState m_nav_final = navigation::NavState::Idle;
  std::unique_ptr<exploration::ExplorationPlanner> m_planner;
  // The simulator's ground truth, null on a real robot (shared_ptr: without the simulator,
  // -DRASM_WITH_SIM=OFF, these types stay incomplete and nothing creates them).
  std::shared_ptr<sim::SurfaceCoverage> m_coverage;
  std::shared_ptr<SimObjectScore> m_object_score;
  pipeline::MapSnapshot m_snapshot;
  // Localisation: the base pose estimated at the last frame and the odometry then.
  Eigen::Vector3d m_est_base = Eigen::Vector3d::Zero(), m_odo_at_est = Eigen::Vector3d::Zero();
  Eigen::Vector3d m_last_base = Eigen::Vector3d::Zero();
  bool m_have_est = false;
  double m_path_m = 0, m_t = 0, m_last_plan_t = -1e9, m_last_metrics_t = -1e9;
  std::optional<double> m_t0;  ///< the first frame's timestamp (times count from it)
  std::chrono::steady_clock::time_point m_wall_t0;  ///< when the first frame arrived
  int m_spin_goals_left = 3;                        ///< the initial turn in place, in thirds
  int m_low_plans = 0, m_plans = 0;
  std::optional<GoalRecord> m_goal;
  double m_goal_rate = 0.0;  ///< rate of the current goal when chosen (for switching)
  std::vector<GoalRecord> m_goals;
  std::vector<SceneView> m_last_views;  ///< candidateViews of the last plan that offered any
  nlohmann::json m_plan_log = nlohmann::json::array();
  std::vector<ExplorationMetricsRow> m_metrics;
  std::string m_stop_reason;
  std::size_t m_frames = 0;
  fusion::TFusionParams m_fusion_params;  ///< IC parameters of the predicted view information
  // Planner thread: one request / result at a time; goal outcomes queued for the planner.
  std::thread m_worker;
  std::mutex m_mx;
  std::condition_variable m_cv;
  std::optional<PlanRequest> m_request;
  std::optional<PlanOutput> m_ready;
  std::vector<std::pair<Eigen::Vector3d, bool>> m_outcomes;
  bool m_busy = false, m_quit = false;
};

}  // namespace rasm::autonomy
