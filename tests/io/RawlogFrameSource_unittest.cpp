// RawlogFrameSource: both rawlog formats, MRPT's real Kinect frame, colour registration
// convention, label filter, corrupt / missing files.
#include "rasm/io/RawlogFrameSource.h"

#include <gtest/gtest.h>
#include <mrpt/core/aligned_allocator.h>
#include <mrpt/img/CImage.h>
#include <mrpt/io/CFileGZOutputStream.h>
#include <mrpt/io/CFileOutputStream.h>
#include <mrpt/io/CMemoryStream.h>
#include <mrpt/obs/CActionCollection.h>
#include <mrpt/obs/CActionRobotMovement2D.h>
#include <mrpt/obs/CObservation3DRangeScan.h>
#include <mrpt/obs/CSensoryFrame.h>
#include <mrpt/serialization/CArchive.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <limits>
#include <opencv2/imgcodecs.hpp>
#include <vector>

#include <zlib.h>

#include "IoTestUtils.h"
#include "rasm/core/Error.h"
#include "rasm/core/SE3.h"
#include "rasm/io/RgbdObservation.h"

namespace fs = std::filesystem;
using namespace rasm;
using namespace rasm::io;
using rasm::io::test::ScratchDir;
using rasm::io::test::syntheticFrame;

