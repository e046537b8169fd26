// rasm::log: console filtering by level, every message in the attached file, level names.
#include <gtest/gtest.h>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

#include "rasm/core/Error.h"
#include "rasm/core/Log.h"

namespace rasm {
namespace {

std::string readAll(std::FILE* f) {
  std::fflush(f);
  std::rewind(f);
  std::string text;
  char buf[256];
  while (std::fgets(buf, sizeof buf, f)) text += buf;
  return text;
}

TEST(Log, TheConsoleShowsFromItsLevelUpAndTheFileEveryMessage) {
  const std::string path =
      (std::filesystem::temp_directory_path() / "rasm_log_unittest.log").string();
  std::filesystem::remove(path);
  std::FILE* console = std::tmpfile();
  ASSERT_NE(console, nullptr);
  log::setConsoleStream(console);
  log::setConsoleLevel(log::Level::Warning);
  {
    log::FileGuard guard(path);
    EXPECT_TRUE(log::fileAttached());
    log::debug("the graph has 12 nodes");
    log::info("rasm run: office -> out");
    log::warning("the detector is off");
    log::error("the robot did not stop");
  }
  EXPECT_FALSE(log::fileAttached());
  log::info("after the run");  // the file is closed: not in it
  log::setConsoleStream(nullptr);
  log::setConsoleLevel(log::Level::Info);

  const std::string shown = readAll(console);
  std::fclose(console);
  EXPECT_EQ(shown, "rasm: warning: the detector is off\nrasm: error: the robot did not stop\n");

  std::ifstream in(path);
  std::vector<std::string> lines;
  for (std::string line; std::getline(in, line);) lines.push_back(line);
  ASSERT_EQ(lines.size(), 4u);
  const char* expected[] = {" debug the graph has 12 nodes", " info rasm run: office -> out",
                            " warning the detector is off", " error the robot did not stop"};
  for (std::size_t i = 0; i < lines.size(); ++i) {
    // 2026-12-07T06:10:01.123Z: a UTC time of 24 characters before the level.
    ASSERT_GE(lines[i].size(), 24u);
    EXPECT_EQ(lines[i][10], 'T');
    EXPECT_EQ(lines[i][23], 'Z');
    EXPECT_EQ(lines[i].substr(24), expected[i]);
  }
  std::filesystem::remove(path);
}

TEST(Log, LevelsAreParsedByNameAndAnUnknownOneIsNamedInTheError) {
  EXPECT_EQ(log::parseLevel("debug", "[output] log_level"), log::Level::Debug);
  EXPECT_EQ(log::parseLevel("error", "[output] log_level"), log::Level::Error);
  try {
    log::parseLevel("loud", "[output] log_level");
    FAIL() << "accepted 'loud'";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("[output] log_level"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("loud"), std::string::npos) << e.what();
  }
}

TEST(Log, AFileThatCannotBeOpenedIsAnErrorNamingIt) {
  EXPECT_THROW(log::attachFile("/nonexistent-folder/run.log"), InputError);
  EXPECT_FALSE(log::fileAttached());
}

}  // namespace
}  // namespace rasm
