#include "rasm/pipeline/OutputFiles.h"

#include <mrpt/io/CStream.h>
#include <mrpt/serialization/CArchive.h>
#include <zlib.h>
#include <algorithm>
#include <cerrno>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <opencv2/imgcodecs.hpp>

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

std::string pngBytes(const std::string& path, const cv::Mat& image) {
  std::vector<unsigned char> png;
  if (!cv::imencode(".png", image, png))
    throw OutputError("output file '" + path + "': PNG encoding failed");
  return std::string(png.begin(), png.end());
}
}  // namespace

void writeAtomically(const std::string& path,
                     const std::function<void(const std::string& part)>& write) {
  const std::string part = path + ".part";
  // The writer's own temporary when it stages one too (io::writeTumTrajectory: "<part>.part").
  const ScopedTemporary registered(path), registered_inner(part);
  std::string error;
  errno = 0;
  try {
    write(part);
    std::error_code ec;
    fs::rename(part, path, ec);
    if (!ec) return;
    error = "cannot rename " + part + ": " + ec.message();
  } catch (const std::exception& e) {
    error = e.what();
  }
  const int err = errno;
  std::error_code ec;
  fs::remove(part, ec);
  fs::remove(part + ".part", ec);
  throw OutputError("output file '" + path + "' not written (" + systemReason(path, err) +
                    "): " + error);
}

void writeFileAtomically(const std::string& path, const std::string& text) {
  writeAtomically(path, [&](const std::string& part) { writeBytes(part, text); });
}

void writeImageAtomically(const std::string& path, const cv::Mat& image) {
  writeFileAtomically(path, pngBytes(path, image));
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
const std::vector<std::string>& OutputFolder::knownNames() {
  // Every file MappingRun, the Mapper's stages and the exploration loop write (README "Outputs
  // of rasm run"); OutputFolder::write refuses others.
  static const std::vector<std::string> names = {
      "config.ini",           "report.json",          "frames.csv",
      "trajectory.txt",       "groundtruth.txt",      "map.ply",
      "map.3Dscene",          "map.surfelmap",        "preview.png",
      "preview_segments.png", "preview_classes.png",  "segments.json",
      "map_segments.ply",     "map_segments.3Dscene", "classes.json",
      "objects.json",         "map_classes.ply",      "map_classes.3Dscene",
      "exploration.json",     "exploration.png",      "annotated.rawlog",
      "plot_trajectory.png",  "plot_timing.png"};
  return names;
}

void OutputFolder::write(const std::string& name,
                         const std::function<void(const std::string& part)>& write) {
  const auto& known = knownNames();
  if (std::find(known.begin(), known.end(), name) == known.end())
    throw std::logic_error("OutputFolder: '" + name + "' is not in OutputFolder::knownNames()");
  writeAtomically(path(name), write);
  recordWritten(name);
}

void OutputFolder::writeText(const std::string& name, const std::string& text) {
  write(name, [&](const std::string& part) { writeBytes(part, text); });
}

void OutputFolder::writeImage(const std::string& name, const cv::Mat& image) {
  writeText(name, pngBytes(path(name), image));
}

void OutputFolder::recordWritten(const std::string& name) {
  if (std::find(m_written.begin(), m_written.end(), name) == m_written.end())
    m_written.push_back(name);
}

std::vector<std::string> OutputFolder::clearPreviousRun() const {
  std::vector<std::string> removed;
  std::error_code ec;
  for (const std::string& name : knownNames())
    if (fs::remove(path(name), ec)) removed.push_back(name);
  // The annotated rawlog's external images, should an earlier version have written them.
  if (fs::remove_all(path("annotated_Images"), ec) > 0) removed.push_back("annotated_Images");
  std::vector<fs::path> parts;
  for (const auto& e : fs::directory_iterator(m_dir, ec))
    if (e.path().extension() == ".part") parts.push_back(e.path());
  for (const fs::path& p : parts)
    if (fs::remove(p, ec)) removed.push_back(p.filename().string());
  return removed;
}

}  // namespace rasm::pipeline
