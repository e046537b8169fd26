#include "rasm/io/RgbdObservation.h"

#include <mrpt/obs/CObservation3DRangeScan.h>

#include <cmath>
#include <cstring>
#include <sstream>

#include "ColourRegistration.h"
#include "ImageCv.h"
#include "MrptErrors.h"
#include "rasm/core/Error.h"
#include "rasm/core/SE3.h"

namespace rasm::io {

namespace {

// Same intrinsics up to printing precision (rawlogs store them as doubles but tools round-trip
// them through text).
bool sameIntrinsics(const CameraIntrinsics& a, const CameraIntrinsics& b) {
  const double eps = 1e-6;
  return std::abs(a.fx - b.fx) < eps && std::abs(a.fy - b.fy) < eps &&
         std::abs(a.cx - b.cx) < eps && std::abs(a.cy - b.cy) < eps && a.width == b.width &&
         a.height == b.height;
}

/// A bool flag of a deserialized observation, checked: MRPT reads a bool as its byte, so a
/// corrupt rawlog can leave any value in it (found by fuzz_rawlog: 30), and loading a bool that
/// is neither 0 nor 1 is undefined behaviour. The byte is read as a byte.
bool flag(const bool& b, const char* name, const std::string& source) {
  unsigned char byte = 0;
  std::memcpy(&byte, &b, 1);
  if (byte > 1)
    throwInputError(source, std::string("corrupt CObservation3DRangeScan: its flag ") + name +
                                " holds the byte " + std::to_string(int(byte)) +
                                " (expected 0 or 1)");
  return byte == 1;
}

}  // namespace

RgbdFrame frameFromObservation(const mrpt::obs::CObservation3DRangeScan& obs,
                               const std::string& source, const ObservationToFrameOptions& opt) {
  const bool has_range = flag(obs.hasRangeImage, "hasRangeImage", source);
  const bool range_is_depth = flag(obs.range_is_depth, "range_is_depth", source);
  const bool has_intensity = flag(obs.hasIntensityImage, "hasIntensityImage", source);
  if (!has_range)
    throwInputError(source, "CObservation3DRangeScan '" + detail::printable(obs.sensorLabel) +
                                "' has no range image (hasRangeImage = false)");
  const int W = int(obs.rangeImage.cols()), H = int(obs.rangeImage.rows());
  if (W == 0 || H == 0) throwInputError(source, "empty range image");
  // Metres per count of the 16-bit range image: above 0.1 m one count spans more than the range
  // of any depth camera (1e30 turns every pixel into an invalid depth, silently).
  if (!(obs.rangeUnits > 0.0f && obs.rangeUnits <= 0.1f)) {
    std::ostringstream s;
    s << "rangeUnits is " << obs.rangeUnits
      << " m per count; expected in (0, 0.1] (0.001 for millimetres)";
    throwInputError(source, s.str());
  }

  RgbdFrame f;
  f.intrinsics = CameraIntrinsics::fromTCamera(obs.cameraParams);
  if (!f.intrinsics.valid())
    throwInputError(source, "depth camera intrinsics (cameraParams) are invalid: " +
                                f.intrinsics.toString() + " (" + f.intrinsics.problem() + ")");

  // Depth (II-A, D_t). rangeImage is row-major (r, c).
  f.depth_m.resize(W, H);
  const float units = obs.rangeUnits;
  const PinholeF K = f.intrinsics.plain();
  for (int y = 0; y < H; ++y) {
    float* row = f.depth_m.row(y);
    for (int x = 0; x < W; ++x) {
      float d = float(obs.rangeImage(y, x)) * units;
      if (!range_is_depth && d > 0.0f) {
        // Range along the ray -> z: |p| = z |K^-1 (u, v, 1)|.
        const float xn = (float(x) - K.cx) / K.fx, yn = (float(y) - K.cy) / K.fy;
        d /= std::sqrt(1.0f + xn * xn + yn * yn);
      }
      row[x] = d;
    }
  }

  // Colour, registered to depth.
  if (has_intensity) {
    cv::Mat m;
    try {
      m = obs.intensityImage.asCvMat<cv::Mat>(mrpt::img::SHALLOW_COPY);
    } catch (const std::exception& e) {
      const std::string file = obs.intensityImage.isExternallyStored()
                                   ? obs.intensityImage.getExternalStorageFileAbsolutePath()
                                   : std::string("(in memory)");
      throwInputError(source, "cannot load the intensity image " + detail::printable(file) + ": " +
                                  detail::shortMrptMessage(e.what()).substr(0, 200));
    }
    Image<Bgr8> colour;
    detail::colourFromMat(m, colour, source);
    CameraIntrinsics Kc = CameraIntrinsics::fromTCamera(obs.cameraParamsIntensity);
    Kc.width = colour.width();
    Kc.height = colour.height();
    const bool coincide = obs.doDepthAndIntensityCamerasCoincide();
    const bool same_size = colour.sameSize(f.depth_m);
    if (coincide && same_size && (!Kc.valid() || sameIntrinsics(Kc, f.intrinsics))) {
      f.colour = std::move(colour);
    } else {
      if (!Kc.valid())
        throwInputError(source, "colour camera intrinsics (cameraParamsIntensity) are invalid: " +
                                    Kc.toString() + " (" + Kc.problem() +
                                    "), needed to register colour to depth");
      // relativePoseIntensityWRTDepth = T_depthSensor_colourOptical (depthSensor: MRPT +X forward).
      const Eigen::Isometry3d T_depthSensor_colourOpt =
          fromCPose3D(obs.relativePoseIntensityWRTDepth);
      if (!T_depthSensor_colourOpt.matrix().allFinite())
        throwInputError(source,
                        "the colour camera's pose (relativePoseIntensityWRTDepth) is not finite: " +
                            obs.relativePoseIntensityWRTDepth.asString());
      const Eigen::Isometry3d T_depthOpt_colourOpt =
          T_mrptSensor_optical().inverse() * T_depthSensor_colourOpt;
      detail::registerColourToDepthFilled(f.depth_m, f.intrinsics, colour, Kc,
                                          T_depthOpt_colourOpt.inverse(), f.colour);
    }
  }

  if (opt.sensor_pose_is_ground_truth) {
    f.gt_T_world_cam = opticalFromMrptSensorPose(obs.sensorPose);
    if (!f.gt_T_world_cam->matrix().allFinite())
      throwInputError(
          source, "the ground-truth pose (sensorPose) is not finite: " + obs.sensorPose.asString());
  }
  return f;
}

void observationFromFrame(const RgbdFrame& frame, mrpt::obs::CObservation3DRangeScan& obs,
                          const FrameToObservationOptions& opt) {
  const int W = frame.width(), H = frame.height();
  obs.sensorLabel = opt.sensor_label;
  obs.timestamp = mrpt::Clock::fromDouble(frame.timestamp_s);
  obs.hasRangeImage = true;
  obs.range_is_depth = true;
  obs.rangeUnits = opt.range_units_m;
  obs.rangeImage_setSize(H, W);
  const double inv_units = 1.0 / double(opt.range_units_m);
  float max_depth = 0.0f;
  for (int y = 0; y < H; ++y) {
    const float* row = frame.depth_m.row(y);
    for (int x = 0; x < W; ++x) {
      const float d = row[x];
      const double q = std::isfinite(d) && d > 0.0f ? std::round(double(d) * inv_units) : 0.0;
      const bool ok = q > 0.0 && q <= 65535.0;
      obs.rangeImage(y, x) = ok ? std::uint16_t(q) : std::uint16_t(0);
      if (ok) max_depth = std::max(max_depth, d);
    }
  }
  obs.maxRange = std::max(10.0f, max_depth);

  obs.hasIntensityImage = !frame.colour.empty();
  if (obs.hasIntensityImage) {
    obs.intensityImage = mrpt::img::CImage(detail::cvView(frame.colour), mrpt::img::DEEP_COPY);
    obs.intensityImageChannel = mrpt::obs::CObservation3DRangeScan::CH_VISIBLE;
  }
  frame.intrinsics.toTCamera(obs.cameraParams);
  obs.cameraParams.ncols = uint32_t(W);
  obs.cameraParams.nrows = uint32_t(H);
  obs.cameraParamsIntensity = obs.cameraParams;
  obs.relativePoseIntensityWRTDepth = mrpt::poses::CPose3D(0, 0, 0, -M_PI / 2, 0, -M_PI / 2);
  obs.sensorPose = (opt.sensor_pose_from_ground_truth && frame.gt_T_world_cam)
                       ? mrptSensorPoseFromOptical(*frame.gt_T_world_cam)
                       : mrpt::poses::CPose3D();
}

}  // namespace rasm::io
