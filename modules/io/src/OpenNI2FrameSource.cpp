#include "rasm/io/OpenNI2FrameSource.h"

#include <mrpt/config/CConfigFileBase.h>
#include <mrpt/config/CConfigFileMemory.h>
#include <mrpt/core/bits_math.h>
#include <mrpt/hwdrivers/COpenNI2Sensor.h>
#include <mrpt/obs/CObservation3DRangeScan.h>

#include <fcntl.h>
#include <unistd.h>

#include <chrono>
#include <thread>

#include "rasm/core/Error.h"
#include "rasm/core/Params.h"
#include "rasm/io/RgbdObservation.h"

namespace rasm::io {

void TOpenNI2Params::loadFromConfigFile(const mrpt::config::CConfigFileBase& c,
                                        const std::string& s) {
  MRPT_LOAD_CONFIG_VAR(device_index, int, c, s);
  MRPT_LOAD_CONFIG_VAR(device_serial, int, c, s);
  MRPT_LOAD_CONFIG_VAR(width, int, c, s);
  MRPT_LOAD_CONFIG_VAR(height, int, c, s);
  MRPT_LOAD_CONFIG_VAR(fps, double, c, s);
  MRPT_LOAD_CONFIG_VAR(registration, string, c, s);
  MRPT_LOAD_CONFIG_VAR(frame_timeout_s, double, c, s);
  requireInRange(device_index, 0, 63, s, "device_index");
  requireInRange(device_serial, 0, 2147483647.0, s, "device_serial");
  if (!((width == 640 && height == 480) || (width == 320 && height == 240)))
    throwInputError("[" + s + "] width, height",
                    std::to_string(width) + " x " + std::to_string(height) +
                        " is not a resolution OpenNI2 cameras stream (640 x 480 or 320 x 240)");
  if (fps != 30.0 && fps != 60.0)
    throwInputError("[" + s + "] fps", "expected 30 or 60, got " + std::to_string(fps));
  if (registration != "device" && registration != "software")
    throwInputError("[" + s + "] registration",
                    "'" + registration + "' is not one of device, software");
  requireInRange(frame_timeout_s, 0.1, 60, s, "frame_timeout_s");
}

void TOpenNI2Params::saveToConfigFile(mrpt::config::CConfigFileBase& c,
                                      const std::string& s) const {
  MRPT_SAVE_CONFIG_VAR(device_index, c, s);
  MRPT_SAVE_CONFIG_VAR(device_serial, c, s);
  MRPT_SAVE_CONFIG_VAR(width, c, s);
  MRPT_SAVE_CONFIG_VAR(height, c, s);
  MRPT_SAVE_CONFIG_VAR(fps, c, s);
  MRPT_SAVE_CONFIG_VAR(registration, c, s);
  MRPT_SAVE_CONFIG_VAR(frame_timeout_s, c, s);
}

namespace {
/// Silences stderr (fd 2) while alive: COpenNI2Generic::start() prints "[start] Initialized
/// OpenNI2." every time, which would land in the middle of rasm's progress line. Errors are
/// reported through exceptions and return values, not that text.
class QuietStderr {
 public:
  QuietStderr() : m_saved(::dup(2)) {
    const int null_fd = ::open("/dev/null", O_WRONLY | O_CLOEXEC);
    if (m_saved >= 0 && null_fd >= 0) ::dup2(null_fd, 2);
    if (null_fd >= 0) ::close(null_fd);
  }
  ~QuietStderr() {
    if (m_saved < 0) return;
    ::dup2(m_saved, 2);
    ::close(m_saved);
  }
  QuietStderr(const QuietStderr&) = delete;
  QuietStderr& operator=(const QuietStderr&) = delete;

 private:
  int m_saved;
};
}  // namespace

struct OpenNI2FrameSource::Impl {
  TOpenNI2Params params;
  std::optional<CameraIntrinsics> intrinsics_override;
  mrpt::hwdrivers::COpenNI2Sensor* sensor = nullptr;  ///< owned once open (see the header)
  bool open = false;
  std::size_t frames = 0;

