#include "ObservationToFrame.h"

#include <mrpt/obs/CObservation3DRangeScan.h>
#include <mrpt/poses/CPose3D.h>

#include <cmath>
#include <sstream>

#include "rasm/core/Error.h"
#include "rasm/core/SE3.h"

namespace rasm::maps::detail {

RgbdFrame frameFromRangeScan(const mrpt::obs::CObservation3DRangeScan& obs, const std::string& source) {
  obs.load();  // external (lazy-load) images
  if (!obs.hasRangeImage || obs.rangeImage.rows() == 0)
    throwInputError(source, "CObservation3DRangeScan without a range image");
  RgbdFrame f;
  const int w = int(obs.rangeImage.cols()), h = int(obs.rangeImage.rows());
  f.intrinsics = CameraIntrinsics::fromTCamera(obs.cameraParams);
  if (f.intrinsics.width == 0 && f.intrinsics.height == 0) {
    f.intrinsics.width = w;
    f.intrinsics.height = h;
  }
  if (!f.intrinsics.valid() || f.intrinsics.width != w || f.intrinsics.height != h) {
    std::ostringstream s;
    s << "depth camera parameters " << f.intrinsics.toString() << " do not fit the " << w << "x" << h
      << " range image";
    throwInputError(source, s.str());
  }
  f.timestamp_s = mrpt::Clock::toDouble(obs.timestamp);

  const PinholeF K = f.intrinsics.plain();
  const float units = obs.rangeUnits;
  f.depth_m.resize(w, h);
  for (int y = 0; y < h; ++y) {
    float* d = f.depth_m.row(y);
    for (int x = 0; x < w; ++x) {
      float r = float(obs.rangeImage(y, x)) * units;
      if (!obs.range_is_depth && r > 0.0f) {
        const float rx = (float(x) - K.cx) / K.fx, ry = (float(y) - K.cy) / K.fy;
        r /= std::sqrt(rx * rx + ry * ry + 1.0f);  // Euclidean range -> z
      }
      d[x] = r;
    }
  }

  if (obs.hasIntensityImage && obs.intensityImage.getWidth() > 0) {
    const mrpt::img::CImage& im = obs.intensityImage;
    const int cw = int(im.getWidth()), ch = int(im.getHeight());
    const bool colour = im.isColor();
    Image<Bgr8> c(cw, ch);
    for (int y = 0; y < ch; ++y) {
      const std::uint8_t* p = im.ptrLine<std::uint8_t>(y);
      for (int x = 0; x < cw; ++x)
        c(x, y) = colour ? Bgr8{p[3 * x], p[3 * x + 1], p[3 * x + 2]} : Bgr8{p[x], p[x], p[x]};
    }
    if (obs.doDepthAndIntensityCamerasCoincide() && cw == w && ch == h) {
      f.colour = std::move(c);
    } else {
      CameraIntrinsics Kc = CameraIntrinsics::fromTCamera(obs.cameraParamsIntensity);
      if (!Kc.valid()) throwInputError(source, "intensity camera parameters are invalid");
      // relativePoseIntensityWRTDepth: colour optical frame in the MRPT depth-sensor frame.
      const Eigen::Isometry3d T_depthOpt_colourOpt =
          T_mrptSensor_optical().inverse() * fromCPose3D(obs.relativePoseIntensityWRTDepth);
      registerColourToDepth(f.depth_m, f.intrinsics, c, Kc, T_depthOpt_colourOpt.inverse(), f.colour);
    }
  }
  f.validate(source);
  return f;
}

}  // namespace rasm::maps::detail
