#include "rasm/core/Log.h"

#include <chrono>
#include <cstring>
#include <ctime>
#include <mutex>

#include "rasm/core/Error.h"

namespace rasm::log {

namespace {

struct State {
  std::mutex mutex;
  Level console_level = Level::Info;
  std::FILE* console = stderr;
  std::FILE* file = nullptr;
  bool progress_line = false;
};

State& state() {
  static State s;
  return s;
}

std::string utcNow() {
  const auto now = std::chrono::system_clock::now();
  const std::time_t t = std::chrono::system_clock::to_time_t(now);
  const long ms = long(
      std::chrono::duration_cast<std::chrono::milliseconds>(now.time_since_epoch()).count() % 1000);
  std::tm tm{};
  gmtime_r(&t, &tm);
  char buf[40];
  std::strftime(buf, sizeof buf, "%Y-%m-%dT%H:%M:%S", &tm);
  char out[48];
  std::snprintf(out, sizeof out, "%s.%03ldZ", buf, ms);
  return out;
}

}  // namespace

const char* toString(Level level) {
  switch (level) {
    case Level::Debug:
      return "debug";
    case Level::Info:
      return "info";
    case Level::Warning:
      return "warning";
    case Level::Error:
      return "error";
  }
  return "?";
}

Level parseLevel(const std::string& text, const std::string& what) {
  for (Level l : {Level::Debug, Level::Info, Level::Warning, Level::Error})
    if (text == toString(l)) return l;
  throwInputError(what, "is '" + text + "'; expected debug, info, warning or error");
}

void setConsoleLevel(Level level) {
  std::lock_guard<std::mutex> lock(state().mutex);
  state().console_level = level;
}

Level consoleLevel() {
  std::lock_guard<std::mutex> lock(state().mutex);
  return state().console_level;
}

void setConsoleStream(std::FILE* stream) {
  std::lock_guard<std::mutex> lock(state().mutex);
  state().console = stream ? stream : stderr;
}

void attachFile(const std::string& path) {
  std::FILE* f = std::fopen(path.c_str(), "a");
  if (!f)
    throwInputError("log file " + path, std::string("cannot be opened: ") + std::strerror(errno));
  std::lock_guard<std::mutex> lock(state().mutex);
  if (state().file) std::fclose(state().file);
  state().file = f;
}

void detachFile() {
  std::lock_guard<std::mutex> lock(state().mutex);
  if (state().file) std::fclose(state().file);
  state().file = nullptr;
}

bool fileAttached() {
  std::lock_guard<std::mutex> lock(state().mutex);
  return state().file != nullptr;
}

void setProgressLineActive(bool active) {
  std::lock_guard<std::mutex> lock(state().mutex);
  state().progress_line = active;
}

void message(Level level, const std::string& text) {
  State& s = state();
  std::lock_guard<std::mutex> lock(s.mutex);
  if (level >= s.console_level) {
    const char* prefix = level == Level::Info      ? ""
                         : level == Level::Debug   ? "rasm: debug: "
                         : level == Level::Warning ? "rasm: warning: "
                                                   : "rasm: error: ";
    std::fprintf(s.console, "%s%s%s\n", s.progress_line ? "\n" : "", prefix, text.c_str());
    std::fflush(s.console);
    s.progress_line = false;
  }
  if (s.file) {
    std::fprintf(s.file, "%s %s %s\n", utcNow().c_str(), toString(level), text.c_str());
    std::fflush(s.file);
  }
}

}  // namespace rasm::log
