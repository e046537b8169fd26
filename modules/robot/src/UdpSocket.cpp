#include "rasm/robot/UdpSocket.h"

#include <arpa/inet.h>
#include <netdb.h>
#include <netinet/in.h>
#include <poll.h>
#include <sys/socket.h>
#include <unistd.h>

#include <cerrno>
#include <cmath>
#include <cstring>
#include <stdexcept>

namespace rasm::robot {

namespace {
sockaddr_in resolve(const std::string& host, int port) {
  sockaddr_in a{};
  a.sin_family = AF_INET;
  a.sin_port = htons(std::uint16_t(port));
  if (inet_pton(AF_INET, host.c_str(), &a.sin_addr) == 1) return a;
  addrinfo hints{}, *res = nullptr;
  hints.ai_family = AF_INET;
  hints.ai_socktype = SOCK_DGRAM;
  const int rc = getaddrinfo(host.c_str(), nullptr, &hints, &res);
  if (rc != 0 || !res)
    throw std::runtime_error("UDP address '" + host + "': cannot be resolved (" + gai_strerror(rc) +
                             ")");
  a.sin_addr = reinterpret_cast<sockaddr_in*>(res->ai_addr)->sin_addr;
  freeaddrinfo(res);
  return a;
}
}  // namespace

UdpSocket::UdpSocket(const std::string& local_host, int local_port)
    : m_name(local_host + ":" + std::to_string(local_port)) {
  if (local_port < 0 || local_port > 65535)
    throw std::runtime_error("UDP port " + std::to_string(local_port) + ": not in 0-65535");
  m_fd = ::socket(AF_INET, SOCK_DGRAM | SOCK_CLOEXEC, 0);
  if (m_fd < 0) throw std::runtime_error("UDP socket: " + std::string(std::strerror(errno)));
  const sockaddr_in a = resolve(local_host, local_port);
  if (::bind(m_fd, reinterpret_cast<const sockaddr*>(&a), sizeof a) != 0) {
    const std::string why = std::strerror(errno);
    ::close(m_fd);
    throw std::runtime_error("UDP socket " + m_name + ": cannot bind (" + why + ")");
  }
}

UdpSocket::~UdpSocket() {
  if (m_fd >= 0) ::close(m_fd);
}

int UdpSocket::localPort() const {
  sockaddr_in a{};
  socklen_t len = sizeof a;
  if (::getsockname(m_fd, reinterpret_cast<sockaddr*>(&a), &len) != 0) return -1;
  return ntohs(a.sin_port);
}

void UdpSocket::sendTo(const std::string& host, int port, const std::uint8_t* data, std::size_t n) {
  const sockaddr_in a = resolve(host, port);
  const ssize_t sent = ::sendto(m_fd, data, n, 0, reinterpret_cast<const sockaddr*>(&a), sizeof a);
  if (sent != ssize_t(n))
    throw std::runtime_error("UDP send to " + host + ":" + std::to_string(port) + ": " +
                             (sent < 0 ? std::strerror(errno) : "short write"));
}

bool UdpSocket::receive(std::vector<std::uint8_t>& out, double timeout_s, std::string* from_host,
                        int* from_port) {
  pollfd p{m_fd, POLLIN, 0};
  const int ms = timeout_s <= 0 ? 0 : int(std::ceil(timeout_s * 1e3));
  const int rc = ::poll(&p, 1, ms);
  if (rc < 0 && errno != EINTR)
    throw std::runtime_error("UDP socket " + m_name + ": poll: " + std::strerror(errno));
  if (rc <= 0) return false;
  out.resize(65536);
  sockaddr_in a{};
  socklen_t len = sizeof a;
  const ssize_t n =
      ::recvfrom(m_fd, out.data(), out.size(), 0, reinterpret_cast<sockaddr*>(&a), &len);
  if (n < 0) {
    // ECONNREFUSED: an earlier datagram met a closed port (ICMP); nothing to read.
    if (errno == ECONNREFUSED || errno == EINTR || errno == EAGAIN) return false;
    throw std::runtime_error("UDP socket " + m_name + ": receive: " + std::strerror(errno));
  }
  out.resize(std::size_t(n));
  if (from_host) {
    char buf[INET_ADDRSTRLEN] = {};
    inet_ntop(AF_INET, &a.sin_addr, buf, sizeof buf);
    *from_host = buf;
  }
  if (from_port) *from_port = ntohs(a.sin_port);
  return true;
}

}  // namespace rasm::robot
