#include "rasm/io/RealTimeFrameSource.h"

#include <chrono>

#ifdef _OPENMP
#include <omp.h>
#endif

namespace rasm::io {

using Clock = std::chrono::steady_clock;

RealTimeFrameSource::RealTimeFrameSource(std::unique_ptr<FrameSource> inner, bool pace)
    : m_inner(std::move(inner)),
      m_pace(pace),
      m_size_hint(m_inner->sizeHint()),
      m_describe(m_inner->describe() + (pace ? " (real time)" : "")) {
  m_thread = std::thread([this] { run(); });
}

RealTimeFrameSource::~RealTimeFrameSource() {
  {
    std::lock_guard<std::mutex> lock(m_mutex);
    m_stop = true;
  }
  m_cv.notify_all();
  if (m_thread.joinable()) m_thread.join();
}

void RealTimeFrameSource::offer(RgbdFrame&& f) {
  const auto now = Clock::now();
  std::lock_guard<std::mutex> lock(m_mutex);
  if (m_stats.offered == 0) m_first_offer = now;
  m_stats.offered_span_s = std::chrono::duration<double>(now - m_first_offer).count();
  ++m_stats.offered;
  if (m_slot) {
    ++m_stats.dropped;
    m_stats.dropped_indices.push_back((long long)m_slot->index);
  }
  m_slot = std::move(f);
}

void RealTimeFrameSource::run() {
#ifdef _OPENMP
  omp_set_num_threads(1);  // as PrefetchingFrameSource: leave the cores to the mapper's team
#endif
  std::optional<Clock::time_point> t0;
  double ts0 = 0.0;
  for (;;) {
    std::optional<RgbdFrame> f;
    std::exception_ptr error;
    try {
      f = m_inner->next();
    } catch (...) {
      error = std::current_exception();
    }
    if (f && m_pace) {
      if (!t0) {
        t0 = Clock::now();
        ts0 = f->timestamp_s;
      }
      const auto due = *t0 + std::chrono::duration_cast<Clock::duration>(
                                 std::chrono::duration<double>(f->timestamp_s - ts0));
      std::unique_lock<std::mutex> lock(m_mutex);
      m_cv.wait_until(lock, due, [&] { return m_stop; });
    }
    {
      std::lock_guard<std::mutex> lock(m_mutex);
      if (m_stop) return;
    }
    if (!f) {
      std::lock_guard<std::mutex> lock(m_mutex);
      m_end = true;
      m_error = error;
      m_cv.notify_all();
      return;
    }
    offer(std::move(*f));
    m_cv.notify_all();
  }
}

std::optional<RgbdFrame> RealTimeFrameSource::next() {
  std::unique_lock<std::mutex> lock(m_mutex);
  m_cv.wait(lock, [&] { return m_slot.has_value() || m_end; });
  if (m_slot) {
    RgbdFrame f = std::move(*m_slot);
    m_slot.reset();
    ++m_stats.delivered;
    return f;
  }
  if (m_error) {
    std::exception_ptr e = m_error;
    m_error = nullptr;  // reported once; later calls see the end
    std::rethrow_exception(e);
  }
  return std::nullopt;
}

RealTimeStats RealTimeFrameSource::stats() const {
  std::lock_guard<std::mutex> lock(m_mutex);
  return m_stats;
}

}  // namespace rasm::io
