#pragma once
// Writes RgbdFrames as an observations-only MRPT rawlog of mrpt::obs::CObservation3DRangeScan
// (+ CObservationOdometry when a frame has odometry), readable by `rawlog-edit --info`,
// RawLogViewer and RawlogFrameSource. Writes go to a temporary beside <path> ("<path>.part",
// created by rasm::AtomicFile, which never follows a link planted there) renamed to <path> by
// close(), so an interrupted run never leaves a file that looks complete.
//
// Per frame: rangeImage in units of range_units_m (default 1 mm, range_is_depth = true),
// intensityImage (BGR), cameraParams = cameraParamsIntensity = the frame intrinsics,
// relativePoseIntensityWRTDepth = (0,0,0,-90deg,0,-90deg) (registered: cameras coincide),
// timestamp = mrpt::Clock::fromDouble(timestamp_s), sensorPose = ground-truth T_world_sensor
// (mrptSensorPoseFromOptical(gt_T_world_cam)) when present. A CObservationComment carrying
// kRawlogGroundTruthMarker is written first so that readers know sensorPose is ground truth
// (even when it is the identity). A frame's odometry is written as a CObservationOdometry
// (label "ODOMETRY", same timestamp) just before its range scan.

#include <memory>
#include <string>

#include "rasm/core/RgbdFrame.h"

namespace mrpt::serialization {
class CSerializable;
}

namespace rasm::io {

struct RawlogWriterOptions {
  std::string sensor_label = "RGBD";
  /// Store images in "<rawlog stem>_Images/" (PNG) instead of inside the rawlog (MRPT external
  /// storage); keeps rawlogs small and images viewable. Applies to the colour image; depth stays
  /// inside the rawlog.
  bool external_images = false;
  /// Store the ground-truth pose (when present) as the observation's sensorPose; otherwise the
  /// identity is stored and poses live only in the trajectory file.
  bool sensor_pose_from_ground_truth = true;
  int compression_level = 1;  ///< gzip level 0-9
  /// rangeImage units in metres (see FrameToObservationOptions).
  float range_units_m = 0.001f;
};

class RawlogWriter {
 public:
  RawlogWriter(const std::string& path, const RawlogWriterOptions& opt = {});
  ~RawlogWriter();  ///< without close(): removes the temporary
  RawlogWriter(const RawlogWriter&) = delete;
  RawlogWriter& operator=(const RawlogWriter&) = delete;

  void write(const RgbdFrame& frame);
  /// Any other MRPT observation (e.g. CObservationImage with rendered label maps).
  void writeObject(const mrpt::serialization::CSerializable& obj);
  void close();
  std::size_t framesWritten() const;
  /// The temporary being written until close() ("<path>.part" unless that name was taken).
  const std::string& temporaryPath() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace rasm::io
