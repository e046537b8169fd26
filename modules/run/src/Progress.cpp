#include "rasm/run/Progress.h"

#include <unistd.h>

#include <algorithm>

#include "rasm/core/Log.h"

namespace rasm::run {

Progress::Progress(std::string label, long long total, double period_s, std::FILE* out, int tty)
    : m_label(std::move(label)),
      m_total(total),
      m_period_s(period_s),
      m_out(out),
      m_tty(tty < 0 ? isatty(fileno(out)) != 0 : tty != 0),
      m_start(Clock::now()),
      m_last(m_start) {}

void Progress::update(long long done, const std::string& extra) {
  const auto now = Clock::now();
  if (std::chrono::duration<double>(now - m_last).count() < m_period_s &&
      (m_total <= 0 || done < m_total))
    return;
  m_last = now;
  print(done, extra, false);
}

void Progress::finish(long long done, const std::string& extra) {
  print(done, extra, true);
}

void Progress::print(long long done, const std::string& extra, bool last) const {
  const double el = std::chrono::duration<double>(Clock::now() - m_start).count();
  const double rate = el > 0 ? done / el : 0.0;
  // On a terminal: back to the line's start, the text, erase what a longer line left.
  const char* begin = m_tty ? "\r" : "";
  const char* end = m_tty ? (last ? "\033[K\n" : "\033[K") : "\n";
  if (m_total > 0) {
    double eta = rate > 0 ? (m_total - done) / rate : 0.0;
    if (m_limit_s > 0) eta = std::max(0.0, std::min(eta, m_limit_s - el));
    std::fprintf(m_out, "%s%s: %lld/%lld (%.0f%%) %.1f/s ETA %.0f s %s%s", begin, m_label.c_str(),
                 done, m_total, 100.0 * done / m_total, rate, eta, extra.c_str(), end);
  } else {
    std::fprintf(m_out, "%s%s: %lld %.1f/s %s%s", begin, m_label.c_str(), done, rate, extra.c_str(),
                 end);
  }
  std::fflush(m_out);
  // A message printed while the line shows starts a line of its own (rasm/core/Log.h).
  if (m_tty && m_out == stderr) log::setProgressLineActive(!last);
}

}  // namespace rasm::run
