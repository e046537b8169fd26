#include "rasm/io/RawlogWriter.h"

#include <mrpt/io/CFileGZOutputStream.h>
#include <mrpt/obs/CObservation3DRangeScan.h>
#include <mrpt/obs/CObservationComment.h>
#include <mrpt/obs/CObservationOdometry.h>
#include <mrpt/serialization/CArchive.h>

#include <cstdio>
#include <filesystem>

#include "MrptErrors.h"
#include "rasm/core/AtomicFile.h"
#include "rasm/core/Error.h"
#include "rasm/io/RawlogFrameSource.h"
#include "rasm/io/RgbdObservation.h"

namespace fs = std::filesystem;

namespace rasm::io {

struct RawlogWriter::Impl {
  std::string path, part;
  std::unique_ptr<AtomicFile> temp;  ///< part = temp->path(), renamed over `path` by close()
  RawlogWriterOptions opt;
  mrpt::io::CFileGZOutputStream file;
  std::unique_ptr<mrpt::serialization::CArchiveStreamBase<mrpt::io::CFileGZOutputStream>> ar;
  std::size_t frames = 0;
  bool open = false;
  bool gt_state = false;  // what the last marker comment said
  fs::path images_dir;
  bool created_images_dir = false;

  void put(const mrpt::serialization::CSerializable& obj) {
    if (!open) throwInputError("rawlog " + path, "write after close()");
    try {
      *ar << obj;
    } catch (const std::exception& e) {
      throwInputError("rawlog " + part, "write failed: " + detail::shortMrptMessage(e.what()));
    }
  }
  void comment(const std::string& text, double t) {
    mrpt::obs::CObservationComment c;
    c.text = text;
    c.sensorLabel = "rasm";
    c.timestamp = mrpt::Clock::fromDouble(t);
    put(c);
  }
};

RawlogWriter::RawlogWriter(const std::string& path, const RawlogWriterOptions& opt)
    : impl_(std::make_unique<Impl>()) {
  Impl& m = *impl_;
  m.path = path;
  m.opt = opt;
  const fs::path parent = fs::path(path).parent_path();
  if (!parent.empty() && !fs::is_directory(parent))
    throwInputError("rawlog " + path, "output folder " + parent.string() + " does not exist");
  try {
    m.temp = std::make_unique<AtomicFile>(path);
  } catch (const std::runtime_error& e) {
    throwInputError("rawlog " + path, e.what());
  }
  m.part = m.temp->path();
  std::string err;
  if (!m.file.open(m.part, std::clamp(opt.compression_level, 0, 9), err))
    throwInputError("rawlog " + path, "cannot open " + m.part + " for writing: " + err);
  m.ar = std::make_unique<mrpt::serialization::CArchiveStreamBase<mrpt::io::CFileGZOutputStream>>(
      m.file);
  m.open = true;
  // Images go where MRPT looks for them (imagesDirectoryOf: "<dir>/<stem>_Images").
  const fs::path p(path);
  m.images_dir = p.parent_path() / (p.stem().string() + "_Images");
}

RawlogWriter::~RawlogWriter() {
  Impl& m = *impl_;
  if (!m.open) return;
  m.ar.reset();
  m.file.close();
  m.temp.reset();  // removes the temporary
  std::error_code ec;
  if (m.created_images_dir) fs::remove_all(m.images_dir, ec);
}

void RawlogWriter::write(const RgbdFrame& frame) {
  Impl& m = *impl_;
  if (!m.open) throwInputError("rawlog " + m.path, "write after close()");
  frame.validate("rawlog " + m.path + ", frame " + std::to_string(m.frames) + " to write");

  const bool gt = m.opt.sensor_pose_from_ground_truth && frame.gt_T_world_cam.has_value();
  if (gt != m.gt_state) {
    m.comment(gt ? kRawlogGroundTruthMarker : kRawlogNoGroundTruthMarker, frame.timestamp_s);
    m.gt_state = gt;
  }
  if (frame.odometry_xyyaw) {
    mrpt::obs::CObservationOdometry odo;
    odo.sensorLabel = "ODOMETRY";
    odo.timestamp = mrpt::Clock::fromDouble(frame.timestamp_s);
    const Eigen::Vector3d& o = *frame.odometry_xyyaw;
    odo.odometry = mrpt::poses::CPose2D(o.x(), o.y(), o.z());
    m.put(odo);
  }

  mrpt::obs::CObservation3DRangeScan obs;
  FrameToObservationOptions conv;
  conv.sensor_label = m.opt.sensor_label;
  conv.range_units_m = m.opt.range_units_m;
  conv.sensor_pose_from_ground_truth = m.opt.sensor_pose_from_ground_truth;
  observationFromFrame(frame, obs, conv);

  if (m.opt.external_images && obs.hasIntensityImage) {
    if (!fs::is_directory(m.images_dir)) {
      std::error_code ec;
      fs::create_directories(m.images_dir, ec);
      if (ec)
        throwInputError("rawlog images folder " + m.images_dir.string(),
                        "cannot create: " + ec.message());
      m.created_images_dir = true;
    }
    char name[128];
    std::snprintf(name, sizeof(name), "%s_%06zu.png", m.opt.sensor_label.c_str(), m.frames);
    const std::string file = (m.images_dir / name).string();
    if (!obs.intensityImage.saveToFile(file))
      throwInputError("rawlog image " + file, "cannot write");
    obs.intensityImage.setExternalStorage(name);  // relative to the images folder
  }
  m.put(obs);
  ++m.frames;
}

void RawlogWriter::writeObject(const mrpt::serialization::CSerializable& obj) {
  impl_->put(obj);
}

void RawlogWriter::close() {
  Impl& m = *impl_;
  if (!m.open) return;
  m.ar.reset();
  m.file.close();
  m.open = false;
  try {
    m.temp->commit();
  } catch (const std::runtime_error& e) {
    throwInputError("rawlog " + m.path, e.what());
  }
}

const std::string& RawlogWriter::temporaryPath() const {
  return impl_->part;
}

std::size_t RawlogWriter::framesWritten() const {
  return impl_->frames;
}

}  // namespace rasm::io
