// The exploring loop (planner, navigator, simulated robot, simulated detector) gives
// byte-identical outputs before and after a change that is meant to move code, not behaviour
// (tests/run/RunChecksums.h, tests/run/run_checksums.txt).
#include <gtest/gtest.h>

#include <filesystem>

#include "rasm/io/FrameSource.h"
#include "rasm/run/MappingRun.h"
#include "run/RunChecksums.h"
#include "run/RunTestFiles.h"

using namespace rasm;
using namespace rasm::run;
using namespace rasm::run::testing;

namespace {

/// CRC of the first simulated frame's depth and colour: the simulator's input to the run.
std::string firstFrameCrc(const MappingRun& run) {
  auto source = run.openSource();
  const auto frame = source->next();
  if (!frame) return "none";
  std::string bytes;
  for (int y = 0; y < frame->height(); ++y) {
    bytes.append(reinterpret_cast<const char*>(frame->depth_m.row(y)),
                 sizeof(float) * frame->width());
    bytes.append(reinterpret_cast<const char*>(frame->colour.row(y)),
                 sizeof(Bgr8) * frame->width());
  }
  return crc32Hex(bytes);
}

}  // namespace

/// The embedded default (the robot exploring the office) for 15 simulated seconds at 320x240.
/// Embree, which renders the simulated frames, picks its SIMD width at run time; the first frame's
/// checksum is stored too, so that a CPU on which Embree renders other bits is told apart from a
/// change of rasm's behaviour.
TEST(RunChecksums, SimulatedExploringRunIsByteIdenticalToTheStoredRun) {
  const std::string out = tempDir("checksums_explore") + "/out";
  RunConfig cfg = RunConfig::embeddedDefault();
  cfg.set("output", "dir", out);
  setQuarterVgaCamera(cfg);
  cfg.set("exploration", "time_budget_s", "15");
  cfg.set("exploration", "wall_budget_s", "0");
  cfg.set("output", "write_3dscene", "false");
  MappingRun run(cfg);
  const std::string input_crc = firstFrameCrc(run);
  if (!writingChecksums()) {
    const auto stored = readStoredChecksums();
    const auto it = stored.find("sim_explore first_frame");
    ASSERT_NE(it, stored.end()) << "no stored checksum of the first frame";
    if (it->second != input_crc)
      GTEST_SKIP() << "the simulator renders other bits on this CPU (first frame " << input_crc
                   << ", stored " << it->second << "): the run cannot be compared";
  }
  const RunSummary s = run.run();
  ASSERT_GT(s.frames, 100u);
  expectStoredChecksums("sim_explore", out,
                        {"trajectory.txt", "groundtruth.txt", "map.surfelmap", "segments.json",
                         "objects.json", "frames.csv", "report.json", "exploration.json"},
                        {{"first_frame", input_crc}});
  std::filesystem::remove_all(std::filesystem::path(out).parent_path());
}
