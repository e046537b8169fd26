#include "rasm/autonomy/RobotFrameSource.h"

namespace rasm::autonomy {

RobotFrameSource::RobotFrameSource(std::unique_ptr<io::FrameSource> inner,
                                   std::unique_ptr<robot::SegwayRmpRobot> robot)
    : m_inner(std::move(inner)), m_robot(std::move(robot)) {}

RobotFrameSource::~RobotFrameSource() {
  m_inner.reset();  // the camera first; then the robot stops (zero velocity, standby)
  m_robot.reset();
}

std::optional<RgbdFrame> RobotFrameSource::next() {
  std::optional<RgbdFrame> f = m_inner->next();
  if (f) f->odometry_xyyaw = m_robot->odometryAt(f->timestamp_s);
  return f;
}

std::string RobotFrameSource::describe() const {
  return m_inner->describe() + " on " + m_robot->describe();
}

}  // namespace rasm::autonomy
