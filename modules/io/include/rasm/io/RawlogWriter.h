#pragma once
// Writes RgbdFrames as an observations-only MRPT rawlog of mrpt::obs::CObservation3DRangeScan
// (+ CObservationOdometry when a frame has odometry), readable by `rawlog-edit --info`,
// RawLogViewer and RawlogFrameSource. Writes go to "<path>.part" and are renamed to <path> by
// close(), so an interrupted run never leaves a file that looks complete.

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
  /// storage); keeps rawlogs small and images viewable.
  bool external_images = false;
  /// Store the ground-truth pose (when present) as the observation's sensorPose; otherwise the
  /// identity is stored and poses live only in the trajectory file.
  bool sensor_pose_from_ground_truth = true;
  int compression_level = 1;  ///< gzip level 0-9
};

class RawlogWriter {
 public:
  RawlogWriter(const std::string& path, const RawlogWriterOptions& opt = {});
  ~RawlogWriter();  ///< without close(): removes the ".part" file
  RawlogWriter(const RawlogWriter&) = delete;
  RawlogWriter& operator=(const RawlogWriter&) = delete;

  void write(const RgbdFrame& frame);
  /// Any other MRPT observation (e.g. CObservationImage with rendered label maps).
  void writeObject(const mrpt::serialization::CSerializable& obj);
  void close();
  std::size_t framesWritten() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace rasm::io
