#pragma once
// Whose files a run folder holds (docs/io.md "What rasm writes, what it never touches, what it
// refuses").
//
// A run marks its folder with ".rasm-run.json" before it writes any other file, and lists each
// file in it before the file (or its temporary) is created: the marker names every file the run
// may have left, even when it was killed. The next run into the folder removes exactly those and
// their temporaries ("<name>.part", "<name>.<8 hex digits>.part"; rasm/core/AtomicFile.h), never
// anything else. A folder of a rasm older than the marker counts by its report.json ("files" and
// report.json itself). Only names a run can write (OutputFolder::knownNames) are ever removed,
// whatever a marker says. A run holds an flock on ".rasm.lock" in its folder for its whole life,
// so that a second run into the same folder fails at once instead of removing the first one's
// files.

#include <string>
#include <vector>

namespace rasm::pipeline {

/// The marker of a run folder and its lock file (both stay in the folder).
inline constexpr const char* kRunMarkerName = ".rasm-run.json";
inline constexpr const char* kRunLockName = ".rasm.lock";

/// [output] overwrite: what a run does with a folder that is not empty.
enum class OverwritePolicy {
  EarlierRun,    ///< "auto": a folder of an earlier run is reused (its files removed); a folder
                 ///< holding any other file is refused
  Never,         ///< "false": only an empty or new folder
  BesideOthers,  ///< "true" (rasm run --force): also a folder holding other files, which are left
                 ///< alone; only the earlier run's files are removed and rasm's names replaced
};
/// The policy of an [output] overwrite value: auto, true or false (InputError otherwise).
OverwritePolicy overwritePolicy(const std::string& value);

/// What a folder holds, as the next run sees it.
struct RunFolderContents {
  bool marked = false;  ///< an earlier run's marker (or an older rasm's report.json) was found
  /// Entries the earlier run listed (the marker and the lock excluded), with their temporaries.
  std::vector<std::string> earlier_run;
  std::vector<std::string> others;  ///< every other entry, the marker and the lock excepted
};
/// The contents of `dir` (an absent folder holds nothing); names sorted.
RunFolderContents inspectRunFolder(const std::string& dir);

/// Throws InputError naming `dir` and the files found when `policy` does not allow a run into a
/// folder with `contents`.
void refuseUnlessAllowed(const std::string& dir, const RunFolderContents& contents,
                         OverwritePolicy policy);

/// flock(LOCK_EX | LOCK_NB) on "<dir>/.rasm.lock" (created when missing, never through a link),
/// held while the object lives; the file holds the holder's pid.
class RunFolderLock {
 public:
  /// InputError "<dir> is in use by another rasm run (pid N)" when another process holds it.
  explicit RunFolderLock(const std::string& dir);
  ~RunFolderLock();
  RunFolderLock(const RunFolderLock&) = delete;
  RunFolderLock& operator=(const RunFolderLock&) = delete;

 private:
  int m_fd = -1;
};

}  // namespace rasm::pipeline
