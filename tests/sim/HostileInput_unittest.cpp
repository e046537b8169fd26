// Hostile numbers in worlds, trajectory specs and camera poses: `.nan`, `.inf`, 1e30 and keys
// given twice are errors naming the file, the line and the key; a non-finite or far-away camera
// pose is an InputError before any ray is cast (it used to abort inside the ray tracer).
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <string>

#include "rasm/core/Error.h"
#include "rasm/sim/CameraPoses.h"
#include "rasm/sim/RayScene.h"
#include "rasm/sim/RgbdSensor.h"
#include "rasm/sim/Trajectory.h"
#include "rasm/sim/World.h"

using namespace rasm::sim;

namespace {

std::string worldError(const std::string& yaml) {
  try {
    loadWorldFromString(yaml, "hostile_world.yaml");
  } catch (const rasm::InputError& e) {
    return e.what();
  }
  return "";
}

std::string specError(const std::string& yaml) {
  try {
    loadTrajectorySpecFromString(yaml, "hostile_spec.yaml");
  } catch (const rasm::InputError& e) {
    return e.what();
  }
  return "";
}

/// One cup; `field` replaces its position.
std::string cupWorld(const std::string& field) {
  return "objects:\n"
         "  - id: 1\n"
         "    class: cup\n"
         "    primitive: box\n"
         "    size: [1, 1, 1]\n"
         "    " +
         field + "\n";
}

bool has(const std::string& text, const std::string& part) {
  return text.find(part) != std::string::npos;
}

}  // namespace

TEST(HostileWorld, NanAndInfPositionsNameFileLineAndKey) {
  for (const char* bad : {".nan", ".inf", "-.inf", "1e30"}) {
    const std::string e = worldError(cupWorld(std::string("position: [0, ") + bad + ", 0]"));
    EXPECT_TRUE(has(e, "hostile_world.yaml:6")) << bad << ": " << e;
    EXPECT_TRUE(has(e, "objects[0].position[1]")) << bad << ": " << e;
    EXPECT_TRUE(has(e, bad)) << bad << ": " << e;
  }
  // 1e30 was accepted as a position; a far but sane one still loads.
  EXPECT_EQ(worldError(cupWorld("position: [0, 9000, 0]")), "");
}

TEST(HostileWorld, AbsurdSizesAreRefused) {
  std::string e = worldError(
      "objects:\n  - {id: 1, class: cup, primitive: box, size: [1e30, 1, 1], position: [0, 0, "
      "0]}\n");
  EXPECT_TRUE(has(e, "objects[0].size[0]")) << e;
  EXPECT_TRUE(has(e, "hostile_world.yaml:2")) << e;
  e = worldError(
      "objects:\n  - {id: 1, class: cup, primitive: box, size: [1, .nan, 1], position: [0, 0, "
      "0]}\n");
  EXPECT_TRUE(has(e, "objects[0].size[1]")) << e;
  EXPECT_TRUE(has(e, "not a finite number")) << e;
  e = worldError(
      "objects:\n  - {id: 1, class: cup, primitive: sphere, radius: .inf, position: [0, 0, 0]}\n");
  EXPECT_TRUE(has(e, "objects[0].radius")) << e;
  e = worldError(
      "objects:\n  - {id: 1, class: cup, primitive: box, size: [1, 1, 1], position: [0, 0, 0], "
      "yaw_deg: .nan}\n");
  EXPECT_TRUE(has(e, "objects[0].yaw_deg")) << e;
  e = worldError(
      "light: {direction: [.nan, 0, -1]}\nobjects:\n  - {id: 1, class: cup, primitive: box, size: "
      "[1, 1, 1], position: [0, 0, 0]}\n");
  EXPECT_TRUE(has(e, "light.direction[0]")) << e;
}

TEST(HostileWorld, RepeatedKeyNamesBothLines) {
  const std::string e = worldError(
      "objects:\n"
      "  - id: 1\n"
      "    class: cup\n"
      "    primitive: box\n"
      "    size: [1, 1, 1]\n"
      "    position: [0, 0, 0]\n"
      "    position: [5, 0, 0]\n");
  EXPECT_TRUE(has(e, "hostile_world.yaml:7")) << e;
  EXPECT_TRUE(has(e, "objects[0].position")) << e;
  EXPECT_TRUE(has(e, "given twice (first at line 6)")) << e;
  const std::string top = worldError(
      "world: a\nworld: b\nobjects:\n  - {id: 1, class: cup, primitive: box, size: [1, 1, 1], "
      "position: [0, 0, 0]}\n");
  EXPECT_TRUE(has(top, "hostile_world.yaml:2")) << top;
  EXPECT_TRUE(has(top, "key 'world' given twice")) << top;
}

