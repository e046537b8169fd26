#pragma once
// Object-centric information of section V-B: the predicted gain in the surfels' view-information
// bins b_v from a candidate view, weighted towards surfels whose class is uncertain.
//
// Fusion keeps, per surfel, the best IC(s) = exp(-lambda1 (max(||p - t||, d_min) - d_min)) seen
// from each view bin (azimuth / elevation of the camera in the surfel frame (b, n x b, n)). A
// candidate view at camera centre t would raise the bin it falls in to max(b_v(i), IC). The
// predicted gain of the view is the paper's pixel-wise sum over the surfel index map rendered at
// the candidate pose (occluded and back-facing surfels are not in it):
//     dIC = sum_pixels u(s) max(0, IC_t(s) - b_v(s)[bin_t(s)]),
// so a surfel counts once per pixel it covers (pixels on target). The bin and IC are computed by
// the very functions fusion updates the bins with (ViewBins.h: viewBinIndex, informationContent;
// quantised as the store keeps them, so a view fusion has just integrated predicts 0).
//
// Class uncertainty weight u(s) (IV evidence, ClassEvidence.h): surfels with evidence weigh
// max(floor, 1 - |2 p_best - 1|), p_best the probability of their best class (0.5 when no class
// rose above the prior): 1 for a surfel the detectors disagree on or have just started on, the
// floor for a settled one. Surfels without any evidence weigh the floor: most of them are walls
// and floor no detector fires on, and V-B's purpose is to settle the classes of objects.

#include <Eigen/Geometry>
#include <cstdint>

#include "rasm/core/Image.h"
#include "rasm/surfel_map/ClassEvidence.h"
#include "rasm/surfel_map/SurfelStore.h"

namespace rasm::fusion {
struct TFusionParams;
}

namespace rasm::exploration {

/// The IC parameters and the bin layout fusion uses ([fusion] ic_lambda1, ic_d_min_m; the map's
/// view_bins_azimuth x view_bins_elevation).
struct ViewInfoModel {
  float lambda1 = 0.5f, d_min_m = 1.0f;
  int n_azimuth = 8, n_elevation = 2;
  static ViewInfoModel of(const fusion::TFusionParams& fusion, const maps::SurfelStoreOptions& map);
};

/// u(s) of the header comment.
float classUncertaintyWeight(const maps::ClassEvidence& evidence, float floor);

struct InformationGain {
  double weighted = 0.0;    ///< dIC: sum of u(s) times the bin gain over the pixels
  double unweighted = 0.0;  ///< the same sum with u = 1
  int pixels = 0;           ///< pixels showing a surfel
};

/// dIC of the view from T_world_cam (optical frame) whose rendered surfel index map (II-A I^r,
/// -1 = none; SurfelRenderer::render's `index`) is `index`.
InformationGain predictedInformationGain(const maps::SurfelStore& store,
                                         const Image<std::int32_t>& index,
                                         const Eigen::Isometry3d& T_world_cam,
                                         const ViewInfoModel& model, float weight_floor);

}  // namespace rasm::exploration
