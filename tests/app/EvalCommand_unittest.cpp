// `rasm eval ate|rpe` on bad arguments (issue 15): the built binary is run, its exit code and
// message checked.
#include <gtest/gtest.h>
#include <unistd.h>

#include <array>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <string>

namespace fs = std::filesystem;

namespace {

struct Result {
  int status = -1;
  std::string output;
};

Result rasmCommand(const std::string& args) {
  Result r;
  const std::string cmd = std::string(RASM_BINARY) + " " + args + " 2>&1";
  FILE* p = popen(cmd.c_str(), "r");
  if (!p) return r;
  std::array<char, 4096> buf{};
  while (std::fgets(buf.data(), int(buf.size()), p)) r.output += buf.data();
  const int st = pclose(p);
  r.status = WIFEXITED(st) ? WEXITSTATUS(st) : -1;
  return r;
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
