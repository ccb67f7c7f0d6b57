// A TCP connection to a local HTTP server that sends whatever bytes a test writes (a hostile
// client: malformed, partial, slow) and reads what comes back, every wait bounded by a timeout.
#pragma once

#include <arpa/inet.h>
#include <netinet/in.h>
#include <poll.h>
#include <sys/socket.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cstdint>
#include <cstdlib>
#include <string>
#include <string_view>

namespace skyroute::testing {

class RawHttpSocket {
 public:
  // Connected to 127.0.0.1:port (connected() false when that failed); receive_buffer_bytes > 0
  // shrinks the socket's receive buffer (and so the window the server may fill) first.
  explicit RawHttpSocket(int port, int receive_buffer_bytes = 0) {
    fd_ = ::socket(AF_INET, SOCK_STREAM | SOCK_CLOEXEC, 0);
    if (fd_ >= 0 && receive_buffer_bytes > 0) {
      ::setsockopt(fd_, SOL_SOCKET, SO_RCVBUF, &receive_buffer_bytes, sizeof receive_buffer_bytes);
    }
    sockaddr_in a{};
    a.sin_family = AF_INET;
    a.sin_port = htons(static_cast<std::uint16_t>(port));
    a.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
    if (fd_ >= 0 && ::connect(fd_, reinterpret_cast<sockaddr*>(&a), sizeof a) != 0) close();
  }
  ~RawHttpSocket() { close(); }
  RawHttpSocket(const RawHttpSocket&) = delete;
  RawHttpSocket& operator=(const RawHttpSocket&) = delete;
  RawHttpSocket(RawHttpSocket&& o) noexcept : fd_(o.fd_), received_(std::move(o.received_)), ended_(o.ended_) { o.fd_ = -1; }

  bool connected() const { return fd_ >= 0; }
  void close() {
    if (fd_ >= 0) ::close(fd_);
    fd_ = -1;
  }

  // All of `bytes`; false when the server no longer takes them (closed or reset).
  bool send(std::string_view bytes) {
    while (!bytes.empty() && fd_ >= 0) {
      const ssize_t n = ::send(fd_, bytes.data(), bytes.size(), MSG_NOSIGNAL);
      if (n <= 0) return false;
      bytes.remove_prefix(static_cast<std::size_t>(n));
    }
    return bytes.empty();
  }

  // Reads until `needle` has been received (true), or the server ends the connection or timeout_s
  // passes (false).
  bool readUntil(std::string_view needle, double timeout_s) {
    const auto deadline = deadlineIn(timeout_s);
    while (received_.find(needle) == std::string::npos) {
      if (!readBefore(deadline)) return false;
    }
    return true;
  }
  // Reads until the server ends the connection (true) or timeout_s passes (false).
  bool readUntilEnd(double timeout_s) {
    const auto deadline = deadlineIn(timeout_s);
    while (!ended_) {
      if (!readBefore(deadline) && !ended_) return false;
    }
    return true;
  }
  // Whether the server has ended the connection, waiting at most timeout_s for what it sends.
  bool endedWithin(double timeout_s) {
    readUntilEnd(timeout_s);
    return ended_;
  }

  // One read of at most max_bytes, waiting at most timeout_s; false when the server ended the
  // connection or nothing came.
  bool readSome(std::size_t max_bytes, double timeout_s) {
    return readBefore(deadlineIn(timeout_s), max_bytes);
  }

  const std::string& received() const { return received_; }
  bool ended() const { return ended_; }
  // The status of the reply received ("HTTP/1.1 NNN ..."), 0 before its status line.
  int status() const {
    if (received_.size() < 12 || received_.compare(0, 5, "HTTP/") != 0) return 0;
    return std::atoi(received_.substr(9, 3).c_str());
  }
  // The reply's body (after its head), as received so far.
  std::string body() const {
    const std::size_t end = received_.find("\r\n\r\n");
    return end == std::string::npos ? "" : received_.substr(end + 4);
  }
  // A header of the reply, by exact name ("" when absent).
  std::string header(const std::string& name) const {
    const std::size_t end = received_.find("\r\n\r\n");
    const std::size_t at = received_.find("\r\n" + name + ": ");
    if (at == std::string::npos || at > end) return "";
    const std::size_t value = at + name.size() + 4;
    return received_.substr(value, received_.find("\r\n", value) - value);
  }

 private:
  static std::chrono::steady_clock::time_point deadlineIn(double timeout_s) {
    return std::chrono::steady_clock::now() +
           std::chrono::duration_cast<std::chrono::steady_clock::duration>(std::chrono::duration<double>(timeout_s));
  }
  // One read; false when the server ended the connection or the deadline passed.
  bool readBefore(std::chrono::steady_clock::time_point deadline, std::size_t max_bytes = 65536) {
    if (fd_ < 0 || ended_) return false;
    const auto left_ms = std::chrono::duration_cast<std::chrono::milliseconds>(deadline - std::chrono::steady_clock::now()).count();
    if (left_ms <= 0) return false;
    pollfd p{fd_, POLLIN, 0};
    if (::poll(&p, 1, static_cast<int>(left_ms)) <= 0) return false;
    char buffer[65536];
    const ssize_t n = ::recv(fd_, buffer, std::min(sizeof buffer, max_bytes), 0);
    if (n <= 0) {
      ended_ = true;  // closed, or reset
      return false;
    }
    received_.append(buffer, static_cast<std::size_t>(n));
    return true;
  }

  int fd_ = -1;
  std::string received_;
  bool ended_ = false;
};

// A request head for 127.0.0.1:port: the request line, Host, "Connection: close" (so that any
// server ends the connection after its reply), the given header lines (each ending in CRLF), and
// the blank line.
inline std::string requestHead(const std::string& method_and_path, int port, const std::string& headers = "") {
  return method_and_path + " HTTP/1.1\r\nHost: 127.0.0.1:" + std::to_string(port) + "\r\nConnection: close\r\n" +
         headers + "\r\n";
}

}  // namespace skyroute::testing
