#pragma once
// A detector on its own worker thread (paper VI: YOLO on the GPU and the zero-shot classifier on
// the CPU start on the same frame and finish at about the same time, while mapping goes on).
//  - One job at a time: offer() hands the worker a frame when it is idle and returns false when
//    it is still busy with an earlier one (that frame is skipped for this detector and counted);
//    nothing ever queues, so a slow detector costs detections, never memory or latency.
//  - Results carry the index of the frame they were computed on; the mapper fuses them with that
//    frame's L^p (ClassificationStage), whenever they arrive.
//  - A detector that throws is disabled (its error kept for the report) and mapping goes on.
//  - threaded = false runs detect() inside offer() (deterministic runs, tests).

#include <condition_variable>
#include <cstddef>
#include <memory>
#include <mutex>
#include <string>
#include <thread>
#include <vector>

#include "rasm/classification/Detector.h"

namespace rasm::classification {

struct DetectorResult {
  std::size_t frame_index = 0;
  int worker = 0;  ///< index of the worker (ClassificationStage's detector order)
  std::vector<Detection> detections;
  double ms = 0.0;      ///< detect() wall time
  bool failed = false;  ///< detect() threw (the worker is now disabled): no detections
};

struct DetectorWorkerStats {
  std::size_t offered = 0;  ///< frames offered
  std::size_t calls = 0;    ///< frames detected (finished)
  std::size_t skipped = 0;  ///< frames offered while busy or disabled
  std::size_t detections = 0;
  double ms_total = 0.0, ms_max = 0.0;
};

class DetectorWorker {
 public:
  DetectorWorker(std::unique_ptr<Detector> detector, int worker_index, bool threaded);
  ~DetectorWorker();
  DetectorWorker(const DetectorWorker&) = delete;
  DetectorWorker& operator=(const DetectorWorker&) = delete;

  /// Starts detection on `frame` (kept alive by the worker while it runs) unless the worker is
  /// busy or disabled; returns whether it started.
  bool offer(std::shared_ptr<const RgbdFrame> frame);
  /// Appends the results finished since the last call.
  void collect(std::vector<DetectorResult>& out);
  /// Blocks until the job in flight (if any) has finished.
  void waitIdle();

  const Detector& detector() const { return *m_detector; }
  bool disabled() const;
  /// Why it was disabled ("" while it works).
  std::string error() const;
  DetectorWorkerStats stats() const;

 private:
  void loop();
  void run(const std::shared_ptr<const RgbdFrame>& frame);

  std::unique_ptr<Detector> m_detector;
  const int m_index;
  const bool m_threaded;
  mutable std::mutex m_mutex;
  std::condition_variable m_cv;
  std::shared_ptr<const RgbdFrame> m_job;  ///< the frame to detect next (null: none)
  bool m_busy = false, m_stop = false, m_disabled = false;
  std::string m_error;
  std::vector<DetectorResult> m_done;
  DetectorWorkerStats m_stats;
  std::thread m_thread;
};

}  // namespace rasm::classification
