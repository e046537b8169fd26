#include "rasm/pipeline/stages/ExplorationStage.h"

#include <mrpt/config/CConfigFileBase.h>

#include "rasm/core/Error.h"

namespace rasm::pipeline {

void TExplorationLoopParams::loadFromConfigFile(const mrpt::config::CConfigFileBase& c,
                                                const std::string& s) {
  enabled = c.read_string(s, "enabled", enabled);
  MRPT_LOAD_CONFIG_VAR(camera_rate_hz, double, c, s);
  MRPT_LOAD_CONFIG_VAR(octree_every_n_frames, int, c, s);
  MRPT_LOAD_CONFIG_VAR(replan_period_s, double, c, s);
  MRPT_LOAD_CONFIG_VAR(switch_ratio, double, c, s);
  MRPT_LOAD_CONFIG_VAR(planner_thread, bool, c, s);
  MRPT_LOAD_CONFIG_VAR(stop_entropy_nats, double, c, s);
  MRPT_LOAD_CONFIG_VAR(stop_information, double, c, s);
  MRPT_LOAD_CONFIG_VAR(stop_plans, int, c, s);
  MRPT_LOAD_CONFIG_VAR(time_budget_s, double, c, s);
  MRPT_LOAD_CONFIG_VAR(path_budget_m, double, c, s);
  MRPT_LOAD_CONFIG_VAR(wall_budget_s, double, c, s);
  MRPT_LOAD_CONFIG_VAR(workspace_from_world, bool, c, s);
  MRPT_LOAD_CONFIG_VAR(metrics_period_s, double, c, s);
  const auto need = [&](bool ok, const char* key, const char* what) {
    if (!ok) throwInputError("[" + s + "] " + key, what);
  };
  need(enabled == "true" || enabled == "false" || enabled == "auto", "enabled",
       "expected true, false or auto");
  need(camera_rate_hz > 0.0 && camera_rate_hz <= 1000.0, "camera_rate_hz", "expected (0, 1000] Hz");
  need(octree_every_n_frames >= 1, "octree_every_n_frames", "expected >= 1");
  need(replan_period_s >= 0.0, "replan_period_s", "expected >= 0 (0: replan on arrival only)");
  need(switch_ratio >= 1.0, "switch_ratio", "expected >= 1");
  need(stop_entropy_nats >= 0.0, "stop_entropy_nats", "expected >= 0");
  need(stop_information >= 0.0, "stop_information", "expected >= 0");
  need(stop_plans >= 1, "stop_plans", "expected >= 1");
  need(time_budget_s >= 0.0, "time_budget_s", "expected >= 0 (0: none)");
  need(path_budget_m >= 0.0, "path_budget_m", "expected >= 0 (0: none)");
  need(wall_budget_s >= 0.0, "wall_budget_s", "expected >= 0 wall-clock seconds (0: none)");
  need(metrics_period_s >= 0.0, "metrics_period_s", "expected >= 0 (0: at the end only)");
}

void TExplorationLoopParams::saveToConfigFile(mrpt::config::CConfigFileBase& c,
                                              const std::string& s) const {
  MRPT_SAVE_CONFIG_VAR(enabled, c, s);
  MRPT_SAVE_CONFIG_VAR(camera_rate_hz, c, s);
  MRPT_SAVE_CONFIG_VAR(octree_every_n_frames, c, s);
  MRPT_SAVE_CONFIG_VAR(replan_period_s, c, s);
  MRPT_SAVE_CONFIG_VAR(switch_ratio, c, s);
  MRPT_SAVE_CONFIG_VAR(planner_thread, c, s);
  MRPT_SAVE_CONFIG_VAR(stop_entropy_nats, c, s);
  MRPT_SAVE_CONFIG_VAR(stop_information, c, s);
  MRPT_SAVE_CONFIG_VAR(stop_plans, c, s);
  MRPT_SAVE_CONFIG_VAR(time_budget_s, c, s);
  MRPT_SAVE_CONFIG_VAR(path_budget_m, c, s);
  MRPT_SAVE_CONFIG_VAR(wall_budget_s, c, s);
  MRPT_SAVE_CONFIG_VAR(workspace_from_world, c, s);
  MRPT_SAVE_CONFIG_VAR(metrics_period_s, c, s);
}

void ExplorationStage::configure(const TMapperParams& /*mapper*/) {
  m_params.validate("exploration");
}

void ExplorationStage::setExploring(bool exploring) {
  if (!exploring)
    m_octree.reset();
  else if (!m_octree)
    m_octree = std::make_unique<exploration::OccupancyOctree>(m_params);
}

void ExplorationStage::setWorkspace(const Eigen::AlignedBox3d& box) {
  m_params.workspace_min_x_m = box.min().x();
  m_params.workspace_min_y_m = box.min().y();
  m_params.workspace_min_z_m = box.min().z();
  m_params.workspace_max_x_m = box.max().x();
  m_params.workspace_max_y_m = box.max().y();
  m_params.workspace_max_z_m = box.max().z();
  m_params.validate("exploration");
  m_octree = std::make_unique<exploration::OccupancyOctree>(m_params);
}

void ExplorationStage::process(FrameContext& ctx, maps::CSurfelMap& /*map*/) {
  m_inserted_this_frame = false;
  if (!m_octree || !ctx.result.fusable()) return;
  if (m_fused++ % std::size_t(m_loop.octree_every_n_frames) != 0) return;
  const RgbdFrame& f = *ctx.frame;
  m_octree->insertDepthFrame(f.depth_m, f.intrinsics, ctx.result.T_world_cam);
  ++m_inserted;
  m_inserted_this_frame = true;
}

void ExplorationStage::csvColumns(std::vector<std::string>& columns) const {
  columns.push_back("octree_updated");
}

void ExplorationStage::csvValues(const FrameContext& /*ctx*/, CsvRow& row) const {
  row.add(m_inserted_this_frame);
}

void ExplorationStage::report(nlohmann::json& rep) const {
  if (!m_octree) return;
  const auto counts = m_octree->countCells();
  rep["occupancy"] = {
      {"frames_inserted", m_inserted},       {"resolution_m", m_params.resolution_m},
      {"entropy_nats", m_octree->entropy()}, {"workspace_cells", m_octree->workspaceCells()},
      {"cells_free", counts.free},           {"cells_occupied", counts.occupied},
      {"cells_unknown", counts.unknown}};
}

}  // namespace rasm::pipeline
