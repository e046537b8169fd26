#pragma once
// Files written complete or not at all, never through a name somebody else put there (docs/io.md
// "What rasm writes, what it never touches, what it refuses"). Every writer of rasm stages its
// file through AtomicFile; the scratch folders of commands that need one are ScratchFolders.
//
// AtomicFile creates its temporary in the final file's folder with
// open(O_CREAT | O_EXCL | O_NOFOLLOW): "<final><suffix>" when that name is free, else
// "<final>.<8 random hex digits><suffix>". A file or symlink already at either name (a planted
// link, a stale temporary, a user's download) is never opened, followed or removed. commit()
// renames the temporary over the final name: rename(2) replaces a file or symlink there and never
// follows it. A temporary not committed is removed by the destructor.
//
// The writers fill the temporary by its path (fopen, gzopen, MRPT's streams, OpenCV): in a folder
// others may write to (/tmp, sticky), only its owner can remove or rename the file rasm created.

#include <functional>
#include <string>

namespace rasm {

/// Creates a new, empty regular file for the content of `final_path`, in its folder (see
/// above), and returns its path. std::runtime_error naming `final_path` and the system's reason
/// when none can be created (errno is kept).
std::string createExclusiveTemp(const std::string& final_path, const std::string& suffix = ".part");

/// A temporary for `final_path` (createExclusiveTemp), renamed over it by commit().
class AtomicFile {
 public:
  explicit AtomicFile(std::string final_path, const std::string& suffix = ".part");
  ~AtomicFile();  ///< removes the temporary unless committed
  AtomicFile(const AtomicFile&) = delete;
  AtomicFile& operator=(const AtomicFile&) = delete;

  /// The temporary to fill (an empty regular file rasm created).
  const std::string& path() const { return m_temp; }
  const std::string& finalPath() const { return m_final; }
  /// Renames the temporary over finalPath(). std::runtime_error "cannot rename <temp> to
  /// <final>: <reason>" (the temporary is then removed).
  void commit();

 private:
  std::string m_final, m_temp;
  bool m_done = false;
};

/// `fill(temp)` writes the content of `path` into the temporary `temp` (AtomicFile with `suffix`:
/// a writer that picks its format by the name, as cv::imwrite, needs the extension at the end),
/// which is renamed over `path` when `fill` returns true. std::runtime_error naming `path` when
/// it returns false or the temporary cannot be made; the temporary is then removed.
void writeThroughTemporary(const std::string& path,
                           const std::function<bool(const std::string& temp)>& fill,
                           const std::string& suffix = ".part");

/// `bytes` as the content of `path` through an AtomicFile, checked through fclose (a full disk
/// shows at the last flush). std::runtime_error naming `path` on failure; nothing is left behind.
void writeFileAtomic(const std::string& path, const std::string& bytes);

/// Refuses to write `path` when the folder it goes into is missing (or is not a folder): writers
/// create no folder chains (a mistyped path made `rasm convert` create a folder at the filesystem
/// root). InputError "<what>: its folder '<parent>' does not exist (create it first; rasm creates
/// no parent folders)". A path without a folder part (the working directory) is fine.
void requireParentFolder(const std::string& path, const std::string& what);

/// A new folder of its own under the system's temporary folder ($TMPDIR, else /tmp), created by
/// mkdtemp(3) with mode 0700 ("<prefix>XXXXXX"), removed with its content when destroyed.
class ScratchFolder {
 public:
  explicit ScratchFolder(const std::string& prefix);
  ~ScratchFolder();
  ScratchFolder(const ScratchFolder&) = delete;
  ScratchFolder& operator=(const ScratchFolder&) = delete;
  const std::string& path() const { return m_path; }

 private:
  std::string m_path;
};

}  // namespace rasm
