#include "rasm/tracking/LoopClosureParams.h"

#include <mrpt/config/CConfigFileBase.h>

#include <string>

#include "ParamsPut.h"
#include "rasm/core/Error.h"
#include "rasm/core/Params.h"

namespace rasm::tracking {

namespace {
using detail::put;
}  // namespace

void TLoopClosureParams::loadFromConfigFile(const mrpt::config::CConfigFileBase& c,
                                            const std::string& s) {
  MRPT_LOAD_CONFIG_VAR_CS(enabled, bool);
  MRPT_LOAD_CONFIG_VAR_CS(node_every_s, double);
  MRPT_LOAD_CONFIG_VAR_CS(chain_sigma_m_per_m, double);
  MRPT_LOAD_CONFIG_VAR_CS(chain_sigma_deg_per_deg, double);
  MRPT_LOAD_CONFIG_VAR_CS(chain_sigma_deg_per_m, double);
  MRPT_LOAD_CONFIG_VAR_CS(chain_sigma_weak_factor, double);
  MRPT_LOAD_CONFIG_VAR_CS(chain_sigma_min_m, double);
  MRPT_LOAD_CONFIG_VAR_CS(chain_sigma_min_deg, double);
  MRPT_LOAD_CONFIG_VAR_CS(loop_sigma_m, double);
  MRPT_LOAD_CONFIG_VAR_CS(loop_sigma_deg, double);
  MRPT_LOAD_CONFIG_VAR_CS(inactive_after_s, double);
  MRPT_LOAD_CONFIG_VAR_CS(check_every_frames, int);
  MRPT_LOAD_CONFIG_VAR_CS(min_inactive_fraction, double);
  MRPT_LOAD_CONFIG_VAR_CS(min_eigenvalue, double);
  MRPT_LOAD_CONFIG_VAR_CS(confirmations, int);
  MRPT_LOAD_CONFIG_VAR_CS(confirmation, string);
  MRPT_LOAD_CONFIG_VAR_CS(feature_agreement_m, double);
  MRPT_LOAD_CONFIG_VAR_CS(feature_agreement_deg, double);
  MRPT_LOAD_CONFIG_VAR_CS(min_correction_m, double);
  MRPT_LOAD_CONFIG_VAR_CS(min_correction_deg, double);
  MRPT_LOAD_CONFIG_VAR_CS(max_correction_m, double);
  MRPT_LOAD_CONFIG_VAR_CS(drift_m_per_m, double);
  MRPT_LOAD_CONFIG_VAR_CS(max_correction_deg, double);
  MRPT_LOAD_CONFIG_VAR_CS(drift_deg_per_m, double);
  validate(s);
}

void TLoopClosureParams::saveToConfigFile(mrpt::config::CConfigFileBase& c,
                                          const std::string& s) const {
  put(c, s, "enabled", enabled, "register frames against the inactive map and close loops");
  put(c, s, "node_every_s", node_every_s, "a tracked frame becomes a graph node this often (s)");
  put(c, s, "chain_sigma_m_per_m", chain_sigma_m_per_m, "chain edge sigma per metre travelled");
  put(c, s, "chain_sigma_deg_per_deg", chain_sigma_deg_per_deg,
      "chain edge sigma per degree turned");
  put(c, s, "chain_sigma_deg_per_m", chain_sigma_deg_per_m,
      "chain edge rotation sigma per metre travelled");
  put(c, s, "chain_sigma_weak_factor", chain_sigma_weak_factor,
      "chain sigmas times up to this where frames were degenerate or lost");
  put(c, s, "chain_sigma_min_m", chain_sigma_min_m, "chain edge translation sigma, at least (m)");
  put(c, s, "chain_sigma_min_deg", chain_sigma_min_deg, "chain edge rotation sigma, at least");
  put(c, s, "loop_sigma_m", loop_sigma_m, "loop constraint translation sigma (m)");
  put(c, s, "loop_sigma_deg", loop_sigma_deg, "loop constraint rotation sigma (deg)");
  put(c, s, "inactive_after_s", inactive_after_s,
      "surfels created this long ago are the inactive map (s)");
  put(c, s, "check_every_frames", check_every_frames,
      "register a tracked frame against the inactive map every N frames");
  put(c, s, "min_inactive_fraction", min_inactive_fraction,
      "... when it covers this fraction of the frame's valid pixels");
  put(c, s, "min_eigenvalue", min_eigenvalue,
      "a registration moves the camera only along directions held this well");
  put(c, s, "confirmations", confirmations,
      "consecutive checks that must ask for the same correction");
  put(c, s, "confirmation", confirmation,
      "colour | features | none: what must put the camera there too");
  put(c, s, "feature_agreement_m", feature_agreement_m, "... within this (m) or 30% ...");
  put(c, s, "feature_agreement_deg", feature_agreement_deg, "... and this (deg) or 30%");
  put(c, s, "min_correction_m", min_correction_m, "smaller corrections are agreement (m) ...");
  put(c, s, "min_correction_deg", min_correction_deg, "... and (deg)");
  put(c, s, "max_correction_m", max_correction_m,
      "refuse corrections beyond this (m) plus drift_m_per_m x path");
  put(c, s, "drift_m_per_m", drift_m_per_m, "drift allowed per metre of path since the old map");
  put(c, s, "max_correction_deg", max_correction_deg,
      "refuse rotations beyond this (deg) plus drift_deg_per_m x path");
  put(c, s, "drift_deg_per_m", drift_deg_per_m, "rotation drift allowed per metre of path");
}

void TLoopClosureParams::validate(const std::string& s) const {
  requireInRange(node_every_s, 0.01, 60.0, s, "node_every_s");
  requireInRange(chain_sigma_m_per_m, 1e-6, 10.0, s, "chain_sigma_m_per_m");
  requireInRange(chain_sigma_deg_per_deg, 1e-6, 10.0, s, "chain_sigma_deg_per_deg");
  requireInRange(chain_sigma_deg_per_m, 0.0, 90.0, s, "chain_sigma_deg_per_m");
  requireInRange(chain_sigma_weak_factor, 1.0, 1e4, s, "chain_sigma_weak_factor");
  requireInRange(chain_sigma_min_m, 1e-6, 10.0, s, "chain_sigma_min_m");
  requireInRange(chain_sigma_min_deg, 1e-6, 90.0, s, "chain_sigma_min_deg");
  requireInRange(loop_sigma_m, 1e-6, 10.0, s, "loop_sigma_m");
  requireInRange(loop_sigma_deg, 1e-6, 90.0, s, "loop_sigma_deg");
  requireInRange(inactive_after_s, 0.1, 1e6, s, "inactive_after_s");
  requireInRange(check_every_frames, 1, 1e6, s, "check_every_frames");
  requireInRange(min_inactive_fraction, 0.0, 1.0, s, "min_inactive_fraction");
  requireInRange(min_eigenvalue, 0.0, 10.0, s, "min_eigenvalue");
  requireInRange(confirmations, 1, 100, s, "confirmations");
  if (confirmation != "colour" && confirmation != "features" && confirmation != "none")
    throwInputError("[" + s + "] confirmation",
                    "is '" + confirmation + "'; expected colour, features or none");
  requireInRange(feature_agreement_m, 0.0, 10.0, s, "feature_agreement_m");
  requireInRange(feature_agreement_deg, 0.0, 180.0, s, "feature_agreement_deg");
  requireInRange(min_correction_m, 0.0, 10.0, s, "min_correction_m");
  requireInRange(min_correction_deg, 0.0, 180.0, s, "min_correction_deg");
  requireInRange(max_correction_m, min_correction_m, 100.0, s, "max_correction_m");
  requireInRange(drift_m_per_m, 0.0, 10.0, s, "drift_m_per_m");
  requireInRange(max_correction_deg, min_correction_deg, 180.0, s, "max_correction_deg");
  requireInRange(drift_deg_per_m, 0.0, 180.0, s, "drift_deg_per_m");
}

}  // namespace rasm::tracking
