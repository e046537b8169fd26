#pragma once
// Writing the files of a run's output folder: complete or not at all under the final name
// (docs/io.md "Runs that never lie").
//
// Every file goes through writeAtomically: the writer fills a temporary rasm::AtomicFile created
// beside <path> ("<path>.part", never through a file or link already there), which is renamed to
// <path> when the writer returns; when it throws (a full disk, a file size limit, a vanished
// folder) the temporary is removed and OutputError names <path> and the system's reason. While a
// temporary exists it is registered with the interrupt handler (Interrupts.h), which removes it
// when a second signal aborts the run. Whose files a run folder holds: RunFolder.h.

#include <functional>
#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

#include "rasm/pipeline/RunFolder.h"

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

/// `write(part)` fills the temporary `part` (an empty file rasm created beside `path`); it is
/// renamed to `path` when `write` returns. When `write` throws or the rename fails, the temporary
/// is removed and OutputError names `path`.
void writeAtomically(const std::string& path,
                     const std::function<void(const std::string& part)>& write);
/// writeAtomically with `text` as the file's bytes (checked through close).
void writeFileAtomically(const std::string& path, const std::string& text);
/// writeAtomically of `image` encoded in the format its extension names (PNG without one).
void writeImageAtomically(const std::string& path, const cv::Mat& image);

/// Serializes `obj` into a new gzip file `path` as MRPT's CFileGZOutputStream + archive do (the
/// .3Dscene and .surfelmap formats), but checks every write and the last flush at gzclose, which
/// MRPT ignores (a full disk there would leave a truncated file). std::runtime_error on failure.
void writeGzArchive(const std::string& path, const mrpt::serialization::CSerializable& obj);

/// `text` with every byte sequence that is not valid UTF-8 replaced by U+FFFD (JSON needs it).
std::string validUtf8(const std::string& text);

/// The output folder of one run: writes its files atomically and remembers which it wrote. A
/// folder claimed for a run (claim) also holds the run's lock and marker (RunFolder.h).
class OutputFolder {
 public:
  /// Writes into `dir` as it is: no lock, no marker, nothing removed (tests of the writers).
  explicit OutputFolder(std::string dir);
  ~OutputFolder();
  OutputFolder(OutputFolder&&) noexcept;
  OutputFolder& operator=(OutputFolder&&) noexcept;

  /// Claims `dir` for one run: creates it when missing; refuses it as `policy` says
  /// (refuseUnlessAllowed: InputError, nothing changed); takes its lock (InputError "<dir> is in
  /// use by another rasm run (pid N)", nothing changed); removes the files the earlier run listed
  /// (their names go to `removed`) and writes the run's marker.
  static OutputFolder claim(const std::string& dir, OverwritePolicy policy,
                            std::vector<std::string>& removed);

  const std::string& dir() const { return m_dir; }
  std::string path(const std::string& name) const { return m_dir + "/" + name; }

  /// writeAtomically(path(name), write) and records `name` (listed in the marker first). `name`
  /// must be one of knownNames() (std::logic_error otherwise: a new output must be added there,
  /// so that the next run into the folder removes it). Does nothing for a name left out.
  void write(const std::string& name, const std::function<void(const std::string& part)>& write);
  void writeText(const std::string& name, const std::string& text);
  void writeImage(const std::string& name, const cv::Mat& image);
  /// Lists `name` in the marker before a file of that name is created by other means (the
  /// annotated rawlog's own writer).
  void announce(const std::string& name);
  /// Records a file written by other means (after announce).
  void recordWritten(const std::string& name);
  /// Files the run's [output] turns off (write_ply = false: every PLY): write() skips them.
  void leaveOut(const std::vector<std::string>& names);
  /// The files written so far, in order.
  const std::vector<std::string>& written() const { return m_written; }

  /// Every file name a run may write into its folder.
  static const std::vector<std::string>& knownNames();

 private:
  void writeMarker() const;

  std::string m_dir;
  std::vector<std::string> m_written;
  std::vector<std::string> m_announced;  ///< listed in the marker (claimed folders)
  std::vector<std::string> m_left_out;
  std::unique_ptr<RunFolderLock> m_lock;  ///< held by a claimed folder
};

}  // namespace rasm::pipeline
