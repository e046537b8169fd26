#include "rasm/io/RawlogFrameSource.h"

#include <mrpt/io/CFileGZInputStream.h>
#include <mrpt/io/lazy_load_path.h>
#include <mrpt/obs/CActionCollection.h>
#include <mrpt/obs/CActionRobotMovement2D.h>
#include <mrpt/obs/CObservation3DRangeScan.h>
#include <mrpt/obs/CObservationComment.h>
#include <mrpt/obs/CObservationOdometry.h>
#include <mrpt/obs/CSensoryFrame.h>
#include <mrpt/serialization/CArchive.h>
#include <mrpt/system/datetime.h>

#include <fcntl.h>
#include <unistd.h>
#include <zlib.h>

#include <cerrno>
#include <cstring>
#include <deque>
#include <filesystem>
#include <fstream>
#include <set>
#include <sstream>
#include <vector>

#include "MrptErrors.h"
#include "rasm/core/Error.h"
#include "rasm/io/RgbdObservation.h"

namespace fs = std::filesystem;

namespace rasm::io {

const char* const kRawlogGroundTruthMarker =
    "rasm: sensorPose holds the ground-truth T_world_sensor";
const char* const kRawlogNoGroundTruthMarker = "rasm: sensorPose holds no ground truth";

struct RawlogFrameSource::Impl {
  std::string path;
  RawlogSourceOptions opt;
  mrpt::io::CFileGZInputStream file;
  std::unique_ptr<mrpt::serialization::CArchiveStreamBase<mrpt::io::CFileGZInputStream>> ar;
  std::string images_dir;
  std::deque<mrpt::obs::CObservation::Ptr> pending;
  std::size_t entries = 0, frames = 0;
  bool eof = false;
  enum class Marker { None, GroundTruth, NoGroundTruth } gt_marker = Marker::None;
  std::optional<Eigen::Vector3d> odometry;     // consumed by the next frame
  mrpt::poses::CPose2D odometry_from_actions;  // composition of CActionRobotMovement2D increments
  std::set<std::string> range_scan_labels;

