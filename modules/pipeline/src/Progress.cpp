#include "rasm/pipeline/Progress.h"

#include <cstdio>

namespace rasm::pipeline {

Progress::Progress(std::string label, long long total, double period_s)
    : m_label(std::move(label)),
      m_total(total),
      m_period_s(period_s),
      m_start(Clock::now()),
      m_last(m_start) {}

void Progress::update(long long done, const std::string& extra) {
  const auto now = Clock::now();
  if (std::chrono::duration<double>(now - m_last).count() < m_period_s &&
      (m_total <= 0 || done < m_total))
    return;
  m_last = now;
  print(done, extra);
}

void Progress::finish(long long done, const std::string& extra) {
  print(done, extra);
}

void Progress::print(long long done, const std::string& extra) const {
  const double el = std::chrono::duration<double>(Clock::now() - m_start).count();
  const double rate = el > 0 ? done / el : 0.0;
  if (m_total > 0) {
    const double eta = rate > 0 ? (m_total - done) / rate : 0.0;
    std::fprintf(stderr, "%s: %lld/%lld (%.0f%%) %.1f/s ETA %.0f s %s\n", m_label.c_str(), done,
                 m_total, 100.0 * done / m_total, rate, eta, extra.c_str());
  } else {
    std::fprintf(stderr, "%s: %lld %.1f/s %s\n", m_label.c_str(), done, rate, extra.c_str());
  }
}

}  // namespace rasm::pipeline
