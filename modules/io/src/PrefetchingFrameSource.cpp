#include "rasm/io/PrefetchingFrameSource.h"

#include <stdexcept>

#ifdef _OPENMP
#include <omp.h>
#endif

namespace rasm::io {

PrefetchingFrameSource::PrefetchingFrameSource(std::unique_ptr<FrameSource> inner, int depth)
    : m_inner(std::move(inner)),
      m_depth(std::size_t(depth < 1 ? 1 : depth)),
      m_size_hint(m_inner ? m_inner->sizeHint() : -1),
      m_describe(m_inner ? m_inner->describe() : std::string()) {
  if (!m_inner) throw std::invalid_argument("PrefetchingFrameSource: no inner source");
  m_thread = std::thread([this] { run(); });
}

PrefetchingFrameSource::~PrefetchingFrameSource() {
  {
    std::lock_guard<std::mutex> lock(m_mutex);
    m_stop = true;
  }
  m_cv.notify_all();
  if (m_thread.joinable()) m_thread.join();
}

void PrefetchingFrameSource::run() {
#ifdef _OPENMP
  // The read-ahead runs beside the consumer's OpenMP team on the same cores: a parallel region of
  // the source (e.g. colour registration) would start a second team that competes with it. One
  // thread here (a per-thread setting): on 2 cores the mapper's team keeps both.
  omp_set_num_threads(1);
#endif
  for (;;) {
    {
      std::unique_lock<std::mutex> lock(m_mutex);
      m_cv.wait(lock, [&] { return m_stop || m_ready.size() < m_depth; });
      if (m_stop) return;
    }
    std::optional<RgbdFrame> f;
    std::exception_ptr error;
    try {
      f = m_inner->next();
    } catch (...) {
      error = std::current_exception();
    }
    {
      std::lock_guard<std::mutex> lock(m_mutex);
      if (f) {
        m_ready.push_back(std::move(*f));
      } else {
        m_end = true;
        m_error = error;
      }
    }
    m_cv.notify_all();
    if (!f) return;
  }
}

std::optional<RgbdFrame> PrefetchingFrameSource::next() {
  std::unique_lock<std::mutex> lock(m_mutex);
  m_cv.wait(lock, [&] { return !m_ready.empty() || m_end; });
  if (!m_ready.empty()) {
    RgbdFrame f = std::move(m_ready.front());
    m_ready.pop_front();
    lock.unlock();
    m_cv.notify_all();
    return f;
  }
  if (m_error) {
    std::exception_ptr e = m_error;
    m_error = nullptr;  // reported once; later calls see the end
    std::rethrow_exception(e);
  }
  return std::nullopt;
}

}  // namespace rasm::io
