#pragma once
// Section V-A as a stage of the Mapper, after classification (Mapper::assemble): the occupancy
// octree of exploration, updated from every fused depth frame at its tracked pose (a lost or
// relocalising frame's pose is not trusted, so it updates nothing). The stage owns the section
// [exploration]: the octree, candidate views and the information-gain score
// (exploration::TExplorationParams), and whether the run explores and the loop around the planner
// (TExplorationLoopParams: planning period, stopping rule, budgets; ExplorationLoop reads them).
// With [exploration] enabled = false (hand-held runs and replays) the stage does nothing.

#include <memory>

#include "rasm/exploration/OccupancyOctree.h"
#include "rasm/exploration/TExplorationParams.h"
#include "rasm/pipeline/MapperStage.h"

namespace rasm::pipeline {

/// [exploration]'s loop keys: the closed loop of an exploring run (section V-VI;
/// docs/exploration.md "The loop").
struct TExplorationLoopParams : mrpt::config::CLoadableOptions {
  /// "true": drive the robot by information gain (needs a robot: [source] type = sim with a
  /// robot spec; an InputError otherwise); "false": map the source as it comes; "auto" (the
  /// embedded default): explore when the source is a simulated robot spec, map otherwise (a
  /// rawlog, a hand-held path), so `rasm run --set source.path=...` maps without more keys.
  std::string enabled = "false";
  /// Camera rate (Hz) of a simulated robot the run drives, unless [sim] rate_hz sets one: 10 Hz
  /// bridges a robot's motion with the odometry prior and makes the semantic loop fit 2 cores.
  double camera_rate_hz = 10.0;
  /// Octree update from every n-th fused frame (the octree's 10 cm cells change little between
  /// consecutive frames of a robot; 2 halves its cost).
  int octree_every_n_frames = 2;
  /// While the robot drives to a view, replan every this many simulated seconds and switch to the
  /// new best view only when it is clearly better (switch_ratio); on arrival, or when the goal
  /// fails, replan at once.
  double replan_period_s = 8.0;
  double switch_ratio = 2.0;
  /// Plan in a thread of its own on map snapshots and a copy of the octree, while mapping goes
  /// on at camera rate (true), or on the mapping thread between frames (false: deterministic,
  /// the same seed gives the same run; the mapping pauses for the plan, simulated time does not
  /// advance meanwhile). A robot needs true; the simulated embedded default, the evaluation and
  /// the tests use false.
  bool planner_thread = true;
  /// Stopping rule (V): the run ends when, over stop_plans consecutive plans, the best reachable
  /// view gains less than stop_entropy_nats of map entropy AND less than stop_information of
  /// object view information (or no view is reachable), or at a budget (0 = none).
  double stop_entropy_nats = 25.0;
  double stop_information = 50.0;
  int stop_plans = 3;
  double time_budget_s = 300.0;  ///< simulated seconds
  double path_budget_m = 0.0;
  /// Wall-clock seconds from the first frame (0 = none): a time-boxed run (the embedded
  /// default's 5 minutes on 2 cores, outputs included) ends exploring here on a slow machine,
  /// with stop_reason wall_budget; on a fast one time_budget_s ends it first and the run stays
  /// deterministic.
  double wall_budget_s = 0.0;
  /// The workspace of V-A from the simulated world's bounds (walls included) when the source is
  /// the simulator, instead of [exploration] workspace_*.
  bool workspace_from_world = true;
  /// Ground-truth metrics (simulator): surface coverage and objects correctly classified, every
  /// this many simulated seconds and at the end (0: only at the end).
  double metrics_period_s = 15.0;

  void loadFromConfigFile(const mrpt::config::CConfigFileBase& c, const std::string& s) override;
  void saveToConfigFile(mrpt::config::CConfigFileBase& c, const std::string& s) const override;
};

/// The one section [exploration]: the planner's keys and the loop's, loaded and saved together
/// (their names are distinct: ExplorationStage's test checks).
struct TExplorationSection : mrpt::config::CLoadableOptions {
  TExplorationSection(exploration::TExplorationParams& planner, TExplorationLoopParams& loop)
      : planner(planner), loop(loop) {}
  exploration::TExplorationParams& planner;
  TExplorationLoopParams& loop;
  void loadFromConfigFile(const mrpt::config::CConfigFileBase& c, const std::string& s) override {
    loop.loadFromConfigFile(c, s);
    planner.loadFromConfigFile(c, s);
  }
  void saveToConfigFile(mrpt::config::CConfigFileBase& c, const std::string& s) const override {
    loop.saveToConfigFile(c, s);
    planner.saveToConfigFile(c, s);
  }
};

class ExplorationStage : public MapperStage {
 public:
  ExplorationStage() : MapperStage("occupancy") {}
  ExplorationStage(const ExplorationStage&) = delete;  // (m_section refers to the members)
  ExplorationStage& operator=(const ExplorationStage&) = delete;

  std::vector<ParamsSection> sections() override { return {{"exploration", &m_section}}; }
  void configure(const TMapperParams& mapper) override;
  void process(FrameContext& ctx, maps::CSurfelMap& map) override;
  void csvColumns(std::vector<std::string>& columns) const override;
  void csvValues(const FrameContext& ctx, CsvRow& row) const override;
  void report(nlohmann::json& rep) const override;

  const exploration::TExplorationParams& params() const { return m_params; }
  const TExplorationLoopParams& loopParams() const { return m_loop; }
  /// Whether this run explores (MappingRun decides from [exploration] enabled and the source): the
  /// octree exists only then.
  void setExploring(bool exploring);
  bool exploring() const { return m_octree != nullptr; }
  /// Replaces the workspace box of V-A (before the first frame: the octree is rebuilt empty).
  void setWorkspace(const Eigen::AlignedBox3d& box);
  /// The octree (read it from the mapping thread, between frames).
  const exploration::OccupancyOctree& octree() const { return *m_octree; }

 private:
  exploration::TExplorationParams m_params;
  TExplorationLoopParams m_loop;
  TExplorationSection m_section{m_params, m_loop};
  std::unique_ptr<exploration::OccupancyOctree> m_octree;
  std::size_t m_fused = 0, m_inserted = 0;
  bool m_inserted_this_frame = false;
};

}  // namespace rasm::pipeline
