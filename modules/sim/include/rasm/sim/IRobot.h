#pragma once
// The robot interface moved to modules/robot (rasm::robot::IRobot), where the real robots
// (SegwayRmpRobot) implement it too; the simulator's code keeps its name for it.

#include "rasm/robot/IRobot.h"

namespace rasm::sim {
using IRobot = robot::IRobot;
}  // namespace rasm::sim
