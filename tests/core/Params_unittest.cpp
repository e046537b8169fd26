#include <gtest/gtest.h>
#include <mrpt/config/CConfigFileMemory.h>

#include <mrpt/img/TCamera.h>
#include <limits>
#include "rasm/core/CameraIntrinsics.h"
#include "rasm/core/Error.h"
#include "rasm/core/Params.h"
#include "rasm/core/RgbdFrame.h"

using namespace rasm;

namespace {
struct TDemoParams : mrpt::config::CLoadableOptions {
  double sigma = 0.6;
  int levels = 3;
  void loadFromConfigFile(const mrpt::config::CConfigFileBase& c, const std::string& s) override {
    MRPT_LOAD_CONFIG_VAR(sigma, double, c, s);
    MRPT_LOAD_CONFIG_VAR(levels, int, c, s);
    requireInRange(sigma, 1e-6, 10.0, s, "sigma");
  }
  void saveToConfigFile(mrpt::config::CConfigFileBase& c, const std::string& s) const override {
    MRPT_SAVE_CONFIG_VAR(sigma, c, s);
    MRPT_SAVE_CONFIG_VAR(levels, c, s);
  }
};
}  // namespace

TEST(Params, LoadsKnownKeysAndRejectsUnknown) {
  mrpt::config::CConfigFileMemory cfg(std::string("[demo]\nsigma = 0.5\nlevels = 2\n"));
  TDemoParams p;
  loadParamsStrict(cfg, "demo", p, "test.ini");
  EXPECT_DOUBLE_EQ(p.sigma, 0.5);
  EXPECT_EQ(p.levels, 2);

  mrpt::config::CConfigFileMemory bad(std::string("[demo]\nsigmaa = 0.5\n"));
  try {
    loadParamsStrict(bad, "demo", p, "test.ini");
    FAIL() << "unknown key accepted";
  } catch (const InputError& e) {
    const std::string msg = e.what();
    EXPECT_NE(msg.find("test.ini"), std::string::npos) << msg;
    EXPECT_NE(msg.find("sigmaa"), std::string::npos) << msg;
    EXPECT_NE(msg.find("[demo]"), std::string::npos) << msg;
  }
  mrpt::config::CConfigFileMemory garbage(std::string("[demo]\nlevels = 3x\n"));
  try {
    loadParamsStrict(garbage, "demo", p, "test.ini");
    FAIL() << "'3x' accepted as an int";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("levels"), std::string::npos) << e.what();
  }
  mrpt::config::CConfigFileMemory fine(std::string("[demo]\nsigma = 0.60\nlevels = 4\n"));
  EXPECT_NO_THROW(loadParamsStrict(fine, "demo", p, "test.ini"));
  mrpt::config::CConfigFileMemory range(std::string("[demo]\nsigma = -1\n"));
  EXPECT_THROW(loadParamsStrict(range, "demo", p, "test.ini"), InputError);
}

TEST(RgbdFrame, ValidateNamesProblem) {
  RgbdFrame f;
  f.intrinsics = CameraIntrinsics(100, 100, 15.5, 11.5, 32, 24);
  f.depth_m = Image<float>(32, 24, 1.0f);
  EXPECT_NO_THROW(f.validate("frame 0"));
  f.depth_m(3, 4) = std::numeric_limits<float>::quiet_NaN();
  try {
    f.validate("seq.rawlog frame 7");
    FAIL();
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("seq.rawlog frame 7"), std::string::npos);
    EXPECT_NE(std::string(e.what()).find("(3,4)"), std::string::npos);
  }
  f.depth_m = Image<float>(30, 24, 1.0f);
  EXPECT_THROW(f.validate("x"), InputError);
  f.depth_m = Image<float>(32, 24, 1.0f);
  f.colour = Image<Bgr8>(16, 12);
  EXPECT_THROW(f.validate("x"), InputError);
}

TEST(CameraIntrinsics, TCameraRoundTripAndPresets) {
  const CameraIntrinsics k = CameraIntrinsics::preset("tum_fr1");
  mrpt::img::TCamera c;
  k.toTCamera(c);
  EXPECT_EQ(CameraIntrinsics::fromTCamera(c), k);
  EXPECT_THROW(CameraIntrinsics::preset("nope"), InputError);
  const CameraIntrinsics l1 = k.level(1);
  EXPECT_EQ(l1.width, 320);
  EXPECT_NEAR(l1.cx, (318.6 + 0.5) / 2 - 0.5, 1e-12);
}
