// The Segway RMP packets: CRC, command encoding byte for byte, feedback layout and parsing.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>

#include "rasm/robot/RmpProtocol.h"

using namespace rasm::robot;

TEST(RmpProtocol, Crc16IsArcCheckValue) {
  // CRC-16/ARC (reflected 0xA001, initial 0): the catalogue's check value of "123456789".
  const char* s = "123456789";
  EXPECT_EQ(rmp::crc16(reinterpret_cast<const std::uint8_t*>(s), std::strlen(s)), 0xBB3D);
  EXPECT_EQ(rmp::crc16(nullptr, 0), 0);
}

TEST(RmpProtocol, MotionCommandBytes) {
  const rmp::CommandPacket p = rmp::encodeMotion(0.5f, -0.25f);
  // id 0x0500, 0.5f = 0x3F000000, -0.25f = 0xBE800000, big-endian.
  const std::uint8_t head[10] = {0x05, 0x00, 0x3F, 0x00, 0x00, 0x00, 0xBE, 0x80, 0x00, 0x00};
  EXPECT_EQ(std::memcmp(p.data(), head, 10), 0);
  const std::uint16_t crc = rmp::crc16(p.data(), 10);
  EXPECT_EQ(p[10], crc >> 8);
  EXPECT_EQ(p[11], crc & 0xFF);
  rmp::DecodedCommand c;
  ASSERT_TRUE(rmp::decodeCommand(p.data(), p.size(), c));
  EXPECT_EQ(c.id, rmp::kMotionCommandId);
  EXPECT_EQ(c.float1(), 0.5f);
  EXPECT_EQ(c.float2(), -0.25f);
  // Out of range and non-finite values are clamped / zeroed, never sent.
  ASSERT_TRUE(rmp::decodeCommand(rmp::encodeMotion(3.0f, NAN).data(), 12, c));
  EXPECT_EQ(c.float1(), 1.0f);
  EXPECT_EQ(c.float2(), 0.0f);
}

TEST(RmpProtocol, CorruptCommandIsRejected) {
  rmp::CommandPacket p = rmp::encodeConfig(rmp::ConfigCommand::SetOperationalMode,
                                           std::uint32_t(rmp::ModeRequest::Tractor));
  rmp::DecodedCommand c;
  ASSERT_TRUE(rmp::decodeCommand(p.data(), p.size(), c));
  EXPECT_EQ(c.id, rmp::kConfigCommandId);
  EXPECT_EQ(c.word1, 32u);
  EXPECT_EQ(c.word2, 5u);
  p[5] ^= 0x01;
  EXPECT_FALSE(rmp::decodeCommand(p.data(), p.size(), c));
  EXPECT_FALSE(rmp::decodeCommand(p.data(), 11, c));
}

TEST(RmpProtocol, FeedbackLayoutAndRoundTrip) {
  const rmp::FeedbackLayout layout;
  // 13 forced words (bits 0-12 of bitmap 1), linear and differential velocity (bits 27, 28),
  // right and left front wheel positions (bitmap 2 bits 1, 2), then the CRC word.
  EXPECT_EQ(layout.words(), 18u);
  EXPECT_EQ(layout.wordIndex(1, rmp::kFb1OperationalState), 9);
  EXPECT_EQ(layout.wordIndex(1, rmp::kFb1MinPropulsionBattSoc), 11);
  EXPECT_EQ(layout.wordIndex(1, rmp::kFb1LinearVel), 13);
  EXPECT_EQ(layout.wordIndex(1, rmp::kFb1DifferentialWheelVel), 14);
  EXPECT_EQ(layout.wordIndex(2, rmp::kFb2RightFrontPos), 15);
  EXPECT_EQ(layout.wordIndex(2, rmp::kFb2LeftFrontPos), 16);
  EXPECT_EQ(layout.wordIndex(3, 1u), -1);

  rmp::Feedback fb;
  fb.fault_status = {0, 0x40, 0, 0};
  fb.operational_state = 3;
  fb.battery_soc_pct = 91.5f;
  fb.linear_vel_mps = 0.25f;
  fb.yaw_rate_rps = -0.125f;
  fb.right_wheel_m = 12.5f;
  fb.left_wheel_m = -3.25f;
  std::vector<std::uint8_t> bytes = rmp::encodeFeedback(layout, fb);
  ASSERT_EQ(bytes.size(), 72u);
  rmp::Feedback out;
  std::string why;
  ASSERT_TRUE(rmp::decodeFeedback(bytes.data(), bytes.size(), layout, out, why)) << why;
  EXPECT_EQ(out.fault_status[1], 0x40u);
  EXPECT_TRUE(out.anyFault());
  EXPECT_EQ(out.operational_state, 3u);
  EXPECT_EQ(out.battery_soc_pct, 91.5f);
  EXPECT_EQ(out.linear_vel_mps, 0.25f);
  EXPECT_EQ(out.yaw_rate_rps, -0.125f);
  EXPECT_EQ(out.right_wheel_m, 12.5f);
  EXPECT_EQ(out.left_wheel_m, -3.25f);

  bytes[20] ^= 0x10;
  EXPECT_FALSE(rmp::decodeFeedback(bytes.data(), bytes.size(), layout, out, why));
  EXPECT_EQ(why, "response CRC mismatch");
  EXPECT_FALSE(rmp::decodeFeedback(bytes.data(), 60, layout, out, why));
  EXPECT_NE(why.find("60 bytes, expected 72"), std::string::npos) << why;
}
