#include "rasm/io/PreloadedFrameSource.h"

#include <stdexcept>
#include <string>

#include "rasm/core/Error.h"

namespace rasm::io {

namespace {
template <typename T>
std::size_t imageBytes(const Image<T>& img) {
  return img.pitchBytes() * std::size_t(img.height());
}
}  // namespace

PreloadedFrameSource::PreloadedFrameSource(std::unique_ptr<FrameSource> inner, long long max_frames,
                                           const std::function<void(long long)>& on_frame,
                                           std::size_t max_bytes) {
  if (!inner) throw std::invalid_argument("PreloadedFrameSource: no inner source");
  m_describe = inner->describe() + " (preloaded)";
  bool over_limit = false;
  try {
    while (max_frames <= 0 || m_loaded < max_frames) {
      std::optional<RgbdFrame> f = inner->next();
      if (!f) break;
      m_bytes += imageBytes(f->depth_m) + imageBytes(f->colour) + imageBytes(f->gt_instance) +
                 imageBytes(f->gt_class);
      m_frames.push_back(std::move(*f));
      ++m_loaded;
      if (on_frame) on_frame(m_loaded);
      if (max_bytes > 0 && m_bytes > max_bytes) {
        over_limit = true;
        break;
      }
    }
  } catch (...) {
    m_error = std::current_exception();  // rethrown by next() after the frames read before it
  }
  if (over_limit)
    throwInputError("preloading " + inner->describe(),
                    "the first " + std::to_string(m_loaded) + " frames already take " +
                        std::to_string(m_bytes >> 20) + " MiB, over the limit of " +
                        std::to_string(max_bytes >> 20) +
                        " MiB: read fewer frames ([source] max_frames) or do not preload");
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
