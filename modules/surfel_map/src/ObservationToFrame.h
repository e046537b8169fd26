#pragma once
// Minimal CObservation3DRangeScan -> RgbdFrame conversion for CSurfelMap::insertObservation().
// (io's frameFromObservation is the full converter; surfel_map keeps this small one so the map does
// not depend on the io module's readers.)

#include <string>

#include "rasm/core/RgbdFrame.h"

namespace mrpt::obs {
class CObservation3DRangeScan;
}

namespace rasm::maps::detail {

/// Depth in metres (range_is_depth = false is converted to z), colour registered to the depth
/// camera (copied when the cameras coincide, else resampled), depth intrinsics, timestamp.
/// Throws InputError naming `source` when there is no range image or the intrinsics are invalid.
RgbdFrame frameFromRangeScan(const mrpt::obs::CObservation3DRangeScan& obs, const std::string& source);

}  // namespace rasm::maps::detail
