#pragma once
// The next-best-view planner of section V: candidate views (random + object views), pruned by
// reachability, scored by IG(a) = w1 dH + w2 dIC and ranked. Works on a map snapshot (surfel
// store + segment table, never the live map) and the occupancy octree; deterministic for a fixed
// params.seed (the random views are the only random part; ties keep the candidates' order).
//
// Normalisation: dH (nats) and dIC (pixel-weighted IC) have unrelated units and scales, so each
// is divided by its largest value over the reachable candidates of this plan before weighting:
// IG(a) = w1 dH(a) / max dH + w2 dIC(a) / max dIC, in [0, w1 + w2]; the weights then say how much
// the best exploring view counts against the best object view. A term whose maximum is 0 (no
// surfels in any view, nothing left to explore) drops out.
// Ranking: by IG (rank_by_rate = false) or by IG per second of travel,
// IG / (travel_time_s + min_travel_time_s) (default: a nearby view that gains almost as much is
// preferred; the constant keeps views next to the robot from dominating by a vanishing time).

#include <Eigen/Geometry>
#include <vector>

#include "rasm/core/CameraIntrinsics.h"
#include "rasm/exploration/ExplorationPlanner.h"
#include "rasm/exploration/ObjectInformation.h"
#include "rasm/exploration/OccupancyOctree.h"
#include "rasm/exploration/TExplorationParams.h"
#include "rasm/exploration/ViewCandidates.h"
#include "rasm/exploration/ViewPredictor.h"
#include "rasm/segmentation/SegmentTable.h"
#include "rasm/surfel_map/SurfelStore.h"

namespace rasm::exploration {

class ViewPlanner {
 public:
  /// Throws InputError when the params are out of range.
  explicit ViewPlanner(const TExplorationParams& params = {});

  /// Candidates, pruning, prediction and ranking for one snapshot (Plan::blacklisted stays empty
  /// and best_* 0: IgPlanner adds those). Throws InputError when an input pointer is null.
  Plan plan(const PlannerInputs& in) const;

 private:
  std::vector<int> screenCandidates(const maps::SurfelStore& store, const PlannerInputs& in,
                                    const std::vector<ViewCandidate>& candidates,
                                    const std::vector<int>& reachable, int goal_index,
                                    Plan& plan) const;

  TExplorationParams m_params;
};

/// IG(a) = w1 dH / max dH + w2 dIC / max dIC (V, the score of a view; the normalisation of the
/// header comment: a term whose maximum is 0 drops out). The one place the formula is written.
double informationGain(const TExplorationParams& params, double entropy_reduction,
                       double information, double max_entropy_reduction, double max_information);

/// The key views are ranked by: rate (IG per second of travel) when params.rank_by_rate, else
/// gain.
double rankingKey(const TExplorationParams& params, const ViewCandidate& c);

/// Sets gain and rate of each candidate from its dH, dIC and travel time (normalised as in the
/// header comment), in place; `alongside` as in rankCandidates.
void scoreCandidates(const TExplorationParams& params, std::vector<ViewCandidate>& candidates,
                     ViewCandidate* alongside = nullptr);

/// Sets gain and rate of each candidate from its dH, dIC and travel time (normalised as in the
/// header comment) and sorts them best first (stable). `alongside` (the goal the robot drives to)
/// is scored with the same maxima, its own dH and dIC included in them, and not sorted in.
void rankCandidates(const TExplorationParams& params, std::vector<ViewCandidate>& candidates,
                    ViewCandidate* alongside = nullptr);

}  // namespace rasm::exploration
