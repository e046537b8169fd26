// Map snapshots for other threads (issue 13, 3): a reader thread takes snapshots and renders
// from them while the Mapper fuses 300 simulated frames. Every snapshot is the map as it was after
// a whole frame (its surfel count is the one the mapper recorded for that frame), structurally
// sound (finite positions, unit normals, an index the renderer draws from), and snapshots move
// forward. Run under ThreadSanitizer with scripts/tsan.sh. The mapper's wait for a copy is in
// FrameResult::ms ("map_lock_wait"); this test prints it (unit tests are not timed: the bound is
// checked by bench_snapshot).
#include <gtest/gtest.h>

#include <atomic>
#include <cmath>
#include <cstdio>
#include <mutex>
#include <thread>
#include <vector>

#include "rasm/pipeline/Mapper.h"
#include "rasm/sim/SimulatedSequence.h"
#include "rasm/surfel_map/SurfelRenderer.h"

using namespace rasm;
using namespace rasm::pipeline;

namespace {
/// Records the map size after each frame, inside the Mapper's write region (after fusion).
class SizeRecorder : public MapperStage {
 public:
  SizeRecorder() : MapperStage("size_recorder") {}
  void process(FrameContext&, maps::CSurfelMap&) override {}
  void finishFrame(FrameContext&, maps::CSurfelMap& map) override {
    std::lock_guard<std::mutex> lk(mutex);
    sizes.push_back(map.size());
  }
  std::mutex mutex;
  std::vector<int> sizes;  ///< [k] = surfels after frame k
};
}  // namespace

TEST(MapSnapshot, AReaderRendersConsistentSnapshotsWhileTheMapperFuses) {
  const sim::World world = sim::loadWorld("office");
  sim::SequenceOptions opt;
  opt.seed = 2;
  opt.max_frames = 300;
  opt.intrinsics = CameraIntrinsics::preset("kinect_v1").level(1);  // 320x240: a short test
  sim::SimulatedSequence seq(world, sim::loadTrajectorySpec("office_handheld"), opt);

  Mapper mapper;
  auto rec = std::make_unique<SizeRecorder>();
  SizeRecorder& sizes = *rec;
  mapper.addStage(std::move(rec));

  std::atomic<bool> done{false};
  std::atomic<int> snapshots{0}, torn{0}, unsound{0}, backwards{0}, rendered{0};
  std::atomic<double> max_copy_ms{0.0};
  Eigen::Isometry3d T_view = Eigen::Isometry3d::Identity();  // set before the reader starts
  RgbdFrame f;
  ASSERT_TRUE(seq.next(f));
  T_view = *f.gt_T_world_cam;
  const CameraIntrinsics K = f.intrinsics;
  mapper.processFrame(f);

  std::thread reader([&] {
    maps::SurfelRenderer renderer;
    maps::RenderedMaps out;
    std::size_t last = 0;
    while (!done.load()) {
      const std::shared_ptr<const MapSnapshot> s = mapper.snapshot();
      ++snapshots;
      if (s->frames < last) ++backwards;
      last = s->frames;
      max_copy_ms = std::max(max_copy_ms.load(), s->copy_ms);
      {
        std::lock_guard<std::mutex> lk(sizes.mutex);
        if (s->frames == 0 || s->frames > sizes.sizes.size() ||
            sizes.sizes[s->frames - 1] != s->store.size())
          ++torn;
      }
      const maps::SurfelArrays a = s->store.arrays();
      for (int i = 0; i < a.size; i += 97) {
        if (!a.alive(i)) continue;
        const Vec3f p = a.position(i), n = a.normal(i);
        if (!std::isfinite(p.x()) || !std::isfinite(p.y()) || !std::isfinite(p.z()) ||
            std::abs(n.norm() - 1.0f) > 1e-3f)
          ++unsound;
      }
      maps::RenderOptions ro;
      ro.outputs = maps::kRenderDepth;
      maps::RenderStats st;
      renderer.render(s->store, T_view, K, ro, out, &st);
      rendered += st.pixels_drawn > 0;
    }
  });
  double max_wait_ms = 0.0;
  int frames = 1;
  const auto& timers = mapper.timerNames();
  const std::size_t wait_timer =
      std::size_t(std::find(timers.begin(), timers.end(), "map_lock_wait") - timers.begin());
  ASSERT_LT(wait_timer, timers.size());
  while (seq.next(f)) {
    const FrameResult r = mapper.processFrame(f);
    max_wait_ms = std::max(max_wait_ms, r.ms[wait_timer]);
    ++frames;
  }
  done = true;
  reader.join();
  std::printf(
      "%d frames, %d snapshots (copy up to %.2f ms), mapper waited up to %.2f ms for a copy\n",
      frames, snapshots.load(), max_copy_ms.load(), max_wait_ms);
  EXPECT_EQ(frames, 300);
  EXPECT_GT(snapshots.load(), 10);
  EXPECT_EQ(torn.load(), 0) << "a snapshot mixed two frames";
  EXPECT_EQ(unsound.load(), 0);
  EXPECT_EQ(backwards.load(), 0);
  EXPECT_EQ(rendered.load(), snapshots.load()) << "every snapshot renders (its index is sound)";
}
