#include "rasm/classification/DetectorWorker.h"

#include <chrono>
#include <exception>

#include "rasm/core/Timing.h"

namespace rasm::classification {

DetectorWorker::DetectorWorker(std::unique_ptr<Detector> detector, int worker_index, bool threaded)
    : m_detector(std::move(detector)), m_index(worker_index), m_threaded(threaded) {
  if (m_threaded) m_thread = std::thread([this] { loop(); });
}

DetectorWorker::~DetectorWorker() {
  if (!m_threaded) return;
  {
    std::lock_guard<std::mutex> lock(m_mutex);
    m_stop = true;
  }
  m_cv.notify_all();
  m_thread.join();
}

bool DetectorWorker::offer(std::shared_ptr<const RgbdFrame> frame) {
  {
    std::lock_guard<std::mutex> lock(m_mutex);
    ++m_stats.offered;
    if (m_busy || m_disabled) {
      ++m_stats.skipped;
      return false;
    }
    m_busy = true;
    if (m_threaded) m_job = std::move(frame);
  }
  if (m_threaded)
    m_cv.notify_all();
  else
    run(frame);
  return true;
}

void DetectorWorker::loop() {
  for (;;) {
    std::shared_ptr<const RgbdFrame> job;
    {
      std::unique_lock<std::mutex> lock(m_mutex);
      m_cv.wait(lock, [this] { return m_stop || m_job; });
      if (m_stop) return;
      job = std::move(m_job);
      m_job.reset();
    }
    run(job);
  }
}

void DetectorWorker::run(const std::shared_ptr<const RgbdFrame>& frame) {
  DetectorResult result;
  result.frame_index = frame->index;
  result.worker = m_index;
  std::string error;
  const auto t0 = Clock::now();
  try {
    DetectorInput in;
    in.bgr = colourMat(*frame);
    in.frame = frame.get();
    in.frame_index = frame->index;
    result.detections = m_detector->detect(in);
  } catch (const std::exception& e) {
    error = e.what();
  } catch (...) {
    error = "unknown exception";
  }
  result.ms = msSince(t0);
  {
    std::lock_guard<std::mutex> lock(m_mutex);
    m_busy = false;
    if (!error.empty()) {
      m_disabled = true;
      m_error = "detector '" + m_detector->name() + "' failed on frame " +
                std::to_string(frame->index) + " and was disabled: " + error;
      result.failed = true;
      result.detections.clear();
      m_done.push_back(std::move(result));  // so the frame's L^p is released
    } else {
      ++m_stats.calls;
      m_stats.detections += result.detections.size();
      m_stats.ms_total += result.ms;
      if (result.ms > m_stats.ms_max) m_stats.ms_max = result.ms;
      m_done.push_back(std::move(result));
    }
  }
  m_cv.notify_all();
}

void DetectorWorker::collect(std::vector<DetectorResult>& out) {
  std::lock_guard<std::mutex> lock(m_mutex);
  for (auto& r : m_done) out.push_back(std::move(r));
  m_done.clear();
}

void DetectorWorker::waitIdle() {
  std::unique_lock<std::mutex> lock(m_mutex);
  m_cv.wait(lock, [this] { return !m_busy; });
}

bool DetectorWorker::disabled() const {
  std::lock_guard<std::mutex> lock(m_mutex);
  return m_disabled;
}
std::string DetectorWorker::error() const {
  std::lock_guard<std::mutex> lock(m_mutex);
  return m_error;
}
DetectorWorkerStats DetectorWorker::stats() const {
  std::lock_guard<std::mutex> lock(m_mutex);
  return m_stats;
}

}  // namespace rasm::classification
