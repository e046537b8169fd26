// Hostile files for the readers (docs/io.md "Refused or reported"). Image headers are checked
// before decoding: a 20000x20000 depth PNG used to take 2.5 GB and 12 s of decoding before
// "expected 640x480"; now its header is refused at once, as is a depth PNG that is not 16-bit
// grey. A device given as a rawlog, and a gzip rawlog corrupt from its start, say so.
#include <gtest/gtest.h>

#include <chrono>
#include <fstream>
#include <iterator>
#include <opencv2/core.hpp>
#include <opencv2/imgcodecs.hpp>

#include <mrpt/obs/CObservation3DRangeScan.h>
#include "io/IoTestUtils.h"
#include "rasm/core/Error.h"

#include "rasm/io/RawlogFrameSource.h"
#include "rasm/io/RgbdObservation.h"
#include "rasm/io/TumFrameSource.h"

using namespace rasm;
using namespace rasm::io;
using namespace rasm::io::test;

namespace {

/// A PNG whose IHDR claims `w` x `h` (16-bit grey) over a few bytes of data: what a hostile file
/// looks like before anything is decoded.
std::string pngHeaderOnly(std::uint32_t w, std::uint32_t h) {
  std::string b("\x89PNG\r\n\x1a\n", 8);
  const auto be32 = [&](std::uint32_t v) {
    for (int s = 24; s >= 0; s -= 8) b.push_back(char((v >> s) & 0xff));
  };
  be32(13);
  b += "IHDR";
  be32(w);
  be32(h);
  b += std::string("\x10\x00\x00\x00\x00", 5);  // 16-bit, grey, deflate, no filter, no interlace
  be32(0);                                      // CRC (not read: refused before)
  be32(4);
  b += "IDAT";
  b += std::string(4, '\0');
  be32(0);
  be32(0);
  b += "IEND";
  be32(0xAE426082);
  return b;
}

/// A TUM folder of 3 frames of 64x48; frame `bad` gets `bad_depth` as its depth file.
std::string tumFolder(const ScratchDir& dir, int bad, const std::string& bad_depth) {
  const std::string folder = dir / "fr1_hostile";
  std::filesystem::create_directories(folder + "/rgb");
  std::filesystem::create_directories(folder + "/depth");
  std::ofstream rgb(folder + "/rgb.txt"), depth(folder + "/depth.txt");
  for (int i = 0; i < 3; ++i) {
    const std::string t = std::to_string(10 + i) + ".000000";
    if (i == bad) {
      std::ofstream(folder + "/depth/" + t + ".png", std::ios::binary) << bad_depth;
    } else {
      cv::imwrite(folder + "/depth/" + t + ".png", cv::Mat(48, 64, CV_16UC1, cv::Scalar(5000)));
    }
    cv::imwrite(folder + "/rgb/" + t + ".png", cv::Mat(48, 64, CV_8UC3, cv::Scalar(1, 2, 3)));
    depth << t << " depth/" << t << ".png\n";
    rgb << t << " rgb/" << t << ".png\n";
  }
  return folder;
}

std::string errorOfAllFrames(const std::string& folder) {
  try {
    TumSourceOptions opt;
    opt.intrinsics_override = CameraIntrinsics(50, 50, 31.5, 23.5, 64, 48);
    TumFrameSource src(folder, opt);
    while (src.next()) {
    }
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

}  // namespace

TEST(HostileImages, HugePngHeaderIsRefusedBeforeDecoding) {
  ScratchDir dir("huge_png");
  const std::string folder = tumFolder(dir, 1, pngHeaderOnly(20000, 20000));
  const auto t0 = std::chrono::steady_clock::now();
  const std::string e = errorOfAllFrames(folder);
  const double s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  EXPECT_NE(e.find("TUM frame 1, depth image"), std::string::npos) << e;
  EXPECT_NE(e.find("its PNG header says 20000x20000, expected 64x48"), std::string::npos) << e;
  EXPECT_LT(s, 1.0);
}

TEST(HostileImages, HugeFirstImageIsRefusedByTheFixedBound) {
  ScratchDir dir("huge_first");
  const std::string e = errorOfAllFrames(tumFolder(dir, 0, pngHeaderOnly(20000, 20000)));
  EXPECT_NE(e.find("20000x20000"), std::string::npos) << e;
  EXPECT_NE(e.find("at most 4096x4096"), std::string::npos) << e;
}

TEST(HostileImages, OtherSizeThanTheFirstFrameIsNamed) {
  ScratchDir dir("other_size");
  std::vector<unsigned char> png;
  cv::imencode(".png", cv::Mat(24, 32, CV_16UC1, cv::Scalar(5000)), png);
  const std::string e = errorOfAllFrames(tumFolder(dir, 2, std::string(png.begin(), png.end())));
  EXPECT_NE(e.find("TUM frame 2, depth image"), std::string::npos) << e;
  EXPECT_NE(e.find("says 32x24, expected 64x48"), std::string::npos) << e;
}

TEST(HostileImages, EightBitDepthPngIsRefusedByItsHeader) {
  ScratchDir dir("depth8");
  std::vector<unsigned char> png;
  cv::imencode(".png", cv::Mat(48, 64, CV_8UC3, cv::Scalar(1, 2, 3)), png);
  const std::string e = errorOfAllFrames(tumFolder(dir, 1, std::string(png.begin(), png.end())));
  EXPECT_NE(e.find("expected a 16-bit single-channel depth PNG"), std::string::npos) << e;
  EXPECT_NE(e.find("3 channel(s) of 8 bits"), std::string::npos) << e;
}

TEST(HostileRawlog, DeviceIsNotAFile) {
  try {
    RawlogFrameSource src("/dev/urandom");
    FAIL() << "no error";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("rawlog /dev/urandom: is not a regular file"),
              std::string::npos)
        << e.what();
  }
}

TEST(HostileRawlog, GzipCorruptAtItsStartSaysSo) {
  ScratchDir dir("gz30");
  // A gzip header, then bytes that do not decompress.
  std::string bytes("\x1f\x8b\x08\x00\x00\x00\x00\x00\x00\x03", 10);
  for (int i = 0; i < 200; ++i) bytes.push_back(char(0xff - i));
  std::ofstream(dir / "bad.rawlog", std::ios::binary) << bytes;
  try {
    RawlogFrameSource src(dir / "bad.rawlog");
    FAIL() << "no error before the first frame";
  } catch (const InputError& e) {
    const std::string msg = e.what();
    EXPECT_NE(msg.find("rawlog " + std::string(dir / "bad.rawlog") +
                       ": its gzip stream is corrupt (its compressed data is damaged"),
              std::string::npos)
        << msg;
    EXPECT_NE(msg.find("found at byte "), std::string::npos) << msg;
  }
}

/// rangeUnits = 1e30 turned every pixel into an invalid depth: a run of 0 surfels, status ok.
TEST(HostileRawlog, AbsurdRangeUnitsAreRefused) {
  mrpt::obs::CObservation3DRangeScan obs;
  observationFromFrame(syntheticFrame(0), obs);
  EXPECT_NO_THROW(frameFromObservation(obs, "rawlog x.rawlog, frame 0"));
  for (const float units : {1e30f, 0.5f}) {
    obs.rangeUnits = units;
    try {
      frameFromObservation(obs, "rawlog x.rawlog, frame 0");
      ADD_FAILURE() << units << ": no error";
    } catch (const InputError& e) {
      EXPECT_NE(std::string(e.what()).find("rawlog x.rawlog, frame 0: rangeUnits is"),
                std::string::npos)
          << e.what();
      EXPECT_NE(std::string(e.what()).find("expected in (0, 0.1]"), std::string::npos) << e.what();
    }
  }
}

/// A bit flipped early in a gzip rawlog decompressed into altered frames, mapped until
/// deserialization failed many frames later (gzip checks its CRC only at its end). The whole
/// stream is now checked before the first frame: the file is refused and nothing is mapped.
TEST(HostileRawlog, GzipBitFlipIsRefusedBeforeTheFirstFrame) {
  ScratchDir dir("bitflip");
  std::ifstream in(std::string(RASM_SOURCE_DIR) + "/rawlogs/sim_office_handheld_320x240.rawlog",
                   std::ios::binary);
  const std::string good((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  ASSERT_GT(good.size(), 1000u);
  EXPECT_EQ(gzipStreamProblem(std::string(RASM_SOURCE_DIR) +
                              "/rawlogs/sim_office_handheld_320x240.rawlog"),
            "");
  // The flip of the probe (it mapped 19 frames) and one near the end of the stream.
  for (const std::size_t at : {good.size() * 3 / 10, good.size() - 200}) {
    SCOPED_TRACE(at);
    std::string bytes = good;
    bytes[at] ^= 0x10;
    std::ofstream(dir / "flip.rawlog", std::ios::binary) << bytes;
    try {
      RawlogFrameSource src(dir / "flip.rawlog");
      ADD_FAILURE() << "no error before the first frame";
    } catch (const InputError& e) {
      const std::string msg = e.what();
      EXPECT_NE(
          msg.find("rawlog " + std::string(dir / "flip.rawlog") + ": its gzip stream is corrupt ("),
          std::string::npos)
          << msg;
      EXPECT_NE(msg.find("found at byte "), std::string::npos) << msg;
      EXPECT_NE(msg.find("nothing was mapped"), std::string::npos) << msg;
    }
  }
}

/// A gzip rawlog cut short is refused before its first frame, naming where it ends.
TEST(HostileRawlog, GzipTruncatedIsRefusedNamingTheByte) {
  ScratchDir dir("gzcut");
  std::ifstream in(std::string(RASM_SOURCE_DIR) + "/rawlogs/sim_office_handheld_320x240.rawlog",
                   std::ios::binary);
  std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  bytes.resize(bytes.size() - 4);  // only the trailer's length field is missing
  std::ofstream(dir / "cut.rawlog", std::ios::binary) << bytes;
  try {
    RawlogFrameSource src(dir / "cut.rawlog");
    FAIL() << "no error before the first frame";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("its gzip stream is corrupt (truncated at byte " +
                                         std::to_string(bytes.size()) + ": the file ends inside"),
              std::string::npos)
        << e.what();
  }
}
