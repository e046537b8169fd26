#pragma once
// Parameters of surfel map fusion (II-B initialization, II-D fusion and cleanup, III segment
// weights, V-B view bins), INI section [fusion]. Defaults are the paper's values where it gives
// them (sigma = 0.6) and ElasticFusion's (Whelan et al. 2016) otherwise.

#include <mrpt/config/CLoadableOptions.h>

#include <string>

namespace rasm::fusion {

struct TFusionParams : public mrpt::config::CLoadableOptions {
  // ---- measurements (II-B) ----
  float confidence_sigma = 0.6f;  ///< sigma of w = exp(-gamma^2 / (2 sigma^2)) (II-B)
  float min_depth_m = 0.1f;       ///< pixels outside [min, max] depth are not fused
  float max_depth_m = 5.0f;
  /// Measurements seen at more than this angle between the viewing ray and the normal are not
  /// fused (grazing pixels have unreliable depth and huge radii).
  float max_incidence_deg = 80.0f;

  // ---- association through the 4x index map (II-D) ----
  /// |z_surfel - z_measured| (camera frame) allowed for a candidate: max(abs, rel * z).
  float assoc_max_depth_diff_m = 0.03f;
  float assoc_max_depth_diff_rel = 0.01f;
  /// Angle between surfel and measured normal. ElasticFusion uses 0.5 rad, but the normals of raw
  /// Kinect depth (3x3 differences of the bilateral-filtered level 0) are noisy: a tight gate
  /// rejects correct matches and each rejected pixel adds a duplicate surfel, which then costs
  /// every later frame (all passes are O(surfels in view)). Sweep, `rasm run`, 2 threads:
  ///   gate   TUM fr1/xyz: added per frame, ATE   redkitchen: ATE, frames/s, map   sim 60 s: ATE,
  ///   map 30     2.8% of valid pixels, 0.30 cm       2.60 cm, 12.2-12.8, 1.25M         0.67
  ///   cm, 4.2M 40           -                             2.51 cm, 14.1, 1.04M                   -
  ///   45     1.2%, 0.29 cm                       2.49 cm, 14.5-14.8, 0.96M         0.64 cm, 3.3M
  ///   50     1.0%, 0.29 cm                       2.48 cm, 15.3-15.6, 0.88M         0.63 cm, 3.1M
  ///   60     0.8%, 0.30 cm                       2.55 cm, 16.6, 0.77M                   -
  /// 50 deg is the most accurate on all three (45-50 ties); surfaces meeting at more than 50 deg
  /// (walls, floors, box faces) still never share surfels. Above it redkitchen degrades.
  float assoc_max_normal_angle_deg = 50.0f;
  /// Keller et al. 2013 / ElasticFusion: position, normal, colour and radius are averaged only
  /// when the new radius is < ratio * the surfel radius (a finer or equal measurement); otherwise
  /// only confidence and time are updated.
  float radius_update_ratio = 1.5f;
  /// Within that gate the radius is averaged like position and normal (true, ElasticFusion), or
  /// only with smaller measurements (false: "radii only shrink", a coarser view never blurs a
  /// finer surfel). Shrinking only biases radii down: a room circled for 10 minutes keeps
  /// shrinking its surfels and filling the gaps with new ones (+0.8% surfels per lap at a constant
  /// disc area), so the map never plateaus; averaged, it does (docs/io.md "Memory on
  /// long runs": surfels +2.0% / RSS +3.5% over the second half of 10 minutes, against +3.9% /
  /// +6.9%), with TUM / redkitchen ATE unchanged within 0.01 mm / 0.1 mm.
  bool average_radius = true;
  /// A pixel without a candidate in its own 4x4 block adds no surfel when a surfel of a
  /// neighbouring block covers its ray within the gates (kernels::AssociateUpdateKernel::
  /// coveredByNeighbour): prevents duplicates caused by the one-pixel-per-surfel association.
  bool neighbour_coverage_check = true;

  // ---- confidence and stability (II-D) ----
  float stable_confidence = 10.0f;  ///< confidence at which a surfel becomes stable (ElasticFusion)
  float max_confidence = 0.0f;      ///< cap of the accumulated confidence; 0 = none

  // ---- cleanup (II-D) ----
  /// Unstable surfels older than this (since instantiation) are removed; ElasticFusion uses 200
  /// frames (6.7 s at 30 Hz).
  double unstable_max_age_s = 5.0;
  /// ... and unstable surfels not fused for this long (duplicates that never win an association,
  /// noise seen once) go earlier, so they do not pile up for the whole age window.
  double unstable_max_idle_s = 1.0;
  bool carve_free_space = true;
  /// A surfel in view is in free space when it is in front of the measured depth of the pixel it
  /// projects to (and of its 3x3 neighbours) by more than max(abs, rel * depth).
  float carve_margin_m = 0.05f;
  float carve_margin_rel = 0.02f;
  /// Free-space evidence against a STABLE surfel multiplies its confidence by this factor and
  /// clears the stable flag once it falls below stable_confidence; the next violation removes it.
  /// Unstable violators are removed at once. (The paper removes all violators; one bad pose would
  /// then erase stable structure, so stable surfels need repeated evidence: 2-3 frames.)
  float carve_stable_decay = 0.5f;
  /// Merge redundant surfels of the view (Keller et al. 2013, sec. 4.3): two surfels whose
  /// centres project into the same pixel, with normals within merge_max_normal_angle_deg, centres
  /// within the association depth gate along the normal and overlapping discs, become one
  /// (kernels::MergeTest, kernels::mergeSurfels). Without it the duplicates that noise and
  /// sub-pixel motion create, once stable, are never removed: on 7-Scenes redkitchen the
  /// surfels in view grew from 0.56M to 0.95M for the same 307k pixels. CPU backend only.
  bool merge_redundant = true;
  float merge_max_normal_angle_deg = 15.0f;
  /// Each frame merges in every n-th image row only (rows y = k mod n at the k-th merging frame):
  /// a duplicate lives a few frames longer, and merging costs 1/n (on redkitchen at 2 threads
  /// all rows took ~20 ms per frame late in the sequence, 3% of the surfels in view merged).
  int merge_row_stride = 4;

  // ---- memory order ----
  /// Before fusing a frame, re-sort the store block by block (SurfelStore::sortByBlock) once more
  /// than this fraction of its surfels was appended or moved since the last sort, so that the
  /// index-map render, association and update read the arrays in order. 1 = never.
  float resort_unsorted_fraction = 0.5f;

  // ---- segments (III) ----
  /// With a propagated label image L^p: same label -> w_l += w, else w_l -= w and relabel at 0.
  bool update_segments = true;

  // ---- view information bins (V-B) ----
  bool update_view_bins = true;
  float ic_lambda1 = 0.5f;  ///< IC(s) = exp(-lambda1 (max(||p - t||, d_min) - d_min)), 1/m
  float ic_d_min_m = 1.0f;

  void loadFromConfigFile(const mrpt::config::CConfigFileBase& c,
                          const std::string& section) override;
  void saveToConfigFile(mrpt::config::CConfigFileBase& c,
                        const std::string& section) const override;
};

}  // namespace rasm::fusion