TEST(HostileTrajectory, NanAndInfPosesNameFileLineAndKey) {
  std::string e = specError(
      "type: handheld\nkeyframes:\n"
      "  - {t: 0, position: [0, 0, 1], look_at: [1, 0, 1]}\n"
      "  - {t: 1, position: [.nan, 2, 1.5], look_at: [1, 0, 1]}\n");
  EXPECT_TRUE(has(e, "hostile_spec.yaml:4")) << e;
  EXPECT_TRUE(has(e, "keyframes[1].position[0]")) << e;
  EXPECT_TRUE(has(e, "not a finite number")) << e;
  e = specError(
      "type: handheld\nkeyframes:\n"
      "  - {t: 0, position: [0, 0, 1], look_at: [.inf, 1, 1]}\n"
      "  - {t: 1, position: [0, 0, 1], look_at: [1, 0, 1]}\n");
  EXPECT_TRUE(has(e, "hostile_spec.yaml:3")) << e;
  EXPECT_TRUE(has(e, "keyframes[0].look_at[0]")) << e;
  e = specError(
      "type: handheld\nkeyframes:\n"
      "  - {t: 0, position: [0, 0, 1e30], look_at: [1, 0, 1]}\n"
      "  - {t: 1, position: [0, 0, 1], look_at: [1, 0, 1]}\n");
  EXPECT_TRUE(has(e, "keyframes[0].position[2]")) << e;
  EXPECT_TRUE(has(e, "out of range")) << e;
  e = specError(
      "type: handheld\nkeyframes:\n"
      "  - {t: 0, position: [0, 0, 1], yaw_deg: .inf}\n"
      "  - {t: 1, position: [0, 0, 1], yaw_deg: 0}\n");
  EXPECT_TRUE(has(e, "keyframes[0].yaw_deg")) << e;
  e = specError("type: robot\nstart: {x: .nan, y: 0}\nwaypoints: [[1, 2]]\n");
  EXPECT_TRUE(has(e, "start.x")) << e;
  e = specError("type: robot\nstart: {x: 0, y: 0}\nwaypoints: [[1, 2], [1e30, 0]]\n");
  EXPECT_TRUE(has(e, "waypoints[1][0]")) << e;
}

TEST(HostileTrajectory, RepeatedKeyIsAnError) {
  const std::string e = specError(
      "type: handheld\nrate_hz: 30\nrate_hz: 5\nkeyframes:\n"
      "  - {t: 0, position: [0, 0, 1], look_at: [1, 0, 1]}\n"
      "  - {t: 1, position: [0, 0, 1], look_at: [1, 0, 1]}\n");
  EXPECT_TRUE(has(e, "hostile_spec.yaml:3")) << e;
  EXPECT_TRUE(has(e, "key 'rate_hz' given twice (first at line 2)")) << e;
}

TEST(HostileCameraPose, RenderRefusesNonFiniteAndFarPoses) {
  const RayScene scene(loadWorldFromString(
      "objects:\n  - {id: 1, class: wall, primitive: box, size: [0.2, 6, 6], position: [2, 0, "
      "0]}\n",
      "t"));
  TSensorParams p;
  p.camera = "kinect_v1";
  const RgbdSensor sensor(scene, p);
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const double inf = std::numeric_limits<double>::infinity();
  for (const Eigen::Isometry3d& T :
       {cameraPoseFromHeading({0, 0, 0}, inf, 0.0), cameraPoseFromHeading({nan, 0, 0}, 0.0, 0.0),
        cameraPoseFromHeading({3, 2, 1e30}, 0.0, 0.0)}) {
    try {
      (void)sensor.render(T, 0, 7);
      ADD_FAILURE() << "no error for pose\n" << T.matrix();
    } catch (const rasm::InputError& e) {
      EXPECT_TRUE(has(e.what(), "frame 7 camera pose")) << e.what();
    }
  }
}
