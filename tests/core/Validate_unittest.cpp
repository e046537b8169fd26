// One check per kind of number read from outside (rasm/core/Validate.h), and the focal-length
// bound of CameraIntrinsics: 1e30 px gave a 0-surfel map with status ok (issue 40).
#include "rasm/core/Validate.h"

#include <gtest/gtest.h>

#include <limits>

#include "rasm/core/CameraIntrinsics.h"

using namespace rasm;

TEST(Validate, RangeProblemSaysNonFiniteOrOutOfRange) {
  EXPECT_EQ(rangeProblem(3.0, 0, 10), "");
  EXPECT_EQ(rangeProblem(std::numeric_limits<double>::quiet_NaN(), 0, 10),
            "value nan is not a finite number");
  EXPECT_EQ(rangeProblem(std::numeric_limits<double>::infinity(), 0, 10),
            "value inf is not a finite number");
  EXPECT_EQ(rangeProblem(1e30, -1e4, 1e4), "value 1e+30 out of range, expected [-10000, 10000]");
}

TEST(Validate, CoordinatesAndAnglesThrowNamingTheValue) {
  EXPECT_NO_THROW(requireCoordinate(9999.0, "--eye"));
  try {
    requireCoordinate(1e30, "--eye 3,2,1e30");
    FAIL() << "no error";
  } catch (const InputError& e) {
    EXPECT_EQ(std::string(e.what()),
              "--eye 3,2,1e30: value 1e+30 out of range, expected [-10000, "
              "10000]");
  }
  EXPECT_THROW(requireAngleDeg(std::numeric_limits<double>::infinity(), "--yaw inf"), InputError);
  EXPECT_NO_THROW(requireAngleDeg(-720.0, "--yaw -720"));
}

TEST(Validate, AbsurdFocalLengthIsAnIntrinsicsProblem) {
  EXPECT_NE(CameraIntrinsics(1e30, 525, 319.5, 239.5, 640, 480)
                .problem()
                .find("fx = 1e+30: expected a finite focal length in (0, 100000] (pixels)"),
            std::string::npos);
  EXPECT_NE(CameraIntrinsics(525, 2e5, 319.5, 239.5, 640, 480).problem().find("fy = 200000"),
            std::string::npos);
  EXPECT_EQ(CameraIntrinsics(1e5, 1e5, 319.5, 239.5, 640, 480).problem(), "");
}