  std::string frameContext() const {
    return "rawlog " + path + ", frame " + std::to_string(frames) + " (rawlog entry " +
           std::to_string(entries) + ")";
  }
  std::optional<RgbdFrame> handle(const mrpt::obs::CObservation::Ptr& o);
};

// CRawlog::detectImagesDirectory() of MRPT 2.5.8 drops the '/' between folder and file name
// ("/a/b/x.rawlog" -> "/a/bImages"), so its intended rule is implemented here: the first of
// "<dir>/<stem>_Images", "_images", "_IMAGES" that exists, else "<dir>/Images".
std::string imagesDirectoryOf(const std::string& rawlog_path) {
  const fs::path p(rawlog_path);
  for (const char* suffix : {"_Images", "_images", "_IMAGES"}) {
    const fs::path d = p.parent_path() / (p.stem().string() + suffix);
    if (fs::is_directory(d)) return d.string();
  }
  return (p.parent_path() / "Images").string();
}

namespace {
/// Why inflate stopped with Z_DATA_ERROR, in words (zlib's message kept).
std::string inflateProblem(const char* msg) {
  const std::string m = msg ? msg : "unknown error";
  if (m == "incorrect data check")
    return "CRC mismatch: it decompresses, but not into the data that was written";
  if (m == "incorrect length check") return "length mismatch in its gzip trailer";
  return "its compressed data is damaged (zlib: " + m + ")";
}
}  // namespace

std::string gzipStreamProblem(const std::string& path) {
  const int fd = ::open(path.c_str(), O_RDONLY | O_CLOEXEC);
  if (fd < 0) return std::string("cannot be read: ") + std::strerror(errno);
  z_stream zs{};
  if (inflateInit2(&zs, 15 + 16) != Z_OK) {  // gzip wrapper only
    ::close(fd);
    return "zlib could not be initialised";
  }
  std::vector<unsigned char> in(1 << 18), out(1 << 18);
  std::string problem;
  std::uint64_t offset = 0;  // file bytes read so far
  bool member_ended = false;
  for (;;) {
    if (zs.avail_in == 0) {
      const ssize_t n = ::read(fd, in.data(), in.size());
      if (n < 0) {
        problem = std::string("cannot be read: ") + std::strerror(errno);
        break;
      }
      if (n == 0) {
        if (!member_ended)
          problem = "truncated at byte " + std::to_string(offset) +
                    ": the file ends inside its gzip stream, before its checksum";
        break;
      }
      zs.next_in = in.data();
      zs.avail_in = uInt(n);
      offset += std::uint64_t(n);
    }
    if (member_ended) {  // another gzip member follows (as gzread reads it), or trailing bytes
      if (zs.next_in[0] != 0x1f || (zs.avail_in >= 2 && zs.next_in[1] != 0x8b)) break;
      inflateReset(&zs);
      member_ended = false;
    }
    zs.next_out = out.data();
    zs.avail_out = uInt(out.size());
    const int rc = inflate(&zs, Z_NO_FLUSH);
    if (rc == Z_STREAM_END) {
      member_ended = true;
    } else if (rc == Z_DATA_ERROR) {
      problem = inflateProblem(zs.msg) + ", found at byte " + std::to_string(offset - zs.avail_in);
      break;
    } else if (rc != Z_OK && rc != Z_BUF_ERROR) {
      problem = "zlib error " + std::to_string(rc);
      break;
    }
  }
  inflateEnd(&zs);
  ::close(fd);
  return problem;
}

RawlogFrameSource::RawlogFrameSource(const std::string& path, const RawlogSourceOptions& opt)
    : impl_(std::make_unique<Impl>()) {
  impl_->path = path;
  impl_->opt = opt;
  if (std::filesystem::exists(path) && !std::filesystem::is_regular_file(path))
    throwInputError(
        "rawlog " + path,
        std::filesystem::is_directory(path)
            ? "is a folder, expected a .rawlog file"
            : "is not a regular file (a device, pipe or socket), expected a .rawlog file");
  if (!std::filesystem::is_regular_file(path)) throwInputError("rawlog " + path, "file not found");
  std::string err;
  if (!impl_->file.open(path, err)) throwInputError("rawlog " + path, "cannot open: " + err);
  impl_->ar =
      std::make_unique<mrpt::serialization::CArchiveStreamBase<mrpt::io::CFileGZInputStream>>(
          impl_->file);
  impl_->images_dir = imagesDirectoryOf(path);
  std::ifstream magic(path, std::ios::binary);
  char b[2] = {0, 0};
  const bool gzip = magic.read(b, 2) && b[0] == '\x1f' && b[1] == '\x8b';
  // gzip checks its CRC only at the end of the stream: a bit flip early in the file would
  // decompress into altered frames, mapped before the error surfaced. The whole stream is
  // checked first.
  if (gzip)
    if (const std::string problem = gzipStreamProblem(path); !problem.empty())
      throwInputError("rawlog " + path,
                      "its gzip stream is corrupt (" + problem +
                          "); refused before its first frame: nothing was mapped");
}

RawlogFrameSource::~RawlogFrameSource() = default;

std::string RawlogFrameSource::describe() const {
  return "rawlog " + impl_->path;
}
std::size_t RawlogFrameSource::entriesRead() const {
  return impl_->entries;
}

static bool isIdentity(const mrpt::poses::CPose3D& p) {
  return p.translation().norm() < 1e-9 &&
         (p.getRotationMatrix().asEigen() - Eigen::Matrix3d::Identity()).cwiseAbs().maxCoeff() <
             1e-9;
}

std::optional<RgbdFrame> RawlogFrameSource::Impl::handle(const mrpt::obs::CObservation::Ptr& o) {
  using namespace mrpt::obs;
  if (const auto c = std::dynamic_pointer_cast<CObservationComment>(o)) {
    if (c->text.find(kRawlogGroundTruthMarker) != std::string::npos)
      gt_marker = Marker::GroundTruth;
    if (c->text.find(kRawlogNoGroundTruthMarker) != std::string::npos)
      gt_marker = Marker::NoGroundTruth;
    return std::nullopt;
  }
  if (const auto od = std::dynamic_pointer_cast<CObservationOdometry>(o)) {
    odometry = Eigen::Vector3d(od->odometry.x(), od->odometry.y(), od->odometry.phi());
    return std::nullopt;
  }
  const auto scan = std::dynamic_pointer_cast<CObservation3DRangeScan>(o);
  if (!scan) return std::nullopt;
  range_scan_labels.insert(detail::printable(scan->sensorLabel));
  if (!opt.sensor_label.empty() && scan->sensorLabel != opt.sensor_label) return std::nullopt;

  const std::string ctx = frameContext();
  // External images are relative to the rawlog's "<stem>_Images" folder; the base path is global
  // state in MRPT, so it is set right before each load.
  mrpt::io::setLazyLoadPathBase(images_dir);
  try {
    scan->load();
  } catch (const std::exception& e) {
    throwInputError(ctx, "cannot load externally stored data (images folder " + images_dir +
                             "): " + detail::shortMrptMessage(e.what()));
  }
  bool gt = false;
  switch (opt.ground_truth) {
    case RawlogSourceOptions::GroundTruthPolicy::Always:
      gt = true;
      break;
    case RawlogSourceOptions::GroundTruthPolicy::Never:
      gt = false;
      break;
    case RawlogSourceOptions::GroundTruthPolicy::Auto:
      gt = gt_marker == Marker::None ? !isIdentity(scan->sensorPose)
                                     : gt_marker == Marker::GroundTruth;
      break;
  }
  ObservationToFrameOptions conv;
  conv.sensor_pose_is_ground_truth = gt;
  RgbdFrame f = frameFromObservation(*scan, ctx, conv);
  scan->unload();
  f.index = frames;
  f.timestamp_s = scan->timestamp == INVALID_TIMESTAMP ? double(frames) / 30.0
                                                       : mrpt::Clock::toDouble(scan->timestamp);
  f.odometry_xyyaw = odometry;
  odometry.reset();
  f.validate(ctx);
  ++frames;
  return f;
}

std::optional<RgbdFrame> RawlogFrameSource::next() {
  using namespace mrpt::obs;
  Impl& m = *impl_;
  for (;;) {
    while (!m.pending.empty()) {
      const auto o = m.pending.front();
      m.pending.pop_front();
      if (auto f = m.handle(o)) return f;
    }
    if (m.eof) return std::nullopt;

    // The two rawlog formats of CRawlog::getActionObservationPairOrObservation(), one object at
    // a time, telling a clean end of file from a truncated / corrupt object (see header).
    mrpt::serialization::CSerializable::Ptr obj;
    try {
      *m.ar >> obj;
    } catch (const mrpt::serialization::CExceptionEOF&) {
      m.eof = true;
      if (m.frames == 0) {
        std::ostringstream s;
        s << "no CObservation3DRangeScan";
        if (!m.opt.sensor_label.empty()) s << " with sensor label '" << m.opt.sensor_label << "'";
        s << " in " << m.entries << " rawlog entries";
        if (!m.range_scan_labels.empty()) {
          s << " (3D range scan labels present:";
          for (const auto& l : m.range_scan_labels) s << " '" << l << "'";
          s << ")";
        }
        std::error_code ec;
        const auto bytes = fs::file_size(m.path, ec);
        if (m.entries == 0 && !ec && bytes > 0)
          s << ": its " << bytes
            << " bytes hold no readable entry (not a rawlog, or corrupt from its start: e.g. a "
               "gzip stream that does not decompress)";
        throwInputError("rawlog " + m.path, s.str());
      }
      return std::nullopt;
    } catch (const std::exception& e) {
      throwInputError(m.frameContext(),
                      "corrupt or truncated rawlog: " + detail::shortMrptMessage(e.what()));
    }
    ++m.entries;
    if (const auto o = std::dynamic_pointer_cast<CObservation>(obj)) {
      m.pending.push_back(o);
    } else if (const auto sf = std::dynamic_pointer_cast<CSensoryFrame>(obj)) {
      for (const auto& o : *sf) m.pending.push_back(o);
    } else if (const auto acts = std::dynamic_pointer_cast<CActionCollection>(obj)) {
      if (const auto mv = acts->getActionByClass<CActionRobotMovement2D>()) {
        if (mv->estimationMethod == CActionRobotMovement2D::emOdometry) {
          m.odometry_from_actions = m.odometry_from_actions + mv->rawOdometryIncrementReading;
          const auto& p = m.odometry_from_actions;
          m.odometry = Eigen::Vector3d(p.x(), p.y(), p.phi());
        }
      }
    }
    // Other objects (CRawlog comments, maps, ...) are not frames: skipped.
  }
}

}  // namespace rasm::io
