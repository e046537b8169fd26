// `rasm eval ate|rpe` on bad arguments (issue 15): the built binary is run, its exit code and
// message checked.
#include <gtest/gtest.h>
#include <unistd.h>

#include <algorithm>
#include <array>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <string>

#include "RasmProcess.h"

namespace fs = std::filesystem;

namespace {

using rasm::app::testing::Result;

Result rasmCommand(const std::string& args) {
  return rasm::app::testing::runRasm(args);
}

class EvalCommand : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() / ("rasm_eval_" + std::to_string(::getpid()));
    fs::create_directories(dir_);
    std::ofstream f(gt());
    for (int i = 0; i < 10; ++i) f << 1.0 + 0.1 * i << " " << 0.01 * i << " 0 1 0 0 0 1\n";
  }
  void TearDown() override { fs::remove_all(dir_); }
  std::string gt() const { return (dir_ / "gt.txt").string(); }
  fs::path dir_;
};

}  // namespace

TEST_F(EvalCommand, FolderAsEstimateIsNamed) {
  const Result r = rasmCommand("eval ate " + gt() + " " + dir_.string());
  EXPECT_NE(r.status, 0) << r.output;
  EXPECT_NE(r.output.find(dir_.string() + ": is a folder"), std::string::npos) << r.output;
  EXPECT_EQ(r.output.find("0 poses"), std::string::npos) << r.output;
}

TEST_F(EvalCommand, EmptyEstimateIsNamed) {
  std::ofstream((dir_ / "empty.txt").string()) << "# nothing\n";
  const Result r = rasmCommand("eval ate " + gt() + " " + (dir_ / "empty.txt").string());
  EXPECT_NE(r.status, 0) << r.output;
  EXPECT_NE(r.output.find("empty.txt: holds no pose"), std::string::npos) << r.output;
}

TEST_F(EvalCommand, MaxDtAndDeltaMustBePositiveFiniteNumbers) {
  for (const char* v : {"-1", "0", "nan", "inf", "three"}) {
    const Result r = rasmCommand("eval ate " + gt() + " " + gt() + " --max-dt " + v);
    EXPECT_NE(r.status, 0) << v << ": " << r.output;
    EXPECT_NE(r.output.find("--max-dt"), std::string::npos) << v << ": " << r.output;
  }
  Result r = rasmCommand("eval rpe " + gt() + " " + gt() + " --delta nan");
  EXPECT_NE(r.status, 0) << r.output;
  EXPECT_NE(r.output.find("--delta"), std::string::npos) << r.output;
  r = rasmCommand("eval rpe " + gt() + " " + gt() + " --frames --delta 1.5");
  EXPECT_NE(r.status, 0) << r.output;
  EXPECT_NE(r.output.find("whole number"), std::string::npos) << r.output;
  r = rasmCommand("eval ate " + gt() + " " + gt() + " --max-dt 0.02");
  EXPECT_EQ(r.status, 0) << r.output;
}

namespace {
/// A frames.csv of `n` frames at 10 Hz with the columns `rasm eval memory` reads, surfels and
/// memory following `surfels(i)` (RSS = 100 MB + 200 bytes per surfel; store 64 bytes each).
template <typename F>
void writeMemoryCsv(const fs::path& dir, int n, F surfels) {
  fs::create_directories(dir);
  std::ofstream f((dir / "frames.csv").string());
  f << "index,timestamp_s,tracked,surfels,ms_total,rss_mb,map_memory_bytes\n";
  for (int i = 0; i < n; ++i) {
    const double s = surfels(i);
    f << i << "," << 100.0 + 0.1 * i << ",1," << s << ",30," << 100.0 + 200.0 * s / 1048576.0 << ","
      << 64.0 * s << "\n";
  }
}
}  // namespace

// issue 15, 6: the plateau criterion over the second half of a run, on curves with known answers.
TEST_F(EvalCommand, MemoryPlateausOnlyWhenTheSecondHalfStopsGrowing) {
  // Covered after a third of the run, then flat: no growth over the second half.
  writeMemoryCsv(dir_ / "flat", 300, [](int i) { return 1e6 * std::min(1.0, i / 100.0) + 1000; });
  Result r = rasmCommand("eval memory " + (dir_ / "flat").string() + " --json " +
                         (dir_ / "flat.json").string() + " --plot " + (dir_ / "flat.png").string());
  EXPECT_EQ(r.status, 0) << r.output;
  EXPECT_NE(r.output.find("plateau"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("64 bytes/surfel"), std::string::npos) << r.output;
  EXPECT_TRUE(fs::file_size(dir_ / "flat.png") > 1000);
  // Growing linearly all along: s(149) = 1.5e6 at half time, s(299) = 3e6 at the end: +100%.
  writeMemoryCsv(dir_ / "growing", 300, [](int i) { return 1e4 * (i + 1); });
  r = rasmCommand("eval memory " + (dir_ / "growing").string());
  EXPECT_EQ(r.status, 1) << r.output;
  EXPECT_NE(r.output.find("STILL GROWING"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("(+100.0%"), std::string::npos) << r.output;
  // A 4% rise is within the 5% criterion, a 6% rise is not.
  writeMemoryCsv(dir_ / "rise4", 300, [](int i) { return i < 200 ? 1e6 : 1.04e6; });
  EXPECT_EQ(rasmCommand("eval memory " + (dir_ / "rise4").string()).status, 0);
  writeMemoryCsv(dir_ / "rise6", 300, [](int i) { return i < 200 ? 1e6 : 1.06e6; });
  EXPECT_EQ(rasmCommand("eval memory " + (dir_ / "rise6").string()).status, 1);
}

TEST_F(EvalCommand, MemoryNamesAFramesCsvWithoutItsColumns) {
  fs::create_directories(dir_ / "old");
  std::ofstream((dir_ / "old" / "frames.csv").string())
      << "index,timestamp_s,tracked,surfels\n0,1,1,5\n";
  const Result r = rasmCommand("eval memory " + (dir_ / "old").string());
  EXPECT_NE(r.status, 0) << r.output;
  EXPECT_NE(r.output.find("frames.csv: has no column 'rss_mb'"), std::string::npos) << r.output;
  EXPECT_NE(rasmCommand("eval memory " + (dir_ / "missing").string()).status, 0);
}
