#pragma once
// The frames of a camera on a real robot ([robot] type = segway_rmp): each frame of the inner
// (live) source gets the robot's wheel odometry at its timestamp (SegwayRmpRobot::odometryAt,
// both on this computer's clock) in RgbdFrame::odometry_xyyaw, which the tracking stage turns
// into the motion prior exactly as it does with the simulated robot's odometry (OdometryPrior).
// The robot is connected in the constructor (InputError naming it when it does not answer) and
// stopped when this source is destroyed.

#include <memory>

#include "rasm/io/FrameSource.h"
#include "rasm/robot/SegwayRmpRobot.h"

namespace rasm::autonomy {

class RobotFrameSource : public io::FrameSource {
 public:
  RobotFrameSource(std::unique_ptr<io::FrameSource> inner,
                   std::unique_ptr<robot::SegwayRmpRobot> robot);
  ~RobotFrameSource() override;

  std::optional<RgbdFrame> next() override;
  long long sizeHint() const override { return m_inner->sizeHint(); }
  std::string describe() const override;
  robot::SegwayRmpRobot& robot() { return *m_robot; }
  const robot::SegwayRmpRobot& robot() const { return *m_robot; }

 private:
  std::unique_ptr<io::FrameSource> m_inner;
  std::unique_ptr<robot::SegwayRmpRobot> m_robot;
};

}  // namespace rasm::autonomy
