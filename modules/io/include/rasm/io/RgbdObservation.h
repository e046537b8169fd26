#pragma once
// Conversions between rasm::RgbdFrame and mrpt::obs::CObservation3DRangeScan, shared by
// RawlogFrameSource, RawlogWriter and anything else that faces MRPT observations (live sources,
// annotated rawlogs). Conventions are documented in RawlogFrameSource.h / RawlogWriter.h.

#include <string>

#include "rasm/core/RgbdFrame.h"

namespace mrpt::obs {
class CObservation3DRangeScan;
}

namespace rasm::io {

struct ObservationToFrameOptions {
  /// Read sensorPose as the ground-truth camera pose (T_world_sensor, MRPT sensor frame).
  bool sensor_pose_is_ground_truth = false;
};

/// RgbdFrame from an observation whose images are in memory (call obs.load() first for external
/// storage). `source` names the observation in error messages ("rawlog x.rawlog, frame 3").
/// Leaves timestamp_s, index, odometry to the caller. Throws InputError for missing range image,
/// mismatched sizes, invalid intrinsics or non-finite depth.
RgbdFrame frameFromObservation(const mrpt::obs::CObservation3DRangeScan& obs,
                               const std::string& source,
                               const ObservationToFrameOptions& opt = {});

struct FrameToObservationOptions {
  std::string sensor_label = "RGBD";
  /// rangeImage units (m). 1 mm is MRPT's and OpenNI's default; depth above 65.535 m (u16 max)
  /// is stored as 0 (invalid).
  float range_units_m = 0.001f;
  /// Store gt_T_world_cam (when present) as sensorPose; else the identity.
  bool sensor_pose_from_ground_truth = true;
};

/// Fills `obs` (depth + registered colour, coinciding cameras, timestamp, sensor pose).
void observationFromFrame(const RgbdFrame& frame, mrpt::obs::CObservation3DRangeScan& obs,
                          const FrameToObservationOptions& opt = {});

}  // namespace rasm::io
