#include "rasm/io/PreloadedFrameSource.h"

#include <stdexcept>

namespace rasm::io {

PreloadedFrameSource::PreloadedFrameSource(std::unique_ptr<FrameSource> inner, long long max_frames,
                                           const std::function<void(long long)>& on_frame) {
  if (!inner) throw std::invalid_argument("PreloadedFrameSource: no inner source");
  m_describe = inner->describe() + " (preloaded)";
  try {
    while (max_frames <= 0 || m_loaded < max_frames) {
      std::optional<RgbdFrame> f = inner->next();
      if (!f) break;
      m_frames.push_back(std::move(*f));
      ++m_loaded;
      if (on_frame) on_frame(m_loaded);
    }
  } catch (...) {
    m_error = std::current_exception();
  }
  m_size_hint = m_loaded;
}

std::optional<RgbdFrame> PreloadedFrameSource::next() {
  if (m_frames.empty()) {
    if (m_error) {
      const std::exception_ptr e = m_error;
      m_error = nullptr;
      std::rethrow_exception(e);
    }
    return std::nullopt;
  }
  RgbdFrame f = std::move(m_frames.front());
  m_frames.pop_front();
  return f;
}

}  // namespace rasm::io
