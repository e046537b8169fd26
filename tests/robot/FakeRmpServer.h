#pragma once
// A stand-in for a Segway RMP on loopback: a real UDP socket served by a thread, answering every
// valid command packet with feedback in the layout it was configured with, and driving a
// differential base by the motion commands it receives (normalised by the limits it was sent),
// so the robot's odometry can be checked against the wheel travel it was sent.

#include <gtest/gtest.h>

#include <atomic>
#include <chrono>
#include <cmath>
#include <mutex>
#include <thread>
#include <vector>

#include "rasm/robot/RmpProtocol.h"
#include "rasm/robot/UdpSocket.h"

namespace rasm::robot::test {

class FakeRmpServer {
 public:
  explicit FakeRmpServer(double track_width_m = 0.7112)
      : m_socket("127.0.0.1", 0), m_track(track_width_m) {
    m_layout.bitmap1 = rmp::kForcedFeedback1;  // the RMP's state before rasm configures it
    m_layout.bitmap2 = m_layout.bitmap3 = 0;
    m_thread = std::thread([this] { serve(); });
  }
  ~FakeRmpServer() { stop(); }
  void stop() {
    m_quit = true;
    if (m_thread.joinable()) m_thread.join();
  }
  int port() const { return m_socket.localPort(); }
  /// While false, packets are read and recorded but not answered (a powered-off base).
  std::atomic<bool> responsive{true};

  struct Record {
    std::vector<rmp::DecodedCommand> motion, config;
    std::size_t bad_packets = 0;
    double left_m = 0, right_m = 0;   ///< wheel travel
    double x = 0, y = 0, yaw = 0;     ///< the base's pose by its own integration
    double max_v = 2.2, max_w = 3.0;  ///< limits it was sent
  };
  Record record() const {
    std::lock_guard<std::mutex> lock(m_mx);
    return m_rec;
  }

 private:
  void serve() {
    std::vector<std::uint8_t> buf;
    std::string host;
    int from = 0;
    auto last = std::chrono::steady_clock::now();
    while (!m_quit) {
      if (!m_socket.receive(buf, 0.02, &host, &from)) continue;
      rmp::DecodedCommand c;
      std::lock_guard<std::mutex> lock(m_mx);
      if (!rmp::decodeCommand(buf.data(), buf.size(), c)) {
        ++m_rec.bad_packets;
        continue;
      }
      const auto now = std::chrono::steady_clock::now();
      const double dt = std::chrono::duration<double>(now - last).count();
      last = now;
      if (c.id == rmp::kMotionCommandId) {
        m_rec.motion.push_back(c);
        drive(c.float1() * m_rec.max_v, c.float2() * m_rec.max_w, dt);
      } else {
        m_rec.config.push_back(c);
        configure(c);
      }
      if (!responsive) continue;
      rmp::Feedback fb;
      fb.operational_state = 3;
      fb.battery_soc_pct = 87.5f;
      fb.left_wheel_m = float(m_rec.left_m);
      fb.right_wheel_m = float(m_rec.right_m);
      const auto out = rmp::encodeFeedback(m_layout, fb);
      m_socket.sendTo(host, from, out.data(), out.size());
    }
  }
  void drive(double v, double w, double dt) {
    dt = std::min(dt, 0.1);
    m_rec.left_m += (v - 0.5 * w * m_track) * dt;
    m_rec.right_m += (v + 0.5 * w * m_track) * dt;
    m_rec.x += v * std::cos(m_rec.yaw + 0.5 * w * dt) * dt;
    m_rec.y += v * std::sin(m_rec.yaw + 0.5 * w * dt) * dt;
    m_rec.yaw += w * dt;
  }
  void configure(const rmp::DecodedCommand& c) {
    using C = rmp::ConfigCommand;
    switch (C(c.word1)) {
      case C::SetUserFeedback1:
        m_layout.bitmap1 = c.word2;
        break;
      case C::SetUserFeedback2:
        m_layout.bitmap2 = c.word2;
        break;
      case C::SetUserFeedback3:
        m_layout.bitmap3 = c.word2;
        break;
      case C::SetMaxVelocity:
        m_rec.max_v = c.float2();
        break;
      case C::SetMaxTurnRate:
        m_rec.max_w = c.float2();
        break;
      default:
        break;
    }
  }

  UdpSocket m_socket;
  double m_track;
  rmp::FeedbackLayout m_layout;
  mutable std::mutex m_mx;
  Record m_rec;
  std::atomic<bool> m_quit{false};
  std::thread m_thread;
};

}  // namespace rasm::robot::test
