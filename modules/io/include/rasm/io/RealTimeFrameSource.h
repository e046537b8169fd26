#pragma once
// Frames offered in real time to a consumer that may be slower (paper VI: "mapping in one thread
// at camera rate"): a reader thread takes frames from the inner source and offers each one at
// its time, into a single slot. A frame offered while the slot still holds one the consumer has
// not taken (the mapper is busy with an earlier frame) replaces it, and the replaced frame is
// dropped and counted: never more than one frame waits, whatever the consumer's speed, and the
// consumer always gets the newest one.
//  - pace = true (replays: rawlog / TUM / 7-Scenes with [source] real_time): frame k is offered
//    at wall time t0 + (timestamp_k - timestamp_0), t0 = when the first one was read.
//  - pace = false (live sensors, which pace themselves): frames are offered as the inner source
//    returns them.
// An exception of the inner source is rethrown by next() once the frame in the slot was taken.
// `rasm run`: [source] real_time (replays), always for live sources ([source] type = openni2).

#include <chrono>
#include <condition_variable>
#include <exception>
#include <memory>
#include <mutex>
#include <optional>
#include <thread>
#include <vector>

#include "rasm/io/FrameSource.h"

namespace rasm::io {

struct RealTimeStats {
  long long offered = 0;                   ///< frames the inner source delivered and were offered
  long long dropped = 0;                   ///< offered but replaced before the consumer took them
  long long delivered = 0;                 ///< taken by the consumer
  std::vector<long long> dropped_indices;  ///< RgbdFrame::index of the dropped frames
  double offered_span_s = 0.0;             ///< wall time from the first to the last offer
};

class RealTimeFrameSource : public FrameSource {
 public:
  RealTimeFrameSource(std::unique_ptr<FrameSource> inner, bool pace);
  /// Stops the reader after the read under way (if any) and joins it.
  ~RealTimeFrameSource() override;

  /// The newest offered frame not taken yet (waits for the next offer when there is none).
  std::optional<RgbdFrame> next() override;
  long long sizeHint() const override { return m_size_hint; }
  std::string describe() const override { return m_describe; }
  RealTimeStats stats() const;

 private:
  void run();
  void offer(RgbdFrame&& f);

  std::unique_ptr<FrameSource> m_inner;
  const bool m_pace;
  const long long m_size_hint;
  const std::string m_describe;
  mutable std::mutex m_mutex;
  std::condition_variable m_cv;
  std::optional<RgbdFrame> m_slot;
  bool m_end = false, m_stop = false;
  std::exception_ptr m_error;
  RealTimeStats m_stats;
  std::chrono::steady_clock::time_point m_first_offer;
  std::thread m_thread;
};

}  // namespace rasm::io
