#pragma once
// Frames from an MRPT rawlog (either format: observations-only, or action / sensory-frame
// pairs), streamed one object at a time.
//
// Per mrpt::obs::CObservation3DRangeScan (label-filtered):
//  - depth: rangeImage * rangeUnits -> metres. Ranges along the ray (range_is_depth == false) are
//    converted to depth z = r / |K^-1 (u, v, 1)|.
//  - colour: intensityImage (grey images are replicated to B = G = R). When the depth and colour
//    cameras do not coincide (doDepthAndIntensityCamerasCoincide() false, or a different colour
//    resolution / intrinsics), colour is resampled into the depth camera with
//    registerColourToDepth using cameraParamsIntensity and relativePoseIntensityWRTDepth
//    (= T_depthSensor_colourOptical: depthSensor is MRPT's +X-forward frame, the colour camera
//    its optical frame). Pixels without depth take the colour along their ray at the frame's
//    median depth (no black holes for detectors). Lens distortion (TCamera::dist) is ignored:
//    rasm uses a pinhole model.
//  - intrinsics: cameraParams (the depth camera).
//  - ground truth: rasm stores T_world_sensor in `sensorPose` (see RawlogWriter). gt_T_world_cam
//    = opticalFromMrptSensorPose(sensorPose) where rasm's marker comments say so (RawlogWriter
//    writes them), or, in rawlogs without them, when sensorPose is not the identity (MRPT's
//    default, i.e. "no pose"). GroundTruthPolicy overrides this.
//  - odometry: the latest CObservationOdometry (absolute) before the frame, or the composition of
//    the CActionRobotMovement2D odometry increments of the action collections read so far
//    (actions / sensory-frames format).
//  - timestamp: mrpt::Clock::toDouble(obs->timestamp) (UNIX seconds); an observation with
//    INVALID_TIMESTAMP gets index / 30 s.
// Externally stored images (CImage external storage) are loaded from imagesDirectoryOf(path)
// ("<rawlog stem>_Images/", MRPT's rule).
//
// End of file vs. corruption: CRawlog::getActionObservationPairOrObservation() returns false for
// both (it prints corruption to std::cerr), so this reader implements the same two-format logic
// over `archive >> obj` itself and tells mrpt::serialization::CExceptionEOF (clean end between
// objects) from any other exception (truncated or corrupt object) -> InputError naming the file,
// the frame index and the rawlog entry reached.

#include <memory>
#include <string>

#include "rasm/io/FrameSource.h"

namespace rasm::io {

struct RawlogSourceOptions {
  /// Only CObservation3DRangeScan with this sensor label (empty: all of them).
  std::string sensor_label;
  enum class GroundTruthPolicy {
    Auto,    ///< rasm markers when present; else only non-identity sensor poses
    Always,  ///< sensorPose is ground truth (even the identity)
    Never    ///< no ground truth from sensorPose
  };
  GroundTruthPolicy ground_truth = GroundTruthPolicy::Auto;
};

/// Texts of the CObservationComments RawlogWriter puts before a run of frames whose sensorPose
/// holds (or does not hold) the ground-truth T_world_sensor; written only where that changes.
extern const char* const kRawlogGroundTruthMarker;
extern const char* const kRawlogNoGroundTruthMarker;

/// Folder of a rawlog's externally stored images: "<dir>/<stem>_Images" (or _images, _IMAGES)
/// when it exists, else "<dir>/Images" (CRawlog::detectImagesDirectory's rule, which MRPT 2.5.8
/// implements with a missing path separator).
std::string imagesDirectoryOf(const std::string& rawlog_path);

/// A gzip file read to its end without keeping the data: "" when every member ends with its CRC
/// and length checked, else what is wrong ("truncated at byte N: ...", "CRC mismatch: ...,
/// found at byte N", damaged deflate data). RawlogFrameSource runs it on a gzip rawlog before
/// its first frame (gzip checks the CRC only at the end of the stream: a bit flip early in the
/// file decompresses into altered frames). Bytes after a member that do not start another gzip
/// member are ignored, as zlib's gzread does.
std::string gzipStreamProblem(const std::string& path);

class RawlogFrameSource : public FrameSource {
 public:
  /// Opens the file (InputError naming it when missing or unreadable, or a gzip rawlog whose
  /// stream is corrupt or truncated: gzipStreamProblem, checked before any frame is read).
  explicit RawlogFrameSource(const std::string& path, const RawlogSourceOptions& opt = {});
  ~RawlogFrameSource() override;

  std::optional<RgbdFrame> next() override;
  std::string describe() const override;

  /// Rawlog entries (top-level objects) read so far.
  std::size_t entriesRead() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace rasm::io
