#include "rasm/pipeline/OutputFiles.h"

#include <mrpt/io/CStream.h>
#include <mrpt/serialization/CArchive.h>
#include <sys/stat.h>
#include <unistd.h>
#include <zlib.h>
#include <algorithm>
#include <cerrno>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <nlohmann/json.hpp>
#include <opencv2/imgcodecs.hpp>
#include <optional>

#include "rasm/core/AtomicFile.h"
#include "rasm/core/Error.h"
#include "rasm/pipeline/Interrupts.h"

namespace fs = std::filesystem;

namespace rasm::pipeline {

namespace {
/// What the system says about the folder of `path` when a write failed: the errno of the failure
/// when the writer left one, and the free space.
std::string systemReason(const std::string& path, int err) {
  std::string why;
  if (err != 0) why = std::strerror(err);
  std::error_code ec;
  const fs::space_info sp = fs::space(fs::path(path).parent_path(), ec);
  if (!ec) {
    char buf[96];
    std::snprintf(buf, sizeof buf, "%s%.1f MB free on its disk", why.empty() ? "" : "; ",
                  double(sp.available) / 1e6);
    why += buf;
  }
  return why;
}

/// `text` into a new file `path`, checked through fclose (a full disk shows at the last flush).
void writeBytes(const std::string& path, const std::string& text) {
  std::FILE* f = std::fopen(path.c_str(), "wb");
  if (!f) throw std::runtime_error("cannot create " + path);
  const bool written = std::fwrite(text.data(), 1, text.size(), f) == text.size();
  const int err = errno;
  const bool closed = std::fclose(f) == 0;
  if (!written) errno = err;
  if (!written || !closed)
    throw std::runtime_error(written ? "write failed at close" : "write failed");
}

/// A write-only gzip file that reports every failure, the one at gzclose included.
class GzOutput : public mrpt::io::CStream {
 public:
  explicit GzOutput(const std::string& path) : m_f(gzopen(path.c_str(), "wb1")) {
    if (!m_f) throw std::runtime_error("cannot create " + path);
  }
  ~GzOutput() override {
    if (m_f) gzclose(m_f);
  }
  size_t Read(void*, size_t) override { throw std::logic_error("GzOutput: write only"); }
  size_t Write(const void* buf, size_t n) override {
    const auto* p = static_cast<const char*>(buf);
    for (size_t done = 0; done < n;) {  // gzwrite takes at most INT_MAX bytes a call
      const unsigned chunk = unsigned(std::min<size_t>(n - done, size_t(1) << 30));
      if (gzwrite(m_f, p + done, chunk) != int(chunk)) {
        m_failed = true;
        throw std::runtime_error("write failed");
      }
      done += chunk;
    }
    m_pos += n;
    return n;
  }
  uint64_t Seek(int64_t, TSeekOrigin) override { throw std::logic_error("GzOutput: no seek"); }
  uint64_t getTotalBytesCount() const override { return m_pos; }
  uint64_t getPosition() const override { return m_pos; }
  bool failed() const { return m_failed; }
  void close() {
    const int r = gzclose(m_f);
    m_f = nullptr;
    if (r != Z_OK) throw std::runtime_error("write failed at close");
  }

