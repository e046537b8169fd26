#pragma once
// Live frames from an OpenNI2 RGB-D camera (Kinect v1 through OpenNI2-FreenectDriver, Asus
// Xtion / PrimeSense Carmine, Orbbec Astra) through MRPT's mrpt::hwdrivers::COpenNI2Sensor
// ([source] type = openni2, section [openni2]). docs/hardware.md.
//
//  - Opening is deferred to the first next(), so that `rasm config` validates a live
//    configuration without a camera and `rasm run` reports a missing one in report.json like any
//    failed source. The devices are listed first (COpenNI2Generic::getConnectedDevices); no
//    device, an index beyond the devices found or a serial number not among them throws
//    InputError naming the device asked for and what was found, within a second.
//  - Frames: CObservation3DRangeScan -> RgbdFrame by frameFromObservation (depth in metres, colour
//    B,G,R); registration = device: the camera registers depth to colour (MRPT asks OpenNI2 for
//    it) and both are taken to coincide, with the colour camera's intrinsics; registration =
//    software: depth stays in the depth camera and rasm resamples colour into it with the
//    calibration MRPT reports (cameraParams, cameraParamsIntensity,
//    relativePoseIntensityWRTDepth). [camera] intrinsics, when set, replace the frame's.
//  - Timestamps: MRPT's (this computer's clock at capture, UNIX seconds).
//  - A device that opens but sends no frame for frame_timeout_s, or a hardware error, throws
//    InputError naming the device.
// MRPT 2.5.8's COpenNI2Sensor throws from its destructor when its device never opened
// (MRPT-NOTES "OpenNI2"): such a sensor object is deliberately not destroyed (a one-off leak of
// a small object instead of std::terminate).

#include <mrpt/config/CLoadableOptions.h>

#include <memory>
#include <optional>
#include <string>

#include "rasm/io/FrameSource.h"

namespace rasm::io {

/// [openni2]: which device and how it streams.
struct TOpenNI2Params : mrpt::config::CLoadableOptions {
  int device_index = 0;   ///< 0 = the first device OpenNI2 lists (ignored when device_serial set)
  int device_serial = 0;  ///< the serial number of the device to open; 0 = use device_index
  int width = 640;        ///< depth and colour resolution: 640 x 480 or 320 x 240
  int height = 480;
  double fps = 30.0;                    ///< 30 (every OpenNI2 camera) or 60 (320 x 240 on some)
  std::string registration = "device";  ///< device | software (see above)
  double frame_timeout_s = 3.0;         ///< longest wait for a frame from an open device

  void loadFromConfigFile(const mrpt::config::CConfigFileBase& c, const std::string& s) override;
  void saveToConfigFile(mrpt::config::CConfigFileBase& c, const std::string& s) const override;
};

class OpenNI2FrameSource : public FrameSource {
 public:
  /// Does not open the device (next() does).
  explicit OpenNI2FrameSource(const TOpenNI2Params& params,
                              const std::optional<CameraIntrinsics>& intrinsics_override = {});
  ~OpenNI2FrameSource() override;

  /// Opens the device (when not yet open); InputError as described above.
  void open();
  std::optional<RgbdFrame> next() override;
  std::string describe() const override;

  /// Devices OpenNI2 lists now (0 without a camera or without OpenNI2 support in MRPT).
  static int connectedDevices();

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace rasm::io
