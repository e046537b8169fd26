#pragma once
// Pose consistency of the zero-shot classifier across views (paper VII-A: "the detected pose
// could be used to verify ... across multiple views", its remedy for the many false positives of
// a 16 x 16 HOG of an outline). A zero-shot detection carries the viewpoint of the template that
// matched (PoseHint: the camera's azimuth and elevation around the model). Seen along the ray
// through the box centre, that viewpoint implies an orientation of the model in the world
// (impliedModelRotation). The views of a real object imply one orientation, up to the model's
// azimuth symmetry; the false matches on a desk edge or a book imply whatever their outlines
// happened to resemble, differently from each view.
//
// PoseConsensus holds each such detection's class evidence, per (segment, best class), until a
// detection of the same class on the same segment from a view at least min_view_change_deg
// away (two images of the same outline from one place agree trivially) implies the same
// orientation within agreement_deg and within max_fraction_of_view_change of the change of view
// (an outline that matches one template whatever the view implies orientations that turn with
// the camera, as far apart as the views; a real object's stay put); then both are released to
// the map's Bayes update (IV) and every later one is released when it agrees with any earlier
// one. Evidence that never agrees is never fused. Segment ids follow the segmentation's merges
// (relabel).
//
// The camera's roll about the line of sight is taken as the model's: the camera's up (-y) is the
// model's up seen from there, as for an upright robot camera or a hand-held one held level (the
// world frame need not be gravity aligned, as the datasets' are not). That is exact on the image
// centre column; off it, on a camera pitched down, the up seen along the ray is rolled by about
// (horizontal offset) x sin(pitch): 2.4 degrees 10 degrees off centre at a 14-degree pitch.

#include <Eigen/Core>
#include <cstddef>
#include <cstdint>
#include <map>
#include <utility>
#include <vector>

#include "rasm/classification/ClassFusion.h"
#include "rasm/classification/Detection.h"

namespace rasm::classification {

/// R_world_model implied by a template viewpoint `pose` matched on the box whose centre lies on
/// `ray_cam` (camera optical frame: x right, y down, z forward; any length > 0) of a camera with
/// rotation R_world_cam. The template camera of renderTemplateView sits at azimuth / elevation
/// around the model looking at its centre, its up the model's +z seen from there.
Eigen::Matrix3d impliedModelRotation(const PoseHint& pose, const Eigen::Matrix3d& R_world_cam,
                                     const Eigen::Vector3d& ray_cam);

/// The angle (degrees, 0..180) between two model orientations, the smallest over the model's
/// azimuth symmetry (rotations about its +z by multiples of azimuth_period_deg; 360: none).
double orientationDisagreementDeg(const Eigen::Matrix3d& R_world_model_a,
                                  const Eigen::Matrix3d& R_world_model_b,
                                  double azimuth_period_deg);

struct PoseObservation {
  Eigen::Matrix3d R_world_model = Eigen::Matrix3d::Identity();
  Eigen::Vector3d sight_world = Eigen::Vector3d::UnitZ();  ///< unit line of sight, camera to box
  double azimuth_period_deg = 360.0;
  std::size_t frame = 0;
  std::vector<SegmentEvidence> evidence;  ///< the detection's items (emptied once released)
  /// The surfels of its segment when it was seen (empty: the segment's at release); a held
  /// detection's evidence is fused into these, whichever segments they belong to by then. Only
  /// the 8 newest held observations of a (segment, class) keep theirs.
  std::vector<std::int32_t> surfels;
  bool released = false;
};

/// An earlier detection released by a later one: its frame, evidence and surfels.
struct ReleasedDetection {
  std::size_t frame = 0;
  std::vector<SegmentEvidence> evidence;
  std::vector<std::int32_t> surfels;
};

class PoseConsensus {
 public:
  PoseConsensus(double agreement_deg = 30.0, double min_view_change_deg = 10.0,
                double max_fraction_of_view_change = 0.7);

  struct Released {
    std::vector<SegmentEvidence> evidence;   ///< this detection's, when released
    bool this_one = false;                   ///< whether the added detection is released
    std::vector<ReleasedDetection> earlier;  ///< held ones released by it
  };
  /// Adds a detection of `class_id` on `segment` (its evidence items name that segment) and
  /// returns what agreement releases now.
  Released add(std::uint32_t segment, int class_id, PoseObservation observation);

  /// Segment l becomes table[l] (0: gone, its held evidence dropped); the observations of merged
  /// segments join.
  void relabel(const std::vector<std::uint32_t>& table);

  std::size_t heldDetections() const;  ///< waiting for an agreeing view
  std::size_t releasedDetections() const { return m_released; }

 private:
  bool agree(const PoseObservation& a, const PoseObservation& b) const;

  double m_agreement_deg, m_min_view_change_deg, m_max_fraction_of_view_change;
  std::map<std::pair<std::uint32_t, int>, std::vector<PoseObservation>> m_observations;
  std::size_t m_released = 0;
};

}  // namespace rasm::classification