 private:
  gzFile m_f;
  uint64_t m_pos = 0;
  bool m_failed = false;
};

/// `image` encoded in the format of `extension` (".png", ".jpg", ...: OpenCV's encoders).
std::string imageBytes(const std::string& path, const cv::Mat& image,
                       const std::string& extension = ".png") {
  std::vector<unsigned char> bytes;
  if (!cv::imencode(extension, image, bytes))
    throw OutputError("output file '" + path + "': " + extension + " encoding failed");
  return std::string(bytes.begin(), bytes.end());
}
}  // namespace

void writeAtomically(const std::string& path,
                     const std::function<void(const std::string& part)>& write) {
  std::string error;
  errno = 0;
  try {
    // The temporary is registered with the abort handler before AtomicFile creates it when its
    // usual name <path>.part is free: registered after, a writer thread preempted between the
    // creation and the registration left it behind when the second signal came then (seen
    // under load). A <path>.part already there is somebody else's (AtomicFile then takes a
    // random name, registered once made): the handler must never remove it.
    const std::string part = path + ".part";
    std::optional<ScopedTemporary> registered;
    struct stat st {};
    if (::lstat(part.c_str(), &st) != 0 && errno == ENOENT) registered.emplace(part);
    AtomicFile file(path);  // removes its temporary unless committed
    if (file.path() != part) {
      registered.reset();
      registered.emplace(file.path());
    }
    errno = 0;
    write(file.path());
    file.commit();
    return;
  } catch (const std::exception& e) {
    error = e.what();
  }
  const int err = errno;
  throw OutputError("output file '" + path + "' not written (" + systemReason(path, err) +
                    "): " + error);
}

void writeFileAtomically(const std::string& path, const std::string& text) {
  writeAtomically(path, [&](const std::string& part) { writeBytes(part, text); });
}

void writeImageAtomically(const std::string& path, const cv::Mat& image) {
  const std::string extension = std::filesystem::path(path).extension().string();
  writeFileAtomically(path, imageBytes(path, image, extension.empty() ? ".png" : extension));
}

void writeGzArchive(const std::string& path, const mrpt::serialization::CSerializable& obj) {
  GzOutput f(path);
  auto a = mrpt::serialization::archiveFrom(f);
  try {
    a << obj;
  } catch (const std::exception&) {
    // MRPT wraps the stream's exception in pages of backtrace: say what failed instead.
    if (f.failed()) throw std::runtime_error("write failed");
    throw;
  }
  f.close();
}

std::string validUtf8(const std::string& s) {
  std::string out;
  out.reserve(s.size());
  std::size_t i = 0;
  while (i < s.size()) {
    const auto c = static_cast<unsigned char>(s[i]);
    // Length of the sequence a valid lead byte starts, and the range of its second byte
    // (overlong forms, surrogates and code points above U+10FFFF are invalid).
    std::size_t n = 0;
    unsigned char lo = 0x80, hi = 0xBF;
    if (c < 0x80)
      n = 1;
    else if (c >= 0xC2 && c <= 0xDF)
      n = 2;
    else if (c >= 0xE0 && c <= 0xEF) {
      n = 3;
      if (c == 0xE0) lo = 0xA0;
      if (c == 0xED) hi = 0x9F;
    } else if (c >= 0xF0 && c <= 0xF4) {
      n = 4;
      if (c == 0xF0) lo = 0x90;
      if (c == 0xF4) hi = 0x8F;
    }
    bool ok = n > 0 && i + n <= s.size();
    for (std::size_t k = 1; ok && k < n; ++k) {
      const auto b = static_cast<unsigned char>(s[i + k]);
      ok = k == 1 ? (b >= lo && b <= hi) : (b >= 0x80 && b <= 0xBF);
    }
    if (ok) {
      out.append(s, i, n);
      i += n;
    } else {
      out += "\xEF\xBF\xBD";  // U+FFFD, for the one byte that does not start a valid sequence
      ++i;
    }
  }
  return out;
}

// ---------------------------------------------------------------------------------------------
OutputFolder::OutputFolder(std::string dir) : m_dir(std::move(dir)) {}
OutputFolder::~OutputFolder() = default;
OutputFolder::OutputFolder(OutputFolder&&) noexcept = default;
OutputFolder& OutputFolder::operator=(OutputFolder&&) noexcept = default;

OutputFolder OutputFolder::claim(const std::string& dir, OverwritePolicy policy,
                                 std::vector<std::string>& removed) {
  const std::string what = "[output] dir '" + dir + "'";
  std::error_code ec;
  // The run's folder is created, never a chain of folders above it (a mistyped --out).
  if (!fs::exists(fs::symlink_status(dir, ec))) {
    requireParentFolder(dir, what);
    fs::create_directory(dir, ec);
    if (ec) throwInputError(what, "cannot be created: " + ec.message());
  }
  if (!fs::is_directory(dir)) throwInputError(what, "is not a folder");
  refuseUnlessAllowed(dir, inspectRunFolder(dir), policy);  // before the lock file is created
  OutputFolder out(dir);
  out.m_lock = std::make_unique<RunFolderLock>(dir);
  // Under the lock, as the earlier run left it.
  const RunFolderContents contents = inspectRunFolder(dir);
  refuseUnlessAllowed(dir, contents, policy);
  removed.clear();
  for (const std::string& name : contents.earlier_run) {
    // Files (a link itself, never its target); a folder only the one rasm wrote images into.
    const bool removed_one = name == "annotated_Images" ? fs::remove_all(out.path(name), ec) > 0
                                                        : fs::remove(out.path(name), ec);
    if (removed_one) removed.push_back(name);
  }
  out.writeMarker();
  return out;
}

void OutputFolder::writeMarker() const {
  // A record, not an output: when it cannot be updated (a full disk) the run goes on, and the
  // files it does not list make the next run refuse the folder rather than remove them.
  nlohmann::json marker;
  marker["comment"] =
      "rasm run's folder: the files this run may have written. The next run into this folder "
      "removes these (and their *.part temporaries) and nothing else.";
  marker["pid"] = long(::getpid());
  marker["files"] = m_announced;
  try {
    writeFileAtomically(path(kRunMarkerName), marker.dump(1) + "\n");
  } catch (const OutputError&) {
  }
}

void OutputFolder::announce(const std::string& name) {
  if (std::find(m_announced.begin(), m_announced.end(), name) != m_announced.end()) return;
  m_announced.push_back(name);
  if (m_lock) writeMarker();
}

void OutputFolder::leaveOut(const std::vector<std::string>& names) {
  m_left_out.insert(m_left_out.end(), names.begin(), names.end());
}

const std::vector<std::string>& OutputFolder::knownNames() {
  // Every file MappingRun, the Mapper's stages and the exploration loop write (README "Outputs
  // of rasm run"); OutputFolder::write refuses others.
  static const std::vector<std::string> names = {"config.ini",
                                                 "report.json",
                                                 "frames.csv",
                                                 "trajectory.txt",
                                                 "groundtruth.txt",
                                                 "map.ply",
                                                 "map.3Dscene",
                                                 "map.surfelmap",
                                                 "preview.png",
                                                 "preview_segments.png",
                                                 "preview_classes.png",
                                                 "segments.json",
                                                 "map_segments.ply",
                                                 "map_segments.3Dscene",
                                                 "classes.json",
                                                 "objects.json",
                                                 "map_classes.ply",
                                                 "map_classes.3Dscene",
                                                 "exploration.json",
                                                 "exploration.png",
                                                 "annotated.rawlog",
                                                 "plot_trajectory.png",
                                                 "plot_timing.png",
                                                 "floorplan.png",
                                                 "floorplan.svg",
                                                 "classes_legend.png",
                                                 "plot_tracking.png",
                                                 "run.log",
                                                 "mesh.ply",
                                                 "mesh_classes.ply",
                                                 "plot_objects.png"};
  return names;
}

void OutputFolder::write(const std::string& name,
                         const std::function<void(const std::string& part)>& write) {
  const auto& known = knownNames();
  if (std::find(known.begin(), known.end(), name) == known.end())
    throw std::logic_error("OutputFolder: '" + name + "' is not in OutputFolder::knownNames()");
  if (std::find(m_left_out.begin(), m_left_out.end(), name) != m_left_out.end()) return;
  announce(name);
  writeAtomically(path(name), write);
  recordWritten(name);
}

void OutputFolder::writeText(const std::string& name, const std::string& text) {
  write(name, [&](const std::string& part) { writeBytes(part, text); });
}

void OutputFolder::writeImage(const std::string& name, const cv::Mat& image) {
  writeText(name, imageBytes(path(name), image));
}

void OutputFolder::recordWritten(const std::string& name) {
  if (std::find(m_written.begin(), m_written.end(), name) == m_written.end())
    m_written.push_back(name);
}

}  // namespace rasm::pipeline