  /// "[openni2] device_index = 0" or "[openni2] device_serial = 1234".
  std::string asked() const {
    return params.device_serial != 0
               ? "[openni2] device_serial = " + std::to_string(params.device_serial)
               : "[openni2] device_index = " + std::to_string(params.device_index);
  }
};

OpenNI2FrameSource::OpenNI2FrameSource(const TOpenNI2Params& params,
                                       const std::optional<CameraIntrinsics>& intrinsics_override)
    : impl_(std::make_unique<Impl>()) {
  impl_->params = params;
  impl_->intrinsics_override = intrinsics_override;
}

OpenNI2FrameSource::~OpenNI2FrameSource() {
  if (impl_->sensor && impl_->open) delete impl_->sensor;  // else: kept (its destructor throws)
}

int OpenNI2FrameSource::connectedDevices() {
  try {
    mrpt::hwdrivers::COpenNI2Generic probe(640, 480, 30.0f, false);
    bool started = false;
    {
      const QuietStderr quiet;
      started = probe.start();
    }
    if (!started) return 0;
    return std::max(0, probe.getConnectedDevices());
  } catch (const std::exception&) {
    return 0;
  }
}

std::string OpenNI2FrameSource::describe() const {
  const auto& p = impl_->params;
  return "openni2 " +
         (p.device_serial != 0 ? "serial " + std::to_string(p.device_serial)
                               : "device " + std::to_string(p.device_index)) +
         " (" + std::to_string(p.width) + "x" + std::to_string(p.height) + " @ " +
         std::to_string(int(p.fps)) + " Hz, registration " + p.registration + ")";
}

void OpenNI2FrameSource::open() {
  if (impl_->open) return;
  const TOpenNI2Params& p = impl_->params;
  // The devices first: without one, MRPT's sensor fails only at its first frame.
  mrpt::hwdrivers::COpenNI2Generic probe(p.width, p.height, float(p.fps), false);
  bool started = false;
  {
    const QuietStderr quiet;
    started = probe.start();
  }
  if (!started)
    throwInputError(impl_->asked(), "OpenNI2 did not initialise (its drivers missing?)");
  const int n = std::max(0, probe.getConnectedDevices());
  const std::string expected =
      " (expected an OpenNI2 RGB-D camera: Kinect v1 (OpenNI2-FreenectDriver), Asus Xtion, "
      "PrimeSense Carmine or Orbbec Astra on USB; check `lsusb` and the udev rules that let "
      "this user open it)";
  if (n == 0) throwInputError(impl_->asked(), "no OpenNI2 device is connected" + expected);
  int id = p.device_index;
  if (p.device_serial != 0 && !probe.getDeviceIDFromSerialNum(unsigned(p.device_serial), id))
    throwInputError(impl_->asked(), "no connected OpenNI2 device has this serial number (" +
                                        std::to_string(n) + " device(s) connected)");
  if (id >= n)
    throwInputError(impl_->asked(), "only " + std::to_string(n) +
                                        " OpenNI2 device(s) connected (indices 0-" +
                                        std::to_string(n - 1) + ")");
  mrpt::config::CConfigFileMemory cfg;
  cfg.write("OPENNI2", "sensorLabel", "OPENNI2");
  cfg.write("OPENNI2", "width", p.width);
  cfg.write("OPENNI2", "height", p.height);
  cfg.write("OPENNI2", "fps", p.fps);
  cfg.write("OPENNI2", "device_number", id);
  cfg.write("OPENNI2", "grab_3D_points", false);
  cfg.write("OPENNI2", "preview_window", false);
  auto* sensor = new mrpt::hwdrivers::COpenNI2Sensor();
  impl_->sensor = sensor;
  try {
    sensor->loadConfig(cfg, "OPENNI2");
    sensor->setSensorIDToOpen(unsigned(id));
    if (p.device_serial != 0) sensor->setSerialToOpen(unsigned(p.device_serial));
    sensor->initialize();
  } catch (const std::exception& e) {
    throwInputError(impl_->asked(), std::string("the device did not open: ") + e.what());
  }
  impl_->open = true;
}

std::optional<RgbdFrame> OpenNI2FrameSource::next() {
  open();
  const TOpenNI2Params& p = impl_->params;
  mrpt::obs::CObservation3DRangeScan obs;
  bool there = false, hw_error = false;
  const auto t0 = std::chrono::steady_clock::now();
  for (;;) {
    try {
      impl_->sensor->getNextObservation(obs, there, hw_error);
    } catch (const std::exception& e) {
      throwInputError(describe(), std::string("reading a frame failed: ") + e.what());
    }
    if (hw_error) throwInputError(describe(), "hardware error reported by the OpenNI2 driver");
    if (there) break;
    if (std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count() >
        p.frame_timeout_s)
      throwInputError(describe(), "no frame for " + std::to_string(p.frame_timeout_s) +
                                      " s ([openni2] frame_timeout_s; unplugged?)");
    std::this_thread::sleep_for(std::chrono::milliseconds(2));
  }
  if (p.registration == "device" && obs.hasIntensityImage &&
      obs.cameraParamsIntensity.ncols == obs.cameraParams.ncols &&
      obs.cameraParamsIntensity.nrows == obs.cameraParams.nrows) {
    // Depth registered to colour by the camera: one camera, the colour one.
    obs.cameraParams = obs.cameraParamsIntensity;
    obs.relativePoseIntensityWRTDepth =
        mrpt::poses::CPose3D(0, 0, 0, mrpt::DEG2RAD(-90.0), 0, mrpt::DEG2RAD(-90.0));
  }
  const std::string what = describe() + ", frame " + std::to_string(impl_->frames);
  RgbdFrame f = frameFromObservation(obs, what);
  f.timestamp_s = mrpt::Clock::toDouble(obs.timestamp);
  f.index = impl_->frames++;
  if (impl_->intrinsics_override) {
    if (impl_->intrinsics_override->width != f.width() ||
        impl_->intrinsics_override->height != f.height())
      throwInputError(what, "[camera] intrinsics are for " +
                                std::to_string(impl_->intrinsics_override->width) + "x" +
                                std::to_string(impl_->intrinsics_override->height) +
                                ", the camera streams " + std::to_string(f.width()) + "x" +
                                std::to_string(f.height()));
    f.intrinsics = *impl_->intrinsics_override;
  }
  f.validate(what);
  return f;
}

}  // namespace rasm::io
