#pragma once
// Internal: colour of another camera resampled into the depth camera (rasm::registerColourToDepth)
// with the holes filled: pixels without a depth measurement take the colour seen along their ray
// at the frame's median depth, so image-space consumers (detectors, edge maps) get a complete
// image instead of black holes. Their parallax error is baseline * f * |1/z - 1/z_median|, a few
// pixels for a Kinect, and those pixels carry no geometry anyway.

#include <Eigen/Geometry>

#include "rasm/core/RgbdFrame.h"

namespace rasm::io::detail {

void registerColourToDepthFilled(const Image<float>& depth_m, const CameraIntrinsics& K_depth,
                                 const Image<Bgr8>& colour, const CameraIntrinsics& K_colour,
                                 const Eigen::Isometry3d& T_colour_depth, Image<Bgr8>& out);

}  // namespace rasm::io::detail
