#pragma once
// A UDP socket (IPv4, POSIX) with receive timeouts: the Segway RMP's network interface speaks
// UDP and mrpt::comms has TCP sockets and serial ports only. Errors throw std::runtime_error
// naming the address and the system's reason.

#include <cstdint>
#include <string>
#include <vector>

namespace rasm::robot {

class UdpSocket {
 public:
  /// Binds to `local_host`:`local_port` (port 0: any free port).
  explicit UdpSocket(const std::string& local_host = "0.0.0.0", int local_port = 0);
  ~UdpSocket();
  UdpSocket(const UdpSocket&) = delete;
  UdpSocket& operator=(const UdpSocket&) = delete;

  /// The port bound (the one the system chose for port 0).
  int localPort() const;
  /// Sends one datagram to host:port (a numeric IPv4 address or a resolvable name).
  void sendTo(const std::string& host, int port, const std::uint8_t* data, std::size_t n);
  /// Waits up to timeout_s for one datagram; false on timeout. `from_host` / `from_port` (when
  /// not null) get the sender.
  bool receive(std::vector<std::uint8_t>& out, double timeout_s, std::string* from_host = nullptr,
               int* from_port = nullptr);

 private:
  int m_fd = -1;
  std::string m_name;
};

}  // namespace rasm::robot
