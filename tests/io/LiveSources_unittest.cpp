// Live and real-time sources: the OpenNI2 source without a camera fails clearly and quickly; the
// real-time wrapper drops frames a slow consumer cannot take instead of queueing them.
#include <gtest/gtest.h>
#include <mrpt/config/CConfigFileMemory.h>

#include <chrono>
#include <thread>

#include "IoTestUtils.h"
#include "rasm/core/Error.h"
#include "rasm/io/OpenNI2FrameSource.h"
#include "rasm/io/RawlogFrameSource.h"
#include "rasm/io/RawlogWriter.h"
#include "rasm/io/RealTimeFrameSource.h"

using namespace rasm;
using namespace rasm::io;

namespace {
double secondsSince(std::chrono::steady_clock::time_point t) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t).count();
}
/// `n` synthetic frames at 30 Hz in a rawlog.
void writeRawlog(const std::string& path, int n) {
  RawlogWriter w(path);
  for (int i = 0; i < n; ++i) w.write(test::syntheticFrame(i));
  w.close();
}
}  // namespace

TEST(OpenNI2FrameSource, WithoutADeviceFailsNamingIt) {
  if (OpenNI2FrameSource::connectedDevices() > 0)
    GTEST_SKIP() << "an OpenNI2 camera is connected to this machine";
  TOpenNI2Params p;
  p.device_index = 0;
  OpenNI2FrameSource source(p);  // does not open: `rasm config` works without a camera
  EXPECT_NE(source.describe().find("openni2 device 0 (640x480 @ 30 Hz"), std::string::npos)
      << source.describe();
  const auto t0 = std::chrono::steady_clock::now();
  try {
    source.next();
    FAIL() << "a frame without a camera";
  } catch (const InputError& e) {
    const std::string msg = e.what();
    EXPECT_NE(msg.find("[openni2] device_index = 0: no OpenNI2 device is connected"),
              std::string::npos)
        << msg;
    EXPECT_NE(msg.find("expected an OpenNI2 RGB-D camera"), std::string::npos) << msg;
  }
  EXPECT_LT(secondsSince(t0), 5.0);
  // Asked by serial number: the message names the serial.
  p.device_serial = 1234;
  OpenNI2FrameSource by_serial(p);
  try {
    by_serial.next();
    FAIL();
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("[openni2] device_serial = 1234"), std::string::npos)
        << e.what();
  }
}

TEST(OpenNI2FrameSource, ParamsAreValidatedByName) {
  auto load = [](const std::string& key, const std::string& value) {
    mrpt::config::CConfigFileMemory ini;
    ini.write("openni2", key, value);
    TOpenNI2Params p;
    p.loadFromConfigFile(ini, "openni2");
  };
  EXPECT_NO_THROW(load("registration", "software"));
  try {
    load("registration", "magic");
    FAIL();
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("[openni2] registration"), std::string::npos);
  }
  try {
    load("width", "800");
    FAIL();
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("800 x 480 is not a resolution"), std::string::npos)
        << e.what();
  }
}

TEST(RealTimeFrameSource, ASlowConsumerGetsTheNewestFramesAndDropsTheRest) {
  test::ScratchDir dir("rt");
  const int n = 45;  // 1.5 s at 30 Hz
  writeRawlog(dir / "seq.rawlog", n);
  RealTimeFrameSource rt(std::make_unique<RawlogFrameSource>(dir / "seq.rawlog"), true);
  const auto t0 = std::chrono::steady_clock::now();
  std::vector<std::size_t> got;
  while (auto f = rt.next()) {
    got.push_back(f->index);
    std::this_thread::sleep_for(std::chrono::milliseconds(100));  // a mapper at 10 Hz
  }
  const double wall = secondsSince(t0);
  const RealTimeStats s = rt.stats();
  EXPECT_EQ(s.offered, n);
  EXPECT_EQ(s.delivered, (long long)got.size());
  EXPECT_EQ(s.delivered + s.dropped, s.offered);
  // About one frame in three is taken (10 Hz of 30 Hz): bounded by the consumer, not queued.
  EXPECT_GE(s.dropped, n / 2) << "delivered " << s.delivered;
  EXPECT_LE(s.delivered, n / 2);
  EXPECT_EQ(s.dropped_indices.size(), std::size_t(s.dropped));
  // Frames come in order, each newer than the last, the last one included.
  for (std::size_t i = 1; i < got.size(); ++i) EXPECT_GT(got[i], got[i - 1]);
  EXPECT_EQ(got.back(), std::size_t(n - 1));
  // Offered at their timestamps: 44 intervals of 1/30 s.
  EXPECT_NEAR(s.offered_span_s, 44.0 * 0.033333, 0.25);
  EXPECT_LT(wall, 1.5 + 0.5);
}

TEST(RealTimeFrameSource, AConsumerFasterThanTheCameraGetsEveryFrame) {
  test::ScratchDir dir("rt_fast");
  writeRawlog(dir / "seq.rawlog", 15);
  RealTimeFrameSource rt(std::make_unique<RawlogFrameSource>(dir / "seq.rawlog"), true);
  std::size_t got = 0;
  while (rt.next()) ++got;
  EXPECT_EQ(got, 15u);
  EXPECT_EQ(rt.stats().dropped, 0);
}
