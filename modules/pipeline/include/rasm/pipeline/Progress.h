#pragma once
// Progress of long work on stderr: items done, rate, ETA; at most one line per period.

#include <chrono>
#include <string>

namespace rasm::pipeline {

class Progress {
 public:
  /// total <= 0: unknown (no percentage / ETA).
  Progress(std::string label, long long total, double period_s = 1.0);
  void update(long long done, const std::string& extra = {});
  void finish(long long done, const std::string& extra = {});

 private:
  using Clock = std::chrono::steady_clock;
  void print(long long done, const std::string& extra) const;
  std::string m_label;
  long long m_total;
  double m_period_s;
  Clock::time_point m_start, m_last;
};

}  // namespace rasm::pipeline
