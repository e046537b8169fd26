#include "ReactiveConfig.h"

#include <sstream>

namespace rasm::navigation {

std::vector<Eigen::Vector2f> growFootprint(const std::vector<Eigen::Vector2f>& footprint,
                                           double margin_m) {
  std::vector<Eigen::Vector2f> out;
  out.reserve(footprint.size());
  for (const Eigen::Vector2f& v : footprint) {
    const float r = v.norm();
    out.push_back(r > 1e-6f ? Eigen::Vector2f(v * ((r + float(margin_m)) / r)) : v);
  }
  return out;
}

namespace {

// Multi-objective scoring of MRPT's example config: kept verbatim (its formulas are exprtk).
const char* kMotionScores = R"INI(
[CMultiObjectiveMotionOptimizerBase]
score1_name     = target_distance
score1_formula  = var effective_trg_d_norm := max(0,target_d_norm-move_cur_d); if(collision_free_distance>effective_trg_d_norm, 1/(1+effective_trg_d_norm^2), 0)
score2_name     = collision_free_distance_score
score2_formula  = var effective_trg_d_norm := max(0,target_d_norm-move_cur_d); if (collision_free_distance>(effective_trg_d_norm+0.05), 1.0, collision_free_distance)
score3_name     = euclidean_nearness
score3_formula  = 1/(1+dist_eucl_min^2)
score4_name     = hysteresis_score
score4_formula  = hysteresis
score5_name     = path_index_near_target
score5_formula  = var dif:=abs(target_k-move_k); if (dif>(num_paths/2)) { dif:=num_paths-dif; }; exp(-abs(dif / (num_paths/10.0)));
score6_name     = ptg_priority_score
score6_formula  = ptg_priority
scores_to_normalize =

[CMultiObjMotionOpt_Scalarization]
scalar_score_formula = ptg_priority_score*(0.3*target_distance + 0.5*collision_free_distance_score + 8.0*euclidean_nearness + 0.1*hysteresis_score + 0.2*path_index_near_target)

[CHolonomicFullEval]
factorWeights        = [0.25 , 0.1 , 1  , 0.05 , 0.5, 1, 1 ]
factorNormalizeOrNot = [0    , 0   , 0  , 0    , 1  , 1, 0 ]
TOO_CLOSE_OBSTACLE = 0.15
TARGET_SLOW_APPROACHING_DISTANCE = 0.10
OBSTACLE_SLOW_DOWN_DISTANCE = 0.15
HYSTERESIS_SECTOR_COUNT = 5
LOG_SCORE_MATRIX = false
clearance_threshold_ratio = 0.10
gap_width_ratio_threshold = 0.20
PHASE_COUNT = 3
PHASE1_FACTORS = [6]
PHASE1_THRESHOLD = 0.5
PHASE2_FACTORS = [4]
PHASE2_THRESHOLD = 0.7
PHASE3_FACTORS = [0 2]
PHASE3_THRESHOLD = 0.7

[CHolonomicND]
WIDE_GAP_SIZE_PERCENT = 0.25
MAX_SECTOR_DIST_FOR_D2_PERCENT = 0.25
RISK_EVALUATION_SECTORS_PERCENT = 0.10
RISK_EVALUATION_DISTANCE = 0.40
TOO_CLOSE_OBSTACLE = 0.15
TARGET_SLOW_APPROACHING_DISTANCE = 0.60
factorWeights = 1.00 0.50 2.00 0.40

[CHolonomicVFF]
TARGET_SLOW_APPROACHING_DISTANCE = 0.10
TARGET_ATTRACTIVE_FORCE = 20.0

[CPointCloudFilterByDistance]
min_dist = 0.10
angle_tolerance = 5.0
too_old_seconds = 1.0
previous_keyframes = 1
max_deletion_ratio = 0.4
)INI";

void writePtg(std::ostream& o, int i, const char* type, const TNavigationParams& p,
              const char* extra) {
  o << "PTG" << i << "_Type = " << type << "\n"
    << "PTG" << i << "_resolution = " << p.ptg_resolution_m << "\n"
    << "PTG" << i << "_refDistance = " << p.ptg_ref_distance_m << "\n"
    << "PTG" << i << "_num_paths = " << p.ptg_num_paths << "\n"
    << "PTG" << i << "_v_max_mps = " << p.max_v_mps << "\n"
    << "PTG" << i << "_w_max_dps = " << p.max_w_degps << "\n"
    << extra;
}

}  // namespace

std::string reactiveConfigText(const TNavigationParams& p,
                               const std::vector<Eigen::Vector2f>& footprint) {
  std::ostringstream o;
  o.precision(10);
  // Our own stuck / timeout checks decide failure; MRPT's alarm is a later backstop.
  o << "[CAbstractNavigator]\n"
    << "dist_to_target_for_sending_event = 0\n"
    << "alarm_seems_not_approaching_target_timeout = " << 2.0 * p.stuck_timeout_s << "\n"
    << "dist_check_target_is_blocked = 0.6\n"
    << "hysteresis_check_target_is_blocked = 5\n"
    << "enable_time_profiler = false\n\n"
    << "[CWaypointsNavigator]\n"
    << "max_distance_to_allow_skip_waypoint = -1\nmin_timesteps_confirm_skip_waypoints = 1\n"
    << "waypoint_angle_tolerance = " << p.heading_tolerance_deg << "\n"
    << "multitarget_look_ahead = 0\n\n"
    << "[CAbstractPTGBasedReactive]\n"
    << "robotMax_V_mps = " << p.max_v_mps << "\nrobotMax_W_degps = " << p.max_w_degps << "\n"
    << "holonomic_method = " << p.holonomic_method << "\n"
    << "motion_decider_method = CMultiObjMotionOpt_Scalarization\n"
    << "ref_distance = " << p.ptg_ref_distance_m << "\n"
    << "speedfilter_tau = 0\nsecure_distance_start = 0.05\nsecure_distance_end = 0.15\n"
    << "use_delays_model = false\nmax_distance_predicted_actual_path = 0.15\n"
    << "min_normalized_free_space_for_ptg_continuation = 0.2\n"
    << "enable_obstacle_filtering = false\nevaluate_clearance = false\n"
    << kMotionScores << "\n"
    << "[CReactiveNavigationSystem]\n"
    << "min_obstacles_height = 0.0\nmax_obstacles_height = 10.0\n"
    << "PTG_COUNT = " << (p.allow_reverse ? 3 : 2) << "\n";
  writePtg(o, 0, "CPTG_DiffDrive_alpha", p,
           "PTG0_cte_a0v_deg = 57\nPTG0_cte_a0w_deg = 57\nPTG0_score_priority = 1.0\n");
  writePtg(o, 1, "CPTG_DiffDrive_C", p, "PTG1_K = 1.0\nPTG1_score_priority = 1.0\n");
  if (p.allow_reverse)
    writePtg(o, 2, "CPTG_DiffDrive_C", p, "PTG2_K = -1.0\nPTG2_score_priority = 0.5\n");
  const std::vector<Eigen::Vector2f> shape = growFootprint(footprint, p.footprint_margin_m);
  o << "RobotModel_shape2D_xs =";
  for (const auto& v : shape) o << " " << v.x();
  o << "\nRobotModel_shape2D_ys =";
  for (const auto& v : shape) o << " " << v.y();
  o << "\n";
  return o.str();
}

}  // namespace rasm::navigation
