#pragma once
// Writing the files of a run's output folder: complete or not at all under the final name
// (docs/io.md "Runs that never lie").
//
// Every file goes through writeAtomically: the writer fills "<path>.part", which is renamed to
// <path> when the writer returns; when it throws (a full disk, a file size limit, a vanished
// folder) the temporary is removed and OutputError names <path> and the system's reason. While a
// temporary exists it is registered with the interrupt handler (Interrupts.h), which removes it
// when a second signal aborts the run.

#include <functional>
#include <stdexcept>
#include <string>
#include <vector>

namespace cv {
class Mat;
}
namespace mrpt::serialization {
class CSerializable;
}

namespace rasm::pipeline {

/// An output file could not be written; the message names the file.
class OutputError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

/// `write(part)` creates the file "<path>.part"; it is renamed to `path` when `write` returns.
/// When `write` throws or the rename fails, the temporary is removed and OutputError names `path`.
void writeAtomically(const std::string& path,
                     const std::function<void(const std::string& part)>& write);
/// writeAtomically with `text` as the file's bytes (checked through close).
void writeFileAtomically(const std::string& path, const std::string& text);
/// writeAtomically of `image` encoded as PNG.
void writeImageAtomically(const std::string& path, const cv::Mat& image);

/// Serializes `obj` into a new gzip file `path` as MRPT's CFileGZOutputStream + archive do (the
/// .3Dscene and .surfelmap formats), but checks every write and the last flush at gzclose, which
/// MRPT ignores (a full disk there would leave a truncated file). std::runtime_error on failure.
void writeGzArchive(const std::string& path, const mrpt::serialization::CSerializable& obj);

/// `text` with every byte sequence that is not valid UTF-8 replaced by U+FFFD (JSON needs it).
std::string validUtf8(const std::string& text);

/// The output folder of one run: writes its files atomically, remembers which it wrote, and
/// clears the files an earlier run left there, so that the folder holds one run's files.
class OutputFolder {
 public:
  explicit OutputFolder(std::string dir) : m_dir(std::move(dir)) {}
  const std::string& dir() const { return m_dir; }
  std::string path(const std::string& name) const { return m_dir + "/" + name; }

  /// writeAtomically(path(name), write) and records `name`. `name` must be one of knownNames()
  /// (std::logic_error otherwise: a new output must be added there, so that the next run into
  /// the folder removes it).
  void write(const std::string& name, const std::function<void(const std::string& part)>& write);
  void writeText(const std::string& name, const std::string& text);
  void writeImage(const std::string& name, const cv::Mat& image);
  /// Records a file written by other means (the annotated rawlog, renamed by its own writer).
  void recordWritten(const std::string& name);
  /// The files written so far, in order.
  const std::vector<std::string>& written() const { return m_written; }

  /// Removes every known output and every "*.part" temporary from the folder (files of an earlier
  /// run; other files are left alone). Returns the names removed.
  std::vector<std::string> clearPreviousRun() const;
  /// Every file name a run may write into its folder.
  static const std::vector<std::string>& knownNames();

 private:
  std::string m_dir;
  std::vector<std::string> m_written;
};

}  // namespace rasm::pipeline
