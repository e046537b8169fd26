// The same input gives byte-identical outputs before and after a change that is meant to move
// code, not behaviour (tests/run/RunChecksums.h, tests/run/run_checksums.txt).
#include <gtest/gtest.h>

#include <filesystem>

#include "rasm/run/MappingRun.h"
#include "run/RunChecksums.h"
#include "run/RunTestFiles.h"

using namespace rasm::run;
using namespace rasm::run::testing;

/// The repository's hand-held rawlog (20 frames, 320x240) through tracking, fusion and
/// segmentation; no detector (the simulated one needs the simulator's ground truth, the DNN
/// detectors the shared data). Only the product's code and the pinned build flags
/// (-march=x86-64-v2) decide these bytes: OpenCV's run-time CPU dispatch does not (checked with
/// OPENCV_CPU_DISABLE=AVX512_SKX,AVX2,FMA3,AVX,POPCNT,SSE4_2,SSE4_1).
TEST(RunChecksums, HandHeldRawlogRunIsByteIdenticalToTheStoredRun) {
  const std::string out = tempDir("checksums_rawlog") + "/out";
  RunConfig cfg =
      RunConfig::fromString("[source]\ntype = rawlog\npath = " + kSimRawlog + "\n", "test");
  cfg.set("output", "dir", out);
  cfg.set("classification", "detectors", "");
  cfg.set("output", "write_3dscene", "false");
  MappingRun run(cfg);
  const RunSummary s = run.run();
  ASSERT_EQ(s.frames, 20u);
  expectStoredChecksums("handheld_rawlog", out,
                        {"trajectory.txt", "map.surfelmap", "map.ply", "segments.json",
                         "objects.json", "frames.csv", "report.json"});
  std::filesystem::remove_all(std::filesystem::path(out).parent_path());
}
