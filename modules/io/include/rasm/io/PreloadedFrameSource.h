#pragma once
// Reads the frames of another source into memory up front, then hands them out in order. For
// benchmarks: the frame rate of a run then measures the mapping alone, as with a live camera that
// delivers decoded frames, not the PNG/JPEG decoding of a dataset on the same cores (on 7-Scenes
// the reader costs ~20 CPU ms per frame, a tenth of a 2-core frame budget). Memory: the decoded
// frames, ~2.2 MB each at 640x480 (float depth + BGR colour). An exception of the inner source is
// rethrown by next() after the frames read before it. Like PrefetchingFrameSource, only for
// sources whose frames do not depend on what the consumer does (recorded data, open-loop
// simulated trajectories). `rasm run`: [source] preload (false).

#include <deque>
#include <exception>
#include <functional>
#include <memory>

#include "rasm/io/FrameSource.h"

namespace rasm::io {

class PreloadedFrameSource : public FrameSource {
 public:
  /// Reads at most `max_frames` frames of `inner` (0 = all) at once; `on_frame(n)` is called
  /// after each (progress). Throws InputError once the decoded frames exceed `max_bytes`
  /// (0 = no limit), naming the source, the frame count and the limit.
  PreloadedFrameSource(std::unique_ptr<FrameSource> inner, long long max_frames = 0,
                       const std::function<void(long long)>& on_frame = {},
                       std::size_t max_bytes = 0);
  /// Bytes of image data held (depth, colour, ground-truth label images).
  std::size_t bytes() const { return m_bytes; }

  std::optional<RgbdFrame> next() override;
  long long sizeHint() const override { return m_size_hint; }
  std::string describe() const override { return m_describe; }
  /// Frames read into memory.
  long long loaded() const { return m_loaded; }

 private:
  std::deque<RgbdFrame> m_frames;
  std::exception_ptr m_error;  ///< what stopped the preload early, rethrown after the frames
  long long m_size_hint = -1, m_loaded = 0;
  std::size_t m_bytes = 0;
  std::string m_describe;
};

}  // namespace rasm::io