namespace {

std::string errorOf(const std::function<void()>& fn) {
  try {
    fn();
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

std::vector<RgbdFrame> readAll(const std::string& path, const RawlogSourceOptions& opt = {}) {
  RawlogFrameSource src(path, opt);
  std::vector<RgbdFrame> out;
  while (auto f = src.next()) out.push_back(std::move(*f));
  return out;
}

mrpt::obs::CObservation3DRangeScan::Ptr scanOf(const RgbdFrame& f, const std::string& label) {
  auto obs = mrpt::obs::CObservation3DRangeScan::Create();
  FrameToObservationOptions o;
  o.sensor_label = label;
  observationFromFrame(f, *obs, o);
  return obs;
}

std::string fileBytes(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  return std::string((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
}

/// Writes `full`: three synthetic frames, uncompressed (a plain file, which MRPT reads as well: a
/// gzip one cut short is refused before its first frame), and `cut`: the same cut in the middle
/// of the third object.
void writeCutRawlog(const std::string& full, const std::string& cut) {
  {
    mrpt::io::CFileOutputStream f(full);
    auto ar = mrpt::serialization::archiveFrom(f);
    for (int i = 0; i < 3; ++i) ar << *scanOf(syntheticFrame(i, 64, 48), "RGBD");
  }
  const std::string bytes = fileBytes(full);
  std::ofstream(cut, std::ios::binary).write(bytes.data(), std::streamsize(bytes.size() * 5 / 6));
}

}  // namespace

TEST(RawlogFrameSource, ActionsAndSensoryFramesFormatWithOdometryIncrements) {
  ScratchDir dir("sf");
  const std::string path = dir / "sf.rawlog";
  const mrpt::poses::CPose2D inc(0.1, 0.02, 0.05);
  {
    mrpt::io::CFileGZOutputStream f(path);
    auto ar = mrpt::serialization::archiveFrom(f);
    for (int i = 0; i < 3; ++i) {
      mrpt::obs::CActionCollection acts;
      mrpt::obs::CActionRobotMovement2D mv;
      mv.computeFromOdometry(inc, mrpt::obs::CActionRobotMovement2D::TMotionModelOptions());
      acts.insert(mv);
      mrpt::obs::CSensoryFrame sf;
      sf.insert(scanOf(syntheticFrame(i), "KINECT"));
      ar << acts << sf;
    }
  }
  const auto frames = readAll(path);
  ASSERT_EQ(frames.size(), 3u);
  mrpt::poses::CPose2D expected;
  for (int i = 0; i < 3; ++i) {
    SCOPED_TRACE(i);
    expected = expected + inc;
    ASSERT_TRUE(frames[i].odometry_xyyaw.has_value());
    EXPECT_NEAR(frames[i].odometry_xyyaw->x(), expected.x(), 1e-9);
    EXPECT_NEAR(frames[i].odometry_xyyaw->y(), expected.y(), 1e-9);
    EXPECT_NEAR(frames[i].odometry_xyyaw->z(), expected.phi(), 1e-9);
    const RgbdFrame ref = syntheticFrame(i);
    EXPECT_NEAR(frames[i].depth_m(5, 7), ref.depth_m(5, 7), 0.0005f);
    EXPECT_EQ(frames[i].colour(5, 7).g, ref.colour(5, 7).g);
    // Written without rasm's marker: a non-identity sensorPose is read as ground truth.
    ASSERT_TRUE(frames[i].gt_T_world_cam.has_value());
    EXPECT_LT(translationDistance(*frames[i].gt_T_world_cam, *ref.gt_T_world_cam), 1e-6);
  }
}

TEST(RawlogFrameSource, SensorLabelFilter) {
  ScratchDir dir("label");
  const std::string path = dir / "two.rawlog";
  {
    mrpt::io::CFileGZOutputStream f(path);
    auto ar = mrpt::serialization::archiveFrom(f);
    for (int i = 0; i < 4; ++i) ar << *scanOf(syntheticFrame(i), i % 2 ? "RIGHT" : "LEFT");
  }
  RawlogSourceOptions opt;
  opt.sensor_label = "RIGHT";
  const auto right = readAll(path, opt);
  ASSERT_EQ(right.size(), 2u);
  EXPECT_EQ(right[0].intrinsics.fx, syntheticFrame(1).intrinsics.fx);
  EXPECT_EQ(right[1].intrinsics.fx, syntheticFrame(3).intrinsics.fx);
  EXPECT_EQ(readAll(path).size(), 4u);

  opt.sensor_label = "NOPE";
  const std::string msg = errorOf([&] { readAll(path, opt); });
  EXPECT_NE(msg.find("'NOPE'"), std::string::npos) << msg;
  EXPECT_NE(msg.find("'LEFT'"), std::string::npos) << msg;  // tells which labels exist
}

// Colour camera 10 cm to the right of the depth camera (MRPT: -y), other intrinsics and size:
// registered colour at depth pixel (x, y) must be the colour pixel the 3-D point projects to.
TEST(RawlogFrameSource, RegistersColourWithRelativePoseIntensityWRTDepth) {
  const int W = 40, H = 30, Wc = 50, Hc = 40;
  const double z = 2.0;
  mrpt::obs::CObservation3DRangeScan obs;
  obs.hasRangeImage = true;
  obs.rangeUnits = 0.001f;
  obs.rangeImage_setSize(H, W);
  obs.rangeImage.fill(uint16_t(z / 0.001));
  CameraIntrinsics Kd(40, 40, 19.5, 14.5, W, H), Kc(50, 50, 24.5, 19.5, Wc, Hc);
  Kd.toTCamera(obs.cameraParams);
  Kc.toTCamera(obs.cameraParamsIntensity);
  cv::Mat col(Hc, Wc, CV_8UC3);
  for (int v = 0; v < Hc; ++v)
    for (int u = 0; u < Wc; ++u) col.at<cv::Vec3b>(v, u) = cv::Vec3b(uchar(u), uchar(v), 200);
  obs.hasIntensityImage = true;
  obs.intensityImage = mrpt::img::CImage(col, mrpt::img::DEEP_COPY);
  obs.relativePoseIntensityWRTDepth = mrpt::poses::CPose3D(0, -0.1, 0, -M_PI / 2, 0, -M_PI / 2);
  ASSERT_FALSE(obs.doDepthAndIntensityCamerasCoincide());

  const RgbdFrame f = frameFromObservation(obs, "test");
  int checked = 0;
  for (int y = 0; y < H; ++y)
    for (int x = 0; x < W; ++x) {
      const double X = (x - Kd.cx) / Kd.fx * z - 0.1, Y = (y - Kd.cy) / Kd.fy * z;  // colour frame
      const long u = std::lround(Kc.fx * X / z + Kc.cx), v = std::lround(Kc.fy * Y / z + Kc.cy);
      if (u < 0 || v < 0 || u >= Wc || v >= Hc) continue;
      ASSERT_EQ(f.colour(x, y).b, u) << x << "," << y;
      ASSERT_EQ(f.colour(x, y).g, v) << x << "," << y;
      ASSERT_EQ(f.colour(x, y).r, 200);
      ++checked;
    }
  EXPECT_GT(checked, W * H / 2);
}

TEST(RawlogFrameSource, RangeAlongTheRayIsConvertedToDepth) {
  const int W = 20, H = 10;
  mrpt::obs::CObservation3DRangeScan obs;
  obs.hasRangeImage = true;
  obs.range_is_depth = false;
  obs.rangeImage_setSize(H, W);
  const CameraIntrinsics K(10, 12, 9.5, 4.5, W, H);
  K.toTCamera(obs.cameraParams);
  // A fronto-parallel plane at z = 1.5 m seen as ranges |p|.
  for (int y = 0; y < H; ++y)
    for (int x = 0; x < W; ++x) {
      const double xn = (x - K.cx) / K.fx, yn = (y - K.cy) / K.fy;
      obs.rangeImage(y, x) = uint16_t(std::lround(1500.0 * std::sqrt(1 + xn * xn + yn * yn)));
    }
  const RgbdFrame f = frameFromObservation(obs, "test");
  for (int y = 0; y < H; ++y)
    for (int x = 0; x < W; ++x) ASSERT_NEAR(f.depth_m(x, y), 1.5f, 0.001f);
}

TEST(RawlogFrameSource, RealKinectFrameFromMrpt) {
  const std::string path = RASM_MRPT_TEST_RAWLOG;
  if (!fs::exists(path)) GTEST_SKIP() << path << " not installed (package mrpt-common)";
  const auto frames = readAll(path);
  ASSERT_EQ(frames.size(), 1u);
  const RgbdFrame& f = frames[0];
  EXPECT_EQ(f.width(), 640);
  EXPECT_EQ(f.height(), 480);
  EXPECT_NEAR(f.intrinsics.fx, 572.88, 0.01);
  EXPECT_NEAR(f.intrinsics.fy, 542.74, 0.01);
  float dmin = 1e9f, dmax = 0;
  int valid = 0;
  for (int y = 0; y < f.height(); ++y)
    for (int x = 0; x < f.width(); ++x)
      if (f.depth_m(x, y) > 0) {
        dmin = std::min(dmin, f.depth_m(x, y));
        dmax = std::max(dmax, f.depth_m(x, y));
        ++valid;
      }
  EXPECT_GT(valid, 640 * 480 / 2);
  EXPECT_GE(dmin, 1.6f);
  EXPECT_LE(dmax, 2.6f);
  // Cameras do not coincide in this rawlog: colour went through registration. Valid-depth pixels
  // must have been filled (the colour camera sees the same scene), i.e. not black.
  long lit = 0;
  for (int y = 0; y < f.height(); ++y)
    for (int x = 0; x < f.width(); ++x) {
      const Bgr8 c = f.colour(x, y);
      if (f.depth_m(x, y) > 0 && (c.b | c.g | c.r) != 0) ++lit;
    }
  EXPECT_GT(lit, 0.9 * valid);
  EXPECT_FALSE(f.gt_T_world_cam.has_value());  // sensorPose is the identity in this file
  EXPECT_GT(f.timestamp_s, 1.4e9);
  if (const char* dump = std::getenv("RASM_IO_DUMP_DIR")) {
    cv::Mat m(f.height(), f.width(), CV_8UC3, const_cast<Bgr8*>(f.colour.data()),
              f.colour.pitchBytes());
    cv::imwrite(std::string(dump) + "/mrpt_frame_registered_colour.png", m);
  }
}

TEST(RawlogFrameSource, MissingFileNamesIt) {
  const std::string msg = errorOf([] { RawlogFrameSource src("/tmp/rasm_no_such_file.rawlog"); });
  EXPECT_NE(msg.find("/tmp/rasm_no_such_file.rawlog"), std::string::npos) << msg;
  EXPECT_NE(msg.find("not found"), std::string::npos) << msg;
}

TEST(RawlogFrameSource, TruncatedRawlogNamesFileAndFrame) {
  ScratchDir dir("trunc");
  const std::string full = dir / "full.rawlog", cut = dir / "cut.rawlog";
  writeCutRawlog(full, cut);
  ASSERT_EQ(readAll(full).size(), 3u);
  RawlogFrameSource src(cut);
  EXPECT_TRUE(src.next().has_value());
  EXPECT_TRUE(src.next().has_value());
  const std::string msg = errorOf([&] { src.next(); });
  EXPECT_NE(msg.find(cut), std::string::npos) << msg;
  EXPECT_NE(msg.find("frame 2"), std::string::npos) << msg;
  EXPECT_NE(msg.find("truncated"), std::string::npos) << msg;
}

TEST(RawlogFrameSource, CompressedTruncatedRawlogIsAnInputError) {
  const std::string path = RASM_MRPT_TEST_RAWLOG;
  if (!fs::exists(path)) GTEST_SKIP() << path << " not installed (package mrpt-common)";
  ScratchDir dir("gz");
  const std::string cut = dir / "cut.rawlog";
  const std::string bytes = fileBytes(path);
  std::ofstream(cut, std::ios::binary).write(bytes.data(), std::streamsize(bytes.size() / 2));
  // Refused before its first frame (the gzip stream is checked whole when the file is opened).
  const std::string msg = errorOf([&] { readAll(cut); });
  EXPECT_NE(msg.find(cut), std::string::npos) << msg;
  EXPECT_NE(msg.find("its gzip stream is corrupt (truncated at byte"), std::string::npos) << msg;
}

TEST(RawlogFrameSource, GarbageFileIsAnInputError) {
  ScratchDir dir("garbage");
  const std::string path = dir / "garbage.rawlog";
  std::ofstream(path)
      << "this is not a rawlog, just some text that goes on for a while............";
  const std::string msg = errorOf([&] { readAll(path); });
  EXPECT_NE(msg.find(path), std::string::npos) << msg;
}

// ---- PrefetchingFrameSource (reads ahead on its own thread) ----

#include "rasm/io/PrefetchingFrameSource.h"

TEST(PrefetchingFrameSource, GivesTheInnerSourcesFramesInOrder) {
  const std::string path =
      std::string(RASM_SOURCE_DIR) + "/rawlogs/sim_office_handheld_320x240.rawlog";
  RawlogFrameSource direct(path);
  PrefetchingFrameSource ahead(std::make_unique<RawlogFrameSource>(path), 3);
  EXPECT_EQ(ahead.describe(), direct.describe());
  EXPECT_EQ(ahead.sizeHint(), direct.sizeHint());
  int n = 0;
  for (;; ++n) {
    std::optional<RgbdFrame> a = direct.next(), b = ahead.next();
    ASSERT_EQ(a.has_value(), b.has_value()) << "frame " << n;
    if (!a) break;
    EXPECT_EQ(a->timestamp_s, b->timestamp_s);
    ASSERT_EQ(a->depth_m.width(), b->depth_m.width());
    ASSERT_EQ(a->colour.height(), b->colour.height());
    for (int y = 0; y < a->depth_m.height(); ++y)
      ASSERT_EQ(
          0, std::memcmp(a->depth_m.row(y), b->depth_m.row(y), a->depth_m.width() * sizeof(float)))
          << "frame " << n << " row " << y;
    for (int y = 0; y < a->colour.height(); ++y)
      ASSERT_EQ(0,
                std::memcmp(a->colour.row(y), b->colour.row(y), a->colour.width() * sizeof(Bgr8)))
          << "frame " << n << " row " << y;
    ASSERT_EQ(a->gt_T_world_cam.has_value(), b->gt_T_world_cam.has_value());
    if (a->gt_T_world_cam) {
      EXPECT_TRUE(a->gt_T_world_cam->isApprox(*b->gt_T_world_cam, 0.0));
    }
  }
  EXPECT_GT(n, 10);
  EXPECT_FALSE(ahead.next().has_value());  // stays at the end
}

namespace {
/// What a wrapper of a RawlogFrameSource over writeCutRawlog's file `cut` must give: its two good
/// frames, then the inner error (naming the file and frame 2), then the end.
void expectTwoFramesThenTheCutError(FrameSource& src, const std::string& cut) {
  EXPECT_TRUE(src.next().has_value());
  EXPECT_TRUE(src.next().has_value());
  const std::string msg = errorOf([&] { src.next(); });
  EXPECT_NE(msg.find(cut), std::string::npos) << msg;
  EXPECT_NE(msg.find("frame 2"), std::string::npos) << msg;
  EXPECT_FALSE(src.next().has_value());
}
}  // namespace

TEST(PrefetchingFrameSource, RethrowsTheInnerErrorAfterTheGoodFrames) {
  ScratchDir dir("prefetch_trunc");
  const std::string full = dir / "full.rawlog", cut = dir / "cut.rawlog";
  writeCutRawlog(full, cut);
  PrefetchingFrameSource src(std::make_unique<RawlogFrameSource>(cut), 4);
  expectTwoFramesThenTheCutError(src, cut);
}

TEST(PrefetchingFrameSource, StopsWhenDestroyedMidStream) {
  const std::string path =
      std::string(RASM_SOURCE_DIR) + "/rawlogs/sim_office_handheld_320x240.rawlog";
  for (int depth : {1, 4}) {
    PrefetchingFrameSource src(std::make_unique<RawlogFrameSource>(path), depth);
    ASSERT_TRUE(src.next().has_value());
  }  // the destructor joins the reader, which is blocked on a full queue
}

// ---- PreloadedFrameSource (reads every frame into memory first: benchmarks) ----

#include "rasm/io/PreloadedFrameSource.h"

TEST(PreloadedFrameSource, ReadsEveryFrameFirstThenGivesThemInOrder) {
  const std::string path =
      std::string(RASM_SOURCE_DIR) + "/rawlogs/sim_office_handheld_320x240.rawlog";
  RawlogFrameSource direct(path);
  long long progress = 0;
  PreloadedFrameSource pre(std::make_unique<RawlogFrameSource>(path), 0,
                           [&](long long n) { progress = n; });
  EXPECT_GT(pre.loaded(), 10);
  EXPECT_EQ(progress, pre.loaded());
  EXPECT_EQ(pre.sizeHint(), pre.loaded());
  EXPECT_NE(pre.describe().find(direct.describe()), std::string::npos);
  long long n = 0;
  for (;; ++n) {
    std::optional<RgbdFrame> a = direct.next(), b = pre.next();
    ASSERT_EQ(a.has_value(), b.has_value()) << "frame " << n;
    if (!a) break;
    EXPECT_EQ(a->timestamp_s, b->timestamp_s);
    for (int y = 0; y < a->depth_m.height(); ++y)
      ASSERT_EQ(
          0, std::memcmp(a->depth_m.row(y), b->depth_m.row(y), a->depth_m.width() * sizeof(float)))
          << "frame " << n << " row " << y;
  }
  EXPECT_EQ(n, pre.loaded());
}

TEST(PreloadedFrameSource, StopsAtTheLimitAndRethrowsTheInnerErrorAfterTheGoodFrames) {
  const std::string path =
      std::string(RASM_SOURCE_DIR) + "/rawlogs/sim_office_handheld_320x240.rawlog";
  PreloadedFrameSource first3(std::make_unique<RawlogFrameSource>(path), 3);
  EXPECT_EQ(first3.loaded(), 3);

  ScratchDir dir("preload_trunc");
  const std::string full = dir / "full.rawlog", cut = dir / "cut.rawlog";
  writeCutRawlog(full, cut);
  PreloadedFrameSource src(std::make_unique<RawlogFrameSource>(cut));
  EXPECT_EQ(src.loaded(), 2);  // the error is held, not thrown by the constructor
  expectTwoFramesThenTheCutError(src, cut);
}

TEST(PreloadedFrameSource, StopsWithAClearErrorOverItsMemoryLimit) {
  const std::string path =
      std::string(RASM_SOURCE_DIR) + "/rawlogs/sim_office_handheld_320x240.rawlog";
  // 320x240 frames hold 320 * 240 * (4 + 3) bytes = 525 KiB of depth and colour: 1 MiB is
  // exceeded by the second frame.
  const std::string msg = errorOf([&] {
    PreloadedFrameSource src(std::make_unique<RawlogFrameSource>(path), 0, {},
                             std::size_t(1) << 20);
  });
  EXPECT_NE(msg.find(path), std::string::npos) << msg;
  EXPECT_NE(msg.find("the first 2 frames"), std::string::npos) << msg;
  EXPECT_NE(msg.find("limit of 1 MiB"), std::string::npos) << msg;
  PreloadedFrameSource fits(std::make_unique<RawlogFrameSource>(path), 1, {}, std::size_t(1) << 20);
  EXPECT_EQ(fits.loaded(), 1);
  EXPECT_GE(fits.bytes(), std::size_t(320 * 240 * 7));
}

/// A corrupt string length in a rawlog (found by fuzz_rawlog: TCamera's name) allocated up to
/// 4 GB in MRPT's deserializer; rasm_io bounds archive strings (MrptStringLimit.cpp).
namespace {
/// `obs` serialized as a one-observation rawlog at `path`, with the first occurrence of `field`
/// replaced by `corrupt` (the same length): a size field a corrupt file could hold.
void writeWithCorruptField(const mrpt::obs::CObservation3DRangeScan& obs, const std::string& field,
                           const std::string& corrupt, const std::string& path) {
  mrpt::io::CMemoryStream mem;
  {
    auto a = mrpt::serialization::archiveFrom(mem);
    a << obs;
  }
  std::string bytes(static_cast<const char*>(mem.getRawBufferData()), mem.getTotalBytesCount());
  const auto at = bytes.find(field);
  ASSERT_NE(at, std::string::npos);
  ASSERT_EQ(field.size(), corrupt.size());
  bytes.replace(at, corrupt.size(), corrupt);
  std::ofstream(path, std::ios::binary) << bytes;
}

/// Reading `path` to its end throws an InputError naming the file and containing `reason`.
void expectReadError(const std::string& path, const std::string& reason) {
  try {
    RawlogFrameSource src(path);
    while (src.next()) {
    }
    ADD_FAILURE() << "corrupt " << path << " accepted";
  } catch (const InputError& e) {
    const std::string m = e.what();
    EXPECT_NE(m.find(path), std::string::npos) << m;
    EXPECT_NE(m.find(reason), std::string::npos) << m;
  }
}

std::string u32(std::uint32_t v) {
  return std::string(reinterpret_cast<const char*>(&v), 4);
}
}  // namespace

TEST(RawlogFrameSource, CorruptStringLengthIsAnErrorNotAnAllocation) {
  ScratchDir dir("strlen");
  mrpt::obs::CObservation3DRangeScan obs;
  observationFromFrame(syntheticFrame(0, 8, 6), obs);
  obs.sensorLabel = "LABELXYZ";
  const std::string path = dir / "corrupt.rawlog";
  writeWithCorruptField(obs, u32(8) + "LABELXYZ", u32(2147483647) + "LABELXYZ", path);
  expectReadError(path, "serialized string of 2147483647 bytes");
  // Strings of sane length still read (the same wire format as MRPT's).
  mrpt::io::CMemoryStream ok;
  auto a = mrpt::serialization::archiveFrom(ok);
  a << std::string("hello") << std::string();
  ok.Seek(0);
  std::string h = "x", e = "y";
  a >> h >> e;
  EXPECT_EQ(h, "hello");
  EXPECT_EQ(e, "");
}

/// A corrupt range-image size made MRPT 2.5's CObservation3DRangeScan::serializeFrom allocate
/// rows x cols before reading a pixel (12 PB seen; found by fuzz_rawlog): MrptSizeLimits.cpp
/// bounds it, and valid sizes still read through MRPT's own code.
TEST(RawlogFrameSource, CorruptRangeImageSizeIsAnErrorNotAnAllocation) {
  ScratchDir dir("rangesize");
  mrpt::obs::CObservation3DRangeScan obs;
  observationFromFrame(syntheticFrame(0, 32, 24), obs);
  ASSERT_TRUE(obs.hasRangeImage);
  // serializeFrom v9+: rangeUnits (float), rows, cols, then the pixels.
  std::string units(4, '\0');
  std::memcpy(units.data(), &obs.rangeUnits, 4);
  const std::string path = dir / "corrupt.rawlog";
  writeWithCorruptField(obs, units + u32(24) + u32(32), units + u32(1u << 20) + u32(1u << 20),
                        path);
  expectReadError(path, "range image of 1048576 x 1048576 pixels");
  // Below the limit, a size that does not match the data fails at the end of the stream as before.
  writeWithCorruptField(obs, units + u32(24) + u32(32), units + u32(600) + u32(800), path);
  expectReadError(path, "");
  // The intact observation reads, range image and all.
  writeWithCorruptField(obs, units + u32(24) + u32(32), units + u32(24) + u32(32), path);
  RawlogFrameSource src(path);
  const auto f = src.next();
  ASSERT_TRUE(f.has_value());
  EXPECT_EQ(f->width(), 32);
  EXPECT_EQ(f->height(), 24);
}

/// A version-10 range scan's extra range layers are sized by CMatrixDynamic::resize(rows, cols)
/// from the file before any pixel is read (a 7 EB request, found by fuzz_rawlog in CI; in a
/// release build a null pointer written through). MrptSizeLimits.cpp bounds every allocation
/// through mrpt::aligned_malloc; an intact layer still reads.
TEST(RawlogFrameSource, CorruptRangeLayerSizeIsAnErrorNotAnAllocation) {
  ScratchDir dir("layersize");
  mrpt::obs::CObservation3DRangeScan obs;
  observationFromFrame(syntheticFrame(0, 32, 24), obs);
  mrpt::math::CMatrix_u16 layer(24, 32);
  for (int r = 0; r < 24; ++r)
    for (int c = 0; c < 32; ++c) layer(r, c) = std::uint16_t(100 * r + c);
  obs.rangeImageOtherLayers["second"] = layer;
  // serializeTo v10: the layer's name, then cols and rows (serializeFrom reads rows, then cols).
  const std::string intact = u32(6) + "second" + u32(32) + u32(24);
  const std::string path = dir / "corrupt.rawlog";
  writeWithCorruptField(obs, intact, u32(6) + "second" + u32(1u << 20) + u32(1u << 20), path);
  expectReadError(path, "MRPT allocation of 2199023255552 bytes");
  writeWithCorruptField(obs, intact, intact, path);
  RawlogFrameSource src(path);
  const auto f = src.next();
  ASSERT_TRUE(f.has_value());
  EXPECT_EQ(f->width(), 32);
  // An allocation of a sane size goes through MRPT's own allocator, aligned as asked.
  void* p = mrpt::aligned_malloc(1000, 32);
  ASSERT_NE(p, nullptr);
  EXPECT_EQ(reinterpret_cast<std::uintptr_t>(p) % 32, 0u);
  mrpt::aligned_free(p);
}

/// A corrupt JPEG stored inside a rawlog (MRPT's CImage JPEG serialization) made libjpeg call
/// exit(1) ("Not a JPEG file: starts with 0x00 0x07"): `rasm run` died without a report. Found by
/// fuzz_rawlog; the 489-byte input is tests/io/data/corrupt_jpeg_in_rawlog.rawlog.
TEST(RawlogFrameSource, CorruptEmbeddedJpegIsAnError) {
  // fuzz_rawlog's input is a gzip stream cut short, now refused when opened: its content, as
  // gzread gives it, reaches the JPEG reader as the original input did.
  ScratchDir dir("jpeg");
  const std::string path = dir / "corrupt_jpeg.rawlog";
  {
    gzFile in = gzopen(
        (std::string(RASM_SOURCE_DIR) + "/tests/io/data/corrupt_jpeg_in_rawlog.rawlog").c_str(),
        "rb");
    ASSERT_NE(in, nullptr);
    std::string plain;
    char buf[4096];
    for (int n; (n = gzread(in, buf, sizeof buf)) > 0;) plain.append(buf, std::size_t(n));
    gzclose(in);
    ASSERT_GT(plain.size(), 100u);
    std::ofstream(path, std::ios::binary) << plain;
  }
  try {
    RawlogFrameSource src(path);
    while (src.next()) {
    }
    FAIL() << "corrupt JPEG accepted";
  } catch (const InputError& e) {
    const std::string m = e.what();
    EXPECT_NE(m.find(path), std::string::npos) << m;
    EXPECT_NE(m.find("mrpt::img::CImage"), std::string::npos) << m;  // not exit(1)
  }
}

/// MRPT 2.5's CImage::serializeFrom sized a JPEG buffer from its uint32 byte count and zeroed it
/// before reading (up to 4 GB; found by fuzz_rawlog as a 10 s timeout). rasm's definition of it
/// (MrptSizeLimits.cpp) caps the count and grows the buffer as bytes arrive; the images MRPT
/// writes still read back pixel for pixel (grey raw, colour JPEG, colour raw, empty).
TEST(RawlogFrameSource, CorruptImageByteCountIsAnErrorNotAnAllocation) {
  mrpt::img::CImage colour(8, 6, mrpt::img::CH_RGB);
  for (int y = 0; y < 6; ++y)
    for (int x = 0; x < 8; ++x)
      for (int c = 0; c < 3; ++c) *colour(x, y, c) = std::uint8_t(40 * c + 5 * x + 7 * y);
  const bool raw_colour = mrpt::img::CImage::DISABLE_JPEG_COMPRESSION();  // process-wide
  mrpt::img::CImage::DISABLE_JPEG_COMPRESSION(false);
  auto bytesOf = [](const mrpt::img::CImage& img) {
    mrpt::io::CMemoryStream mem;
    auto a = mrpt::serialization::archiveFrom(mem);
    a << img;
    return std::string(static_cast<const char*>(mem.getRawBufferData()), mem.getTotalBytesCount());
  };
  auto read = [](const std::string& bytes, mrpt::img::CImage& img) {
    mrpt::io::CMemoryStream mem;
    mem.assignMemoryNotOwn(bytes.data(), bytes.size());
    auto a = mrpt::serialization::archiveFrom(mem);
    a >> img;
  };
  std::string bytes = bytesOf(colour);
  // v9 colour: width, height, then the JPEG byte count.
  const auto at = bytes.find(u32(8) + u32(6));
  ASSERT_NE(at, std::string::npos);
  bytes.replace(at + 8, 4, u32(0xF0000000u));
  mrpt::img::CImage img;
  try {
    read(bytes, img);
    FAIL() << "a 4 GB JPEG byte count was accepted";
  } catch (const std::exception& e) {
    EXPECT_NE(std::string(e.what()).find("serialized JPEG image of 4026531840 bytes"),
              std::string::npos)
        << e.what();
  }
  // Intact images read back as MRPT wrote them.
  read(bytesOf(colour), img);
  ASSERT_EQ(img.getWidth(), 8u);
  ASSERT_EQ(img.getHeight(), 6u);
  EXPECT_TRUE(img.isColor());
  for (int c = 0; c < 3; ++c)
    EXPECT_NEAR(*img(3, 2, c), *colour(3, 2, c), 12) << c;  // JPEG, BGR kept
  mrpt::img::CImage grey(5, 4, mrpt::img::CH_GRAY);
  for (int y = 0; y < 4; ++y)
    for (int x = 0; x < 5; ++x) *grey(x, y) = std::uint8_t(11 * x + 3 * y);
  read(bytesOf(grey), img);
  ASSERT_EQ(img.getWidth(), 5u);
  EXPECT_FALSE(img.isColor());
  for (int y = 0; y < 4; ++y)
    for (int x = 0; x < 5; ++x) EXPECT_EQ(*img(x, y), *grey(x, y));
  mrpt::img::CImage::DISABLE_JPEG_COMPRESSION(true);  // v8 raw colour
  const std::string raw = bytesOf(colour);
  mrpt::img::CImage::DISABLE_JPEG_COMPRESSION(raw_colour);
  read(raw, img);
  for (int c = 0; c < 3; ++c) EXPECT_EQ(*img(7, 5, c), *colour(7, 5, c));
  read(bytesOf(mrpt::img::CImage()), img);
  EXPECT_TRUE(img.isEmpty());
}

/// MRPT reads a bool as its byte, so a corrupt rawlog can leave 30 in hasIntensityImage (found by
/// fuzz_rawlog under UBSan: loading it is undefined behaviour); the frame conversion reads each
/// flag as a byte and names the bad one.
TEST(RawlogFrameSource, CorruptObservationFlagIsNamed) {
  mrpt::obs::CObservation3DRangeScan obs;
  observationFromFrame(syntheticFrame(0), obs);
  const unsigned char corrupt = 30;
  std::memcpy(static_cast<void*>(&obs.hasIntensityImage), &corrupt, 1);
  try {
    frameFromObservation(obs, "test entry 7");
    FAIL() << "a flag byte of 30 was accepted";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("test entry 7"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("flag hasIntensityImage holds the byte 30"),
              std::string::npos)
        << e.what();
  }
  const unsigned char one = 1;
  std::memcpy(static_cast<void*>(&obs.hasIntensityImage), &one, 1);
  EXPECT_EQ(frameFromObservation(obs, "test entry 7").colour.width(), 32);
}

/// A NaN in the colour camera's pose reached the registration's float-to-int pixel conversion
/// (found by fuzz_rawlog under UBSan); a NaN ground-truth pose would have reached the ATE. Both
/// are named now.
TEST(RawlogFrameSource, NonFinitePosesInAnObservationAreNamed) {
  mrpt::obs::CObservation3DRangeScan obs;
  observationFromFrame(syntheticFrame(0), obs);
  obs.relativePoseIntensityWRTDepth = mrpt::poses::CPose3D(0.02, std::nan(""), 0, 0, 0, 0);
  try {
    frameFromObservation(obs, "entry 3");
    FAIL() << "a NaN colour camera pose was accepted";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("relativePoseIntensityWRTDepth) is not finite"),
              std::string::npos)
        << e.what();
  }
  observationFromFrame(syntheticFrame(0), obs);
  obs.sensorPose = mrpt::poses::CPose3D(1, 2, std::numeric_limits<double>::infinity(), 0, 0, 0);
  ObservationToFrameOptions opt;
  opt.sensor_pose_is_ground_truth = true;
  try {
    frameFromObservation(obs, "entry 4", opt);
    FAIL() << "an infinite ground-truth pose was accepted";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("ground-truth pose (sensorPose) is not finite"),
              std::string::npos)
        << e.what();
  }
}

/// The inputs fuzz_rawlog found (tests/io/data/fuzz_rawlog/, the findings of docs/io.md "Bad input
/// and fuzzing", the selector byte removed): each is an InputError naming the file, quickly, with
/// no crash, huge allocation or undefined behaviour (scripts/asan.sh runs this under ASan + UBSan).
TEST(RawlogFrameSource, FuzzFindingsAreClearErrors) {
  const fs::path dir = fs::path(RASM_SOURCE_DIR) / "tests/io/data/fuzz_rawlog";
  int n = 0;
  for (const auto& e : fs::directory_iterator(dir)) {
    ++n;
    expectReadError(e.path().string(), "");
  }
  EXPECT_EQ(n, 7) << "the committed findings";
}
