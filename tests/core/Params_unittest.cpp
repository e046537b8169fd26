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
  // resized: halving the size is a pyramid level; a quarter keeps the field of view (the image
  // border's ray: (0 - 0.5 - cx) / fx is the same at every size).
  const CameraIntrinsics r = k.resized(320, 240);
  EXPECT_NEAR(r.fx, l1.fx, 1e-12);
  EXPECT_NEAR(r.cx, l1.cx, 1e-12);
  EXPECT_NEAR(r.cy, l1.cy, 1e-12);
  const CameraIntrinsics q = k.resized(160, 120);
  EXPECT_EQ(q.width, 160);
  EXPECT_NEAR((-0.5 - q.cx) / q.fx, (-0.5 - k.cx) / k.fx, 1e-12);
  EXPECT_NEAR((q.height - 0.5 - q.cy) / q.fy, (k.height - 0.5 - k.cy) / k.fy, 1e-12);
}

namespace {
std::string loadError(const mrpt::config::CConfigFileBase& cfg, const std::string& source) {
  TDemoParams p;
  try {
    loadParamsStrict(cfg, "demo", p, source);
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}
}  // namespace

/// Values are checked as text before MRPT's atoi/atof read them: "three" was reported as
/// "value 0 out of range", 99999999999999999999 as "value -1".
TEST(Params, ValueTextIsCheckedBeforeRanges) {
  const auto err = [](const std::string& ini) {
    return loadError(mrpt::config::CConfigFileMemory(ini), "test.ini");
  };
  std::string e = err("[demo]\nlevels = three\n");
  EXPECT_NE(e.find("'three' is not an integer"), std::string::npos) << e;
  EXPECT_NE(e.find("[demo] levels"), std::string::npos) << e;
  EXPECT_EQ(e.find("value 0"), std::string::npos) << e;
  e = err("[demo]\nlevels = 99999999999999999999\n");
  EXPECT_NE(e.find("too large"), std::string::npos) << e;
  EXPECT_EQ(e.find("-1"), std::string::npos) << e;
  e = err("[demo]\nlevels = 3000000000\n");
  EXPECT_NE(e.find("too large"), std::string::npos) << e;
  for (const char* v : {"nan", "inf", "-inf", "1e999"}) {
    e = err(std::string("[demo]\nsigma = ") + v + "\n");
    EXPECT_NE(e.find("is not a finite number"), std::string::npos) << v << ": " << e;
    EXPECT_NE(e.find("sigma"), std::string::npos) << e;
  }
  e = err("[demo]\nsigma = three\n");
  EXPECT_NE(e.find("'three' is not a number"), std::string::npos) << e;
  EXPECT_EQ(err("[demo]\nsigma = 1e-1\nlevels = 7\n"), "");
}

/// A ConfigWithOrigins names where a bad key came from: file:line or the command line.
TEST(Params, ErrorsBlameTheKeysOrigin) {
  ConfigWithOrigins cfg(std::string("[demo]\nsigma = 20\nlevels = x\nbogus = 1\n"));
  cfg.setOrigin("demo", "sigma", "my.ini:2");
  cfg.setOrigin("demo", "levels", "command line (demo.levels=x)");
  cfg.setOrigin("demo", "bogus", "command line (demo.bogus=1)");
  std::string e = loadError(cfg, "my.ini");
  EXPECT_NE(e.find("command line (demo.bogus=1) [demo] bogus: unknown key"), std::string::npos)
      << e;
  ConfigWithOrigins two(std::string("[demo]\nsigma = 20\nlevels = x\n"));
  two.setOrigin("demo", "sigma", "my.ini:2");
  two.setOrigin("demo", "levels", "command line (demo.levels=x)");
  e = loadError(two, "my.ini");
  EXPECT_NE(e.find("command line (demo.levels=x) [demo] levels: 'x' is not an integer"),
            std::string::npos)
      << e;
  ConfigWithOrigins range(std::string("[demo]\nsigma = 20\n"));
  range.setOrigin("demo", "sigma", "my.ini:2");
  e = loadError(range, "my.ini");
  EXPECT_NE(e.find("my.ini:2"), std::string::npos) << e;
  EXPECT_NE(e.find("out of range"), std::string::npos) << e;
}

TEST(CameraIntrinsics, ProblemNamesTheBadValue) {
  EXPECT_EQ(CameraIntrinsics(525, 525, 319.5, 239.5, 640, 480).problem(), "");
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const double inf = std::numeric_limits<double>::infinity();
  EXPECT_NE(CameraIntrinsics(nan, 525, 319.5, 239.5, 640, 480).problem().find("fx = nan"),
            std::string::npos);
  EXPECT_NE(CameraIntrinsics(525, inf, 319.5, 239.5, 640, 480).problem().find("fy = inf"),
            std::string::npos);
  EXPECT_NE(CameraIntrinsics(-517, 525, 319.5, 239.5, 640, 480).problem().find("fx = -517"),
            std::string::npos);
  EXPECT_NE(CameraIntrinsics(525, 525, 900, 239.5, 640, 480).problem().find("cx = 900"),
            std::string::npos);
  EXPECT_NE(CameraIntrinsics(525, 525, 319.5, nan, 640, 480).problem().find("cy = nan"),
            std::string::npos);
  EXPECT_FALSE(CameraIntrinsics(525, 525, 319.5, 239.5, 0, 480).valid());
  RgbdFrame f;
  f.intrinsics = CameraIntrinsics(100, 100, 40.0, 11.5, 32, 24);
  f.depth_m = Image<float>(32, 24, 1.0f);
  try {
    f.validate("seq.rawlog frame 3");
    FAIL();
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("cx = 40"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("seq.rawlog frame 3"), std::string::npos) << e.what();
  }
}

#include "rasm/core/ComputeOptions.h"

// [compute] simd_off (issue 13, 5): a list of path names switches exactly those paths to their
// kernel bodies; an unknown name fails at loading and the error names it and the known ones.
TEST(ComputeParams, SimdOffSwitchesExactlyTheNamedPaths) {
  mrpt::config::CConfigFileMemory cfg(
      std::string("[compute]\nsimd = true\nsimd_off = fusion , splat\n"));
  TComputeParams p;
  loadParamsStrict(cfg, "compute", p, "test.ini");
  p.apply();
  for (compute::SimdPath path : compute::simdPaths()) {
    const std::string name = compute::simdPathName(path);
    const bool off = name == "fusion" || name == "splat";
    EXPECT_EQ(compute::simdEnabled(path), !off) << name;
  }
  TComputeParams all;  // defaults: everything back on
  all.apply();
  for (compute::SimdPath path : compute::simdPaths()) EXPECT_TRUE(compute::simdEnabled(path));

  TComputeParams none;
  none.simd = false;
  none.apply();
  for (compute::SimdPath path : compute::simdPaths()) EXPECT_FALSE(compute::simdEnabled(path));
  compute::setSimdEnabled(true);
  EXPECT_EQ(compute::simdPaths().size(), std::size_t(compute::SimdPath::kCount));
}

TEST(ComputeParams, UnknownSimdOffPathIsNamed) {
  mrpt::config::CConfigFileMemory cfg(std::string("[compute]\nsimd_off = fusion,splatt\n"));
  TComputeParams p;
  try {
    loadParamsStrict(cfg, "compute", p, "test.ini");
    FAIL() << "unknown path accepted";
  } catch (const InputError& e) {
    const std::string msg = e.what();
    EXPECT_NE(msg.find("simd_off"), std::string::npos) << msg;
    EXPECT_NE(msg.find("'splatt'"), std::string::npos) << msg;
    EXPECT_NE(msg.find("bilateral_filter"), std::string::npos)
        << msg;  // the known names are listed
  }
  // A deleted SSE path (docs/slam-eval.md "SSE paths") is no longer a name.
  mrpt::config::CConfigFileMemory gone(std::string("[compute]\nsimd_off = culling\n"));
  EXPECT_THROW(loadParamsStrict(gone, "compute", p, "test.ini"), InputError);
}

TEST(Params, SplitListTrimsAndSkipsEmptyItems) {
  EXPECT_EQ(splitList(" a, b ,\tc,,  ,d"), (std::vector<std::string>{"a", "b", "c", "d"}));
  EXPECT_TRUE(splitList("").empty());
  EXPECT_TRUE(splitList(" , ").empty());
  EXPECT_EQ(splitList("one word"), std::vector<std::string>{"one word"});
}
