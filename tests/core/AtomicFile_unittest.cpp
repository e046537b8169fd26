// rasm::AtomicFile and rasm::ScratchFolder (docs/io.md "What rasm writes, what it never touches,
// what it refuses"): a temporary is never opened through a file or link already at its name, the
// final name is replaced (never followed), an uncommitted temporary vanishes, scratch folders are
// unique and removed.
#include <gtest/gtest.h>
#include <unistd.h>

#include <algorithm>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

#include "rasm/core/AtomicFile.h"

namespace fs = std::filesystem;
using rasm::AtomicFile;
using rasm::createExclusiveTemp;
using rasm::ScratchFolder;
using rasm::writeFileAtomic;

namespace {
std::string freshDir(const std::string& name) {
  const fs::path p =
      fs::temp_directory_path() / ("rasm_atomic_" + name + "_" + std::to_string(::getpid()));
  fs::remove_all(p);
  fs::create_directories(p);
  return p.string();
}

void putBytes(const std::string& path, const std::string& bytes) {
  std::ofstream(path, std::ios::binary) << bytes;
}

std::string bytesOf(const std::string& path) {
  std::ifstream f(path, std::ios::binary);
  std::stringstream ss;
  ss << f.rdbuf();
  return ss.str();
}

std::vector<std::string> entriesOf(const std::string& dir) {
  std::vector<std::string> names;
  for (const auto& e : fs::directory_iterator(dir)) names.push_back(e.path().filename().string());
  std::sort(names.begin(), names.end());
  return names;
}
}  // namespace

TEST(AtomicFile, LinkPlantedAtTheTemporaryIsNeitherFollowedNorRemoved) {
  const std::string dir = freshDir("planted");
  putBytes(dir + "/victim.txt", "the victim's bytes\n");
  fs::create_symlink(dir + "/victim.txt", dir + "/out.json.part");
  writeFileAtomic(dir + "/out.json", "{\"rasm\": 1}\n");
  EXPECT_EQ(bytesOf(dir + "/victim.txt"), "the victim's bytes\n");
  EXPECT_TRUE(fs::is_symlink(dir + "/out.json.part"));
  EXPECT_EQ(fs::read_symlink(dir + "/out.json.part"), fs::path(dir + "/victim.txt"));
  EXPECT_FALSE(fs::is_symlink(dir + "/out.json"));
  EXPECT_EQ(bytesOf(dir + "/out.json"), "{\"rasm\": 1}\n");
  EXPECT_EQ(entriesOf(dir), (std::vector<std::string>{"out.json", "out.json.part", "victim.txt"}));
  fs::remove_all(dir);
}

TEST(AtomicFile, DanglingLinkAtTheTemporaryCreatesNothingAtItsTarget) {
  const std::string dir = freshDir("dangling");
  fs::create_symlink(dir + "/created_by_link", dir + "/out.txt.part");
  writeFileAtomic(dir + "/out.txt", "x");
  EXPECT_FALSE(fs::exists(dir + "/created_by_link"));
  EXPECT_EQ(bytesOf(dir + "/out.txt"), "x");
  fs::remove_all(dir);
}

TEST(AtomicFile, LinkAtTheFinalNameIsReplacedByARegularFile) {
  const std::string dir = freshDir("finallink");
  putBytes(dir + "/victim.txt", "victim");
  fs::create_symlink(dir + "/victim.txt", dir + "/out.txt");
  writeFileAtomic(dir + "/out.txt", "rasm");
  EXPECT_EQ(bytesOf(dir + "/victim.txt"), "victim");
  EXPECT_FALSE(fs::is_symlink(dir + "/out.txt"));
  EXPECT_EQ(bytesOf(dir + "/out.txt"), "rasm");
  fs::remove_all(dir);
}

TEST(AtomicFile, SomebodysPartFileStaysAndANameBesideItIsUsed) {
  const std::string dir = freshDir("stale");
  putBytes(dir + "/ubuntu.iso.part", "half a download");
  const std::string temp = createExclusiveTemp(dir + "/ubuntu.iso");
  EXPECT_NE(temp, dir + "/ubuntu.iso.part");
  EXPECT_EQ(temp.rfind(dir + "/ubuntu.iso.", 0), 0u) << temp;
  EXPECT_EQ(temp.substr(temp.size() - 5), ".part") << temp;
  EXPECT_TRUE(fs::is_regular_file(temp));
  EXPECT_EQ(fs::file_size(temp), 0u);
  EXPECT_EQ(bytesOf(dir + "/ubuntu.iso.part"), "half a download");
  fs::remove_all(dir);
}

