#pragma once
// SIGINT / SIGTERM during `rasm run` (docs/io.md "Runs that never lie").
//
// The first signal asks the run to stop: it reads no further frame, finishes the current one and
// writes every output of the frames done (report.json "status": "interrupted"). A second signal
// aborts at once: the handler removes the temporaries being written (ScopedTemporary), writes
// report.json "status": "aborted" when a run folder is set (setAbortReport), and exits with
// 128 + the signal. Only async-signal-safe calls run in the handler (unlink, open, write, rename,
// _exit; getdents64, unlinkat and rmdir for a ScopedAbortRemovesFolder).

#include <string>

namespace rasm::pipeline {

/// Installs the handlers of SIGINT and SIGTERM (for `rasm run`; tests may call it too), and
/// ignores SIGXFSZ: a write beyond a file size limit then fails like one on a full disk.
void installInterruptHandlers();
/// Restores the default actions and forgets a stop request (tests).
void uninstallInterruptHandlers();

/// The signal that asked the run to stop, 0 when none.
int stopSignal();
/// "SIGINT", "SIGTERM" or "signal N".
std::string signalName(int sig);

/// While it lives, the temporary `part` (an AtomicFile's path) is removed by an aborting signal.
/// At most 16 at a time (more are not registered: they are then removed only by the next run into
/// the folder).
class ScopedTemporary {
 public:
  explicit ScopedTemporary(const std::string& part);
  ~ScopedTemporary();
  ScopedTemporary(const ScopedTemporary&) = delete;
  ScopedTemporary& operator=(const ScopedTemporary&) = delete;

 private:
  int m_slot = -1;
};

/// While it lives, an aborting signal removes the folder `dir` after the temporaries and the
/// abort report: the files directly in it (unlinkat over getdents64: async-signal-safe), then the
/// folder itself (rmdir; a subfolder holding files stays). For a scratch folder of the process's
/// own (rasm bench's ScratchFolder), which a first signal removes on the normal return path.
class ScopedAbortRemovesFolder {
 public:
  explicit ScopedAbortRemovesFolder(const std::string& dir);
  ~ScopedAbortRemovesFolder();
  ScopedAbortRemovesFolder(const ScopedAbortRemovesFolder&) = delete;
  ScopedAbortRemovesFolder& operator=(const ScopedAbortRemovesFolder&) = delete;
};

/// Where an aborting signal writes its report.json (empty: none), and the frames done so far.
void setAbortReport(const std::string& report_path);
void setFramesDone(long long frames);

}  // namespace rasm::pipeline
