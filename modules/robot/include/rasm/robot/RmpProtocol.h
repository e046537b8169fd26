#pragma once
// The Segway RMP 220 / 440 (RMP v3 firmware) user interface over UDP/Ethernet, as far as it is
// public (docs/hardware.md "Segway RMP": sources and what is assumed):
//
// Command packet (computer -> RMP, one UDP datagram of 12 bytes, big-endian):
//   bytes 0-1   message id: 0x0500 motion, 0x0501 configuration
//   bytes 2-5   word 1: motion: normalised velocity, IEEE-754 float in [-1, 1] (a fraction of
//               the RMP's maximum velocity); configuration: the general-purpose command id
//   bytes 6-9   word 2: motion: normalised yaw rate, float in [-1, 1] (a fraction of the RMP's
//               maximum yaw rate, counter-clockwise positive); configuration: its parameter
//               (uint32 or float by command)
//   bytes 10-11 CRC-16 of bytes 0-9 (reflected polynomial 0xA001, initial value 0: CRC-16/ARC),
//               high byte first.
// Response packet (RMP -> computer, one datagram per command received): 32-bit big-endian words,
// one per bit set in the user feedback bitmaps 1, 2, 3 (in that order, lowest bit first; the
// bits of kForcedFeedback1 are always present), then one word whose low 16 bits are the CRC-16
// of every byte before them.
// The feedback variables rasm reads and their bits are below; their encoding (float or
// integer) follows the public variable list. Everything the RMP offers besides these is ignored.

#include <array>
#include <cstdint>
#include <string>
#include <vector>

namespace rasm::robot::rmp {

constexpr std::uint16_t kMotionCommandId = 0x0500;
constexpr std::uint16_t kConfigCommandId = 0x0501;
constexpr std::size_t kCommandBytes = 12;

/// General-purpose configuration commands (word 1 of a 0x0501 packet) rasm sends.
enum class ConfigCommand : std::uint32_t {
  None = 0,                 ///< no action; the RMP answers with feedback
  SetMaxVelocity = 1,       ///< float m/s
  SetMaxTurnRate = 6,       ///< float rad/s
  SetUserFeedback1 = 17,    ///< uint32 bitmap
  SetUserFeedback2 = 18,    ///< uint32 bitmap
  SetUserFeedback3 = 19,    ///< uint32 bitmap
  SetOperationalMode = 32,  ///< uint32 OperationalModeRequest
  ResetIntegrators = 34,    ///< uint32 bitmap (0x1F: every position integrator)
};

/// Parameters of ConfigCommand::SetOperationalMode.
enum class ModeRequest : std::uint32_t { Disable = 1, PowerDown = 2, Standby = 4, Tractor = 5 };

// Feedback bits rasm selects.
constexpr std::uint32_t kForcedFeedback1 = 0x00001FFF;  ///< always present (bits 0-12)
constexpr std::uint32_t kFb1FaultStatus1 = 0x00000001;  ///< fault status words 1-4: bits 0-3
constexpr std::uint32_t kFb1OperationalState = 0x00000200;
constexpr std::uint32_t kFb1MinPropulsionBattSoc = 0x00000800;  ///< float, percent
constexpr std::uint32_t kFb1LinearVel = 0x08000000;             ///< float, m/s
constexpr std::uint32_t kFb1DifferentialWheelVel = 0x10000000;  ///< float, rad/s (yaw rate)
constexpr std::uint32_t kFb2RightFrontPos = 0x00000002;         ///< float, m travelled
constexpr std::uint32_t kFb2LeftFrontPos = 0x00000004;          ///< float, m travelled

/// The bitmaps rasm configures at start: the forced block, velocities and wheel positions.
struct FeedbackLayout {
  std::uint32_t bitmap1 = kForcedFeedback1 | kFb1LinearVel | kFb1DifferentialWheelVel;
  std::uint32_t bitmap2 = kFb2RightFrontPos | kFb2LeftFrontPos;
  std::uint32_t bitmap3 = 0;

  /// Words in a response, the CRC word included.
  std::size_t words() const;
  /// Index of the word of `bit` of bitmap `map` (1-3); -1 when not selected.
  int wordIndex(int map, std::uint32_t bit) const;
};

/// What rasm reads from one response.
struct Feedback {
  std::array<std::uint32_t, 4> fault_status{};  ///< fault status words 1-4 (0: no fault)
  std::uint32_t operational_state = 0;
  float battery_soc_pct = 0.0f;
  float linear_vel_mps = 0.0f;
  float yaw_rate_rps = 0.0f;  ///< differential wheel velocity, counter-clockwise positive
  float right_wheel_m = 0.0f, left_wheel_m = 0.0f;
  bool anyFault() const;
};

/// CRC-16 of `n` bytes as the RMP computes it (reflected 0xA001, initial 0).
std::uint16_t crc16(const std::uint8_t* data, std::size_t n);

using CommandPacket = std::array<std::uint8_t, kCommandBytes>;
CommandPacket encodeCommand(std::uint16_t id, std::uint32_t word1, std::uint32_t word2);
/// Motion command; the normalised values are clamped to [-1, 1].
CommandPacket encodeMotion(float velocity_norm, float yaw_rate_norm);
CommandPacket encodeConfig(ConfigCommand cmd, std::uint32_t param);
CommandPacket encodeConfig(ConfigCommand cmd, float param);

/// A command packet read back (what the RMP, or a test's stand-in for it, receives). False when
/// the size or the CRC is wrong.
struct DecodedCommand {
  std::uint16_t id = 0;
  std::uint32_t word1 = 0, word2 = 0;
  float float1() const;
  float float2() const;
};
bool decodeCommand(const std::uint8_t* data, std::size_t n, DecodedCommand& out);

/// A response carrying `fb` in `layout` (words rasm does not read are 0), with its CRC word.
std::vector<std::uint8_t> encodeFeedback(const FeedbackLayout& layout, const Feedback& fb);
/// Parses a response in `layout`; false with `why` set when its size or CRC is wrong.
bool decodeFeedback(const std::uint8_t* data, std::size_t n, const FeedbackLayout& layout,
                    Feedback& out, std::string& why);

std::uint32_t floatBits(float f);
float bitsFloat(std::uint32_t u);

}  // namespace rasm::robot::rmp
