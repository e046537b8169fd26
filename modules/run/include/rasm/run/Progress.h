#pragma once
// Progress of long work on stderr: items done, rate, ETA; at most one line per period. On a
// terminal it is one line, rewritten in place ("\r ... erase to the end of the line"), ended by
// finish(); otherwise (a log file, a pipe, CI) plain lines.

#include <chrono>
#include <cstdio>
#include <string>

namespace rasm::run {

class Progress {
 public:
  /// total <= 0: unknown (no percentage / ETA). `out`: where to print (stderr), `tty`: rewrite
  /// one line (default: whether `out` is a terminal).
  Progress(std::string label, long long total, double period_s = 1.0, std::FILE* out = stderr,
           int tty = -1);
  /// The work ends at the latest `seconds` after construction (a wall-clock budget): the ETA
  /// printed is never beyond it.
  void setTimeLimit(double seconds) { m_limit_s = seconds; }
  void update(long long done, const std::string& extra = {});
  /// The last line (on a terminal: the updated line, then a newline).
  void finish(long long done, const std::string& extra = {});

 private:
  using Clock = std::chrono::steady_clock;
  void print(long long done, const std::string& extra, bool last) const;
  std::string m_label;
  long long m_total;
  double m_period_s;
  std::FILE* m_out;
  bool m_tty;
  double m_limit_s = 0.0;
  Clock::time_point m_start, m_last;
};

}  // namespace rasm::run
