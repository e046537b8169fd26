#pragma once
// Which classified segments objects.json reports as objects (section IV's map, as a user reads
// it): a segment whose best class is confirmed, large enough to be a thing and not the room's
// structure. The rest go to objects.json `other_segments` with the reason.

#include <Eigen/Core>

#include "rasm/classification/ClassFusion.h"
#include "rasm/classification/TClassificationParams.h"

namespace rasm::classification {

/// Whether a classified segment is reported as an object (objects.json `objects`), or why not
/// (`other_segments`): Unconfirmed, its best class never reached min_object_probability;
/// Fragment, fewer than min_object_surfels surfels or no extent above min_object_size_m;
/// Structure, a thin plane larger than structure_min_extent_m both ways (floor, wall, ceiling);
/// RarelyDetected (objects of ObjectMap.h only), detected in too few of the views in which it
/// should have been ([objects] min_existence_probability).
enum class ObjectVerdict { Object, Unconfirmed, Fragment, Structure, RarelyDetected };
const char* toString(ObjectVerdict v);
/// Whether a shape of these extents (any order) is structure: a thin plane larger than
/// structure_min_extent_m both ways.
bool isStructure(const Eigen::Vector3d& extents_m, const TClassificationParams& params);
/// `extents_m`: the segment's principal extents (any order).
ObjectVerdict objectVerdict(const SegmentClass& c, const Eigen::Vector3d& extents_m,
                            const TClassificationParams& params);

}  // namespace rasm::classification
