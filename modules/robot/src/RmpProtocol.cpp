#include "rasm/robot/RmpProtocol.h"

#include <algorithm>
#include <bitset>
#include <cmath>
#include <cstring>

namespace rasm::robot::rmp {

namespace {
void putU16(std::uint8_t* p, std::uint16_t v) {
  p[0] = std::uint8_t(v >> 8);
  p[1] = std::uint8_t(v);
}
void putU32(std::uint8_t* p, std::uint32_t v) {
  for (int i = 0; i < 4; ++i) p[i] = std::uint8_t(v >> (24 - 8 * i));
}
std::uint16_t getU16(const std::uint8_t* p) {
  return std::uint16_t((p[0] << 8) | p[1]);
}
std::uint32_t getU32(const std::uint8_t* p) {
  return (std::uint32_t(p[0]) << 24) | (std::uint32_t(p[1]) << 16) | (std::uint32_t(p[2]) << 8) |
         std::uint32_t(p[3]);
}
/// Words selected by the bits of `bitmap` below `bit`.
int countBelow(std::uint32_t bitmap, std::uint32_t bit) {
  return int(std::bitset<32>(bitmap & (bit - 1)).count());
}
}  // namespace

std::uint32_t floatBits(float f) {
  std::uint32_t u = 0;
  std::memcpy(&u, &f, sizeof u);
  return u;
}
float bitsFloat(std::uint32_t u) {
  float f = 0;
  std::memcpy(&f, &u, sizeof f);
  return f;
}

std::size_t FeedbackLayout::words() const {
  const std::uint32_t b1 = bitmap1 | kForcedFeedback1;
  return std::bitset<32>(b1).count() + std::bitset<32>(bitmap2).count() +
         std::bitset<32>(bitmap3).count() + 1;
}

int FeedbackLayout::wordIndex(int map, std::uint32_t bit) const {
  const std::uint32_t b1 = bitmap1 | kForcedFeedback1;
  const std::uint32_t maps[3] = {b1, bitmap2, bitmap3};
  if (map < 1 || map > 3 || (maps[map - 1] & bit) == 0) return -1;
  int index = 0;
  for (int m = 0; m < map - 1; ++m) index += int(std::bitset<32>(maps[m]).count());
  return index + countBelow(maps[map - 1], bit);
}

bool Feedback::anyFault() const {
  return std::any_of(fault_status.begin(), fault_status.end(), [](auto w) { return w != 0; });
}

std::uint16_t crc16(const std::uint8_t* data, std::size_t n) {
  std::uint16_t crc = 0;
  for (std::size_t i = 0; i < n; ++i) {
    crc ^= data[i];
    for (int b = 0; b < 8; ++b) crc = (crc & 1) ? std::uint16_t((crc >> 1) ^ 0xA001) : crc >> 1;
  }
  return crc;
}

CommandPacket encodeCommand(std::uint16_t id, std::uint32_t word1, std::uint32_t word2) {
  CommandPacket p{};
  putU16(&p[0], id);
  putU32(&p[2], word1);
  putU32(&p[6], word2);
  putU16(&p[10], crc16(p.data(), 10));
  return p;
}

CommandPacket encodeMotion(float velocity_norm, float yaw_rate_norm) {
  auto clamp1 = [](float x) { return std::isfinite(x) ? std::clamp(x, -1.0f, 1.0f) : 0.0f; };
  return encodeCommand(kMotionCommandId, floatBits(clamp1(velocity_norm)),
                       floatBits(clamp1(yaw_rate_norm)));
}

CommandPacket encodeConfig(ConfigCommand cmd, std::uint32_t param) {
  return encodeCommand(kConfigCommandId, std::uint32_t(cmd), param);
}
CommandPacket encodeConfig(ConfigCommand cmd, float param) {
  return encodeCommand(kConfigCommandId, std::uint32_t(cmd), floatBits(param));
}

float DecodedCommand::float1() const {
  return bitsFloat(word1);
}
float DecodedCommand::float2() const {
  return bitsFloat(word2);
}

bool decodeCommand(const std::uint8_t* data, std::size_t n, DecodedCommand& out) {
  if (n != kCommandBytes || crc16(data, 10) != getU16(data + 10)) return false;
  out.id = getU16(data);
  out.word1 = getU32(data + 2);
  out.word2 = getU32(data + 6);
  return true;
}

std::vector<std::uint8_t> encodeFeedback(const FeedbackLayout& layout, const Feedback& fb) {
  const std::size_t words = layout.words();
  std::vector<std::uint8_t> out(4 * words, 0);
  auto put = [&](int map, std::uint32_t bit, std::uint32_t value) {
    const int i = layout.wordIndex(map, bit);
    if (i >= 0) putU32(&out[4 * std::size_t(i)], value);
  };
  for (int k = 0; k < 4; ++k) put(1, kFb1FaultStatus1 << k, fb.fault_status[std::size_t(k)]);
  put(1, kFb1OperationalState, fb.operational_state);
  put(1, kFb1MinPropulsionBattSoc, floatBits(fb.battery_soc_pct));
  put(1, kFb1LinearVel, floatBits(fb.linear_vel_mps));
  put(1, kFb1DifferentialWheelVel, floatBits(fb.yaw_rate_rps));
  put(2, kFb2RightFrontPos, floatBits(fb.right_wheel_m));
  put(2, kFb2LeftFrontPos, floatBits(fb.left_wheel_m));
  putU32(&out[out.size() - 4], crc16(out.data(), out.size() - 2));
  return out;
}

bool decodeFeedback(const std::uint8_t* data, std::size_t n, const FeedbackLayout& layout,
                    Feedback& out, std::string& why) {
  const std::size_t expected = 4 * layout.words();
  if (n != expected) {
    why = "response of " + std::to_string(n) + " bytes, expected " + std::to_string(expected) +
          " (the feedback bitmaps configured)";
    return false;
  }
  if (crc16(data, n - 2) != getU16(data + n - 2)) {
    why = "response CRC mismatch";
    return false;
  }
  auto word = [&](int map, std::uint32_t bit) -> std::uint32_t {
    const int i = layout.wordIndex(map, bit);
    return i >= 0 ? getU32(data + 4 * std::size_t(i)) : 0u;
  };
  for (int k = 0; k < 4; ++k) out.fault_status[std::size_t(k)] = word(1, kFb1FaultStatus1 << k);
  out.operational_state = word(1, kFb1OperationalState);
  out.battery_soc_pct = bitsFloat(word(1, kFb1MinPropulsionBattSoc));
  out.linear_vel_mps = bitsFloat(word(1, kFb1LinearVel));
  out.yaw_rate_rps = bitsFloat(word(1, kFb1DifferentialWheelVel));
  out.right_wheel_m = bitsFloat(word(2, kFb2RightFrontPos));
  out.left_wheel_m = bitsFloat(word(2, kFb2LeftFrontPos));
  return true;
}

}  // namespace rasm::robot::rmp
