// The writers of `rasm convert` and `rasm sim record` (RawlogWriter, writeTumTrajectory,
// convertToRawlog) never follow a link planted at "<output>.part" (docs/io.md "What rasm writes,
// what it never touches, what it refuses"): the link and its target stay byte-identical and the
// output becomes rasm's regular file.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <iterator>
#include <sstream>
#include <string>

#include "IoTestUtils.h"
#include "rasm/io/DatasetConverter.h"
#include "rasm/io/RawlogFrameSource.h"
#include "rasm/io/RawlogWriter.h"
#include "rasm/io/Trajectory.h"

namespace fs = std::filesystem;
using namespace rasm;
using namespace rasm::io;
using rasm::io::test::ScratchDir;
using rasm::io::test::syntheticFrame;

namespace {
const std::string kVictimBytes = "somebody's thesis, not rasm's\n";

std::string bytesOf(const std::string& path) {
  std::ifstream f(path, std::ios::binary);
  std::stringstream ss;
  ss << f.rdbuf();
  return ss.str();
}

/// A victim file and a link to it at "<output>.part".
void plantLink(const ScratchDir& dir, const std::string& output, const std::string& victim) {
  std::ofstream(dir / victim, std::ios::binary) << kVictimBytes;
  fs::create_symlink(dir / victim, dir / (output + ".part"));
}

void expectVictimUntouched(const ScratchDir& dir, const std::string& output,
                           const std::string& victim) {
  EXPECT_EQ(bytesOf(dir / victim), kVictimBytes) << victim;
  EXPECT_TRUE(fs::is_symlink(dir / (output + ".part"))) << output;
  EXPECT_EQ(fs::read_symlink(dir / (output + ".part")), fs::path(dir / victim));
  EXPECT_TRUE(fs::is_regular_file(fs::symlink_status(dir / output))) << output;
}
}  // namespace

TEST(PlantedLinks, RawlogWriterWritesBesideALinkAtItsTemporary) {
  ScratchDir dir("rawlog");
  plantLink(dir, "seq.rawlog", "thesis.tex");
  {
    RawlogWriter w(dir / "seq.rawlog");
    EXPECT_NE(w.temporaryPath(), dir / "seq.rawlog.part");
    w.write(syntheticFrame(0));
    w.write(syntheticFrame(1));
    w.close();
  }
  expectVictimUntouched(dir, "seq.rawlog", "thesis.tex");
  RawlogFrameSource src(dir / "seq.rawlog");
  int frames = 0;
  while (src.next()) ++frames;
  EXPECT_EQ(frames, 2);
}

TEST(PlantedLinks, RawlogWriterDestroyedOpenRemovesOnlyItsOwnTemporary) {
  ScratchDir dir("rawlog_open");
  plantLink(dir, "seq.rawlog", "thesis.tex");
  {
    RawlogWriter w(dir / "seq.rawlog");
    w.write(syntheticFrame(0));
  }
  EXPECT_EQ(bytesOf(dir / "thesis.tex"), kVictimBytes);
  EXPECT_TRUE(fs::is_symlink(dir / "seq.rawlog.part"));
  EXPECT_FALSE(fs::exists(fs::symlink_status(dir / "seq.rawlog")));
  const auto entries = std::distance(fs::directory_iterator(dir.str()), fs::directory_iterator{});
  EXPECT_EQ(entries, 2);  // the victim and the link: no temporary of rasm's left
}

TEST(PlantedLinks, TumTrajectoryWritesBesideALinkAtItsTemporary) {
  ScratchDir dir("tum");
  plantLink(dir, "groundtruth.txt", "config.ini");
  Trajectory traj;
  for (int i = 0; i < 3; ++i) {
    const RgbdFrame f = syntheticFrame(i);
    traj.push_back({f.timestamp_s, *f.gt_T_world_cam});
  }
  writeTumTrajectory(dir / "groundtruth.txt", traj, "test");
  expectVictimUntouched(dir, "groundtruth.txt", "config.ini");
  EXPECT_EQ(readTumTrajectory(dir / "groundtruth.txt").size(), 3u);
}

TEST(PlantedLinks, ConvertWritesBesideLinksAtBothTemporaries) {
  ScratchDir dir("convert");
  {
    RawlogWriter w(dir / "input.rawlog");
    for (int i = 0; i < 3; ++i) w.write(syntheticFrame(i));
    w.close();
  }
  plantLink(dir, "out.rawlog", "important.ply");
  plantLink(dir, "out_groundtruth.txt", "notes.txt");
  RawlogFrameSource src(dir / "input.rawlog");
  const ConvertResult r = convertToRawlog(src, dir / "out.rawlog");
  EXPECT_EQ(r.frames, 3u);
  ASSERT_EQ(r.groundtruth_path, dir / "out_groundtruth.txt");
  expectVictimUntouched(dir, "out.rawlog", "important.ply");
  expectVictimUntouched(dir, "out_groundtruth.txt", "notes.txt");
  EXPECT_EQ(readTumTrajectory(r.groundtruth_path).size(), 3u);
}
