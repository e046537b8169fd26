#pragma once
// rasm::log: the messages a run gives its user, by level. Each goes to the console (stderr) when
// at or above the console level (`rasm run -q` / `-v`, [output] log_level), and every one,
// whatever its level, with a UTC time stamp to the log file while one is attached (the run
// folder's run.log, MappingRun). Thread-safe. The updating progress line (Progress.h) is not a
// message; a message printed while it shows starts on a line of its own.
//
//   log::warning("the detector is off: " + why);   // "rasm: warning: the detector is off: ..."
//   log::info("rasm run: office -> rasm_out");      // as is
//   run.log: "2026-12-07T06:10:01.123Z warning the detector is off: ..."

#include <cstdio>
#include <string>

namespace rasm::log {

enum class Level { Debug = 0, Info, Warning, Error };
const char* toString(Level level);
/// "debug", "info", "warning" or "error"; throws InputError naming `what` otherwise.
Level parseLevel(const std::string& text, const std::string& what);

/// Messages below this level are not shown on the console (default Info).
void setConsoleLevel(Level level);
Level consoleLevel();
/// Where console messages go (default stderr; tests pass a temporary file).
void setConsoleStream(std::FILE* stream);

/// Appends every message to `path` from now on (created, or appended to when it exists): throws
/// InputError naming the file when it cannot be opened. One file at a time: it replaces the last.
void attachFile(const std::string& path);
/// Closes the log file (no-op without one).
void detachFile();
bool fileAttached();

/// The console knows a progress line is on screen (Progress.h): the next message starts a line.
void setProgressLineActive(bool active);

void message(Level level, const std::string& text);
inline void debug(const std::string& text) {
  message(Level::Debug, text);
}
inline void info(const std::string& text) {
  message(Level::Info, text);
}
inline void warning(const std::string& text) {
  message(Level::Warning, text);
}
inline void error(const std::string& text) {
  message(Level::Error, text);
}

/// Attaches `path` for the lifetime of the guard (detached by the destructor).
class FileGuard {
 public:
  explicit FileGuard(const std::string& path) { attachFile(path); }
  ~FileGuard() { detachFile(); }
  FileGuard(const FileGuard&) = delete;
  FileGuard& operator=(const FileGuard&) = delete;
};

}  // namespace rasm::log