TEST(AtomicFile, UncommittedTemporaryIsRemovedAndTheOldFileStays) {
  const std::string dir = freshDir("uncommitted");
  putBytes(dir + "/map.ply", "old");
  {
    AtomicFile file(dir + "/map.ply");
    EXPECT_EQ(file.path(), dir + "/map.ply.part");
    putBytes(file.path(), "half");
  }
  EXPECT_EQ(entriesOf(dir), std::vector<std::string>{"map.ply"});
  EXPECT_EQ(bytesOf(dir + "/map.ply"), "old");
  {
    AtomicFile file(dir + "/map.ply", ".part.png");  // a writer that picks its format by name
    EXPECT_EQ(file.path(), dir + "/map.ply.part.png");
    putBytes(file.path(), "new");
    file.commit();
  }
  EXPECT_EQ(entriesOf(dir), std::vector<std::string>{"map.ply"});
  EXPECT_EQ(bytesOf(dir + "/map.ply"), "new");
  fs::remove_all(dir);
}

TEST(AtomicFile, WriterThatFailsLeavesTheOldFileAndNoTemporary) {
  const std::string dir = freshDir("through");
  putBytes(dir + "/plot.png", "old plot");
  fs::create_symlink(dir + "/plot.png", dir + "/plot.png.part.png");  // planted: not followed
  EXPECT_THROW(rasm::writeThroughTemporary(
                   dir + "/plot.png", [](const std::string&) { return false; }, ".part.png"),
               std::runtime_error);
  EXPECT_EQ(entriesOf(dir), (std::vector<std::string>{"plot.png", "plot.png.part.png"}));
  EXPECT_EQ(bytesOf(dir + "/plot.png"), "old plot");
  std::string used;
  rasm::writeThroughTemporary(
      dir + "/plot.png",
      [&](const std::string& temp) {
        used = temp;
        putBytes(temp, "new plot");
        return true;
      },
      ".part.png");
  EXPECT_EQ(used.substr(used.size() - 9), ".part.png") << used;  // the extension stays last
  EXPECT_NE(used, dir + "/plot.png.part.png");
  EXPECT_EQ(bytesOf(dir + "/plot.png"), "new plot");
  EXPECT_TRUE(fs::is_symlink(dir + "/plot.png.part.png"));
  fs::remove_all(dir);
}

TEST(AtomicFile, MissingFolderIsAnErrorNamingTheFile) {
  try {
    writeFileAtomic("/nonexistent_rasm_folder/out.txt", "x");
    FAIL() << "no error";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("/nonexistent_rasm_folder/out.txt"), std::string::npos)
        << e.what();
  }
}

TEST(ScratchFolder, IsUniqueOwnedAndRemovedWithItsContent) {
  const std::string tmp = freshDir("scratch_tmp");
  const char* old = std::getenv("TMPDIR");
  const std::string old_tmpdir = old ? old : "";
  ::setenv("TMPDIR", tmp.c_str(), 1);
  // A link planted where a fixed name would be: never used.
  fs::create_directories(tmp + "/victim");
  putBytes(tmp + "/victim/config.ini", "the victim's");
  fs::create_directory_symlink(tmp + "/victim", tmp + "/rasm_bench");
  std::string a_path, b_path;
  {
    const ScratchFolder a("rasm_bench_"), b("rasm_bench_");
    a_path = a.path();
    b_path = b.path();
    EXPECT_NE(a_path, b_path);
    EXPECT_EQ(fs::path(a_path).parent_path(), fs::path(tmp));
    EXPECT_EQ(fs::status(a_path).permissions() & fs::perms::all, fs::perms::owner_all);
    putBytes(a_path + "/config.ini", "rasm's");
    fs::create_symlink(tmp + "/victim/config.ini", a_path + "/link");
  }
  if (old)
    ::setenv("TMPDIR", old_tmpdir.c_str(), 1);
  else
    ::unsetenv("TMPDIR");
  EXPECT_FALSE(fs::exists(a_path));
  EXPECT_FALSE(fs::exists(b_path));
  EXPECT_EQ(entriesOf(tmp), (std::vector<std::string>{"rasm_bench", "victim"}));
  EXPECT_EQ(bytesOf(tmp + "/victim/config.ini"), "the victim's");
  fs::remove_all(tmp);
}
