#include "service/gcs_web_connection.hpp"

#include <netdb.h>
#include <poll.h>
#include <sys/eventfd.h>
#include <sys/socket.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <climits>
#include <cmath>
#include <cstdio>
#include <cstring>

namespace skyroute {
namespace {

constexpr std::size_t kLingerMaxBytes = 64 * 1024;  // read and dropped after a reply, at most

using Clock = std::chrono::steady_clock;

Clock::duration seconds(double s) { return std::chrono::duration_cast<Clock::duration>(std::chrono::duration<double>(s)); }

void addressOf(int socket, bool peer, std::string& ip, int& port) {
  sockaddr_storage address{};
  socklen_t length = sizeof address;
  const int rc = peer ? getpeername(socket, reinterpret_cast<sockaddr*>(&address), &length)
                      : getsockname(socket, reinterpret_cast<sockaddr*>(&address), &length);
  ip.clear();
  port = 0;
  if (rc != 0) return;
  char host[NI_MAXHOST] = {}, service[NI_MAXSERV] = {};
  if (getnameinfo(reinterpret_cast<sockaddr*>(&address), length, host, sizeof host, service, sizeof service,
                  NI_NUMERICHOST | NI_NUMERICSERV) == 0) {
    ip = host;
    port = std::atoi(service);
  }
}

}  // namespace

StopSignal::StopSignal() : fd_(eventfd(0, EFD_CLOEXEC | EFD_NONBLOCK)) {}

StopSignal::~StopSignal() {
  if (fd_ >= 0) ::close(fd_);
}

void StopSignal::raise() {
  const std::uint64_t one = 1;
  [[maybe_unused]] const ssize_t written = ::write(fd_, &one, sizeof one);
}

bool StopSignal::raised() const {
  pollfd p{fd_, POLLIN, 0};
  return ::poll(&p, 1, 0) > 0;
}

GuardedConnection::GuardedConnection(int socket, const StopSignal& stop, const ConnectionTimeouts& timeouts)
    : socket_(socket), stop_(stop), timeouts_(timeouts), started_(Clock::now()) {}

GuardedConnection::~GuardedConnection() { close(); }

GuardedConnection::Wait GuardedConnection::wait(short events, double timeout_s, Clock::time_point deadline) const {
  const Clock::time_point until = std::min(Clock::now() + seconds(timeout_s), deadline);
  for (;;) {
    const auto left = std::chrono::duration<double, std::milli>(until - Clock::now()).count();
    if (left <= 0) return Wait::kTimedOut;
    pollfd fds[2] = {{socket_, events, 0}, {stop_.fd(), POLLIN, 0}};
    const int rc = ::poll(fds, 2, static_cast<int>(std::min(std::ceil(left), double{INT_MAX})));
    if (rc < 0) {
      if (errno == EINTR) continue;
      return Wait::kFailed;
    }
    if (fds[1].revents != 0) return Wait::kStopped;
    if ((fds[0].revents & events) != 0) return Wait::kReady;
    if ((fds[0].revents & (POLLERR | POLLHUP | POLLNVAL)) != 0) return Wait::kFailed;
  }
}

Clock::time_point GuardedConnection::writeDeadline() const {
  return life_capped_ ? started_ + seconds(timeouts_.connection_life_s) : Clock::time_point::max();
}

std::optional<HttpHeadScan> GuardedConnection::readHead(const HttpHeadLimits& limits) {
  const Clock::time_point deadline =
      started_ + seconds(std::min(timeouts_.request_timeout_s, timeouts_.connection_life_s));
  char buffer[4096];
  for (;;) {
    HttpHeadScan scan = scanRequestHead(received_, limits);
    if (scan.state == HttpHeadScan::State::kComplete) head_bytes_ = scan.head_bytes;
    if (scan.state != HttpHeadScan::State::kIncomplete) return scan;
    const Wait waited = wait(POLLIN, timeouts_.request_timeout_s, deadline);
    if (waited == Wait::kTimedOut) {
      if (received_.empty()) return std::nullopt;  // an idle connection (a browser's spare one): just closed
      scan.state = HttpHeadScan::State::kRefused;
      char limit[32];
      std::snprintf(limit, sizeof limit, "%g", timeouts_.request_timeout_s);
      scan.refusal = {408, "the request head did not arrive within " + std::string(limit) + " s"};
      return scan;
    }
    if (waited != Wait::kReady) return std::nullopt;
    // Never more than the head may still take, plus one byte to tell that it is over.
    const std::size_t room = limits.max_head_bytes + 1 - std::min(received_.size(), limits.max_head_bytes);
    const ssize_t n = ::recv(socket_, buffer, std::min(sizeof buffer, room), MSG_DONTWAIT);
    if (n == 0) return std::nullopt;
    if (n < 0) {
      if (errno == EAGAIN || errno == EWOULDBLOCK || errno == EINTR) continue;
      return std::nullopt;
    }
    received_.append(buffer, static_cast<std::size_t>(n));
  }
}

void GuardedConnection::refuse(const HttpRefusal& refusal, std::string_view extra_header) {
  const std::string body = refusal.message + "\n";
  std::string reply = "HTTP/1.1 " + std::to_string(refusal.status) + " " + std::string(httpReasonPhrase(refusal.status)) +
                      "\r\nContent-Type: text/plain; charset=utf-8\r\nContent-Length: " + std::to_string(body.size()) +
                      "\r\nCache-Control: no-store\r\nConnection: close\r\n";
  if (!extra_header.empty()) reply += std::string(extra_header) + "\r\n";
  reply += "\r\n" + body;
  for (std::size_t sent = 0; sent < reply.size();) {
    const ssize_t n = write(reply.data() + sent, reply.size() - sent);
    if (n <= 0) return;
    sent += static_cast<std::size_t>(n);
  }
}

void GuardedConnection::close() {
  if (socket_ < 0) return;
  // Closing with unread bytes makes the kernel reset the connection, and the client may lose the
  // reply; so the client first hears the end, and what it still sends is read for a moment.
  ::shutdown(socket_, SHUT_WR);
  const Clock::time_point until = Clock::now() + seconds(timeouts_.linger_s);
  char buffer[4096];
  for (std::size_t dropped = 0; dropped < kLingerMaxBytes;) {
    if (wait(POLLIN, timeouts_.linger_s, until) != Wait::kReady) break;
    const ssize_t n = ::recv(socket_, buffer, sizeof buffer, MSG_DONTWAIT);
    if (n == 0 || (n < 0 && errno != EAGAIN && errno != EWOULDBLOCK && errno != EINTR)) break;
    if (n > 0) dropped += static_cast<std::size_t>(n);
  }
  ::close(socket_);
  socket_ = -1;
}

bool GuardedConnection::is_readable() const {
  if (replayed_ < received_.size()) return true;
  return wait(POLLIN, timeouts_.request_timeout_s, started_ + seconds(timeouts_.request_timeout_s)) == Wait::kReady;
}

bool GuardedConnection::peerLeft() const {
  pollfd p{socket_, POLLIN | POLLRDHUP, 0};
  if (::poll(&p, 1, 0) <= 0) return false;
  if ((p.revents & (POLLRDHUP | POLLHUP | POLLERR)) != 0) return true;
  char byte = 0;
  return ::recv(socket_, &byte, 1, MSG_PEEK | MSG_DONTWAIT) == 0;
}

bool GuardedConnection::is_writable() const {
  return !peerLeft() && wait(POLLOUT, timeouts_.write_timeout_s, writeDeadline()) == Wait::kReady;
}

ssize_t GuardedConnection::read(char* ptr, size_t size) {
  if (replayed_ < received_.size()) {
    const std::size_t n = std::min(size, received_.size() - replayed_);
    std::memcpy(ptr, received_.data() + replayed_, n);
    replayed_ += n;
    return static_cast<ssize_t>(n);
  }
  // httplib reads past the head only for a body, which the head's checks refuse; bounded anyway.
  for (;;) {
    if (!is_readable()) return -1;
    const ssize_t n = ::recv(socket_, ptr, size, MSG_DONTWAIT);
    if (n >= 0 || (errno != EAGAIN && errno != EWOULDBLOCK && errno != EINTR)) return n;
  }
}

ssize_t GuardedConnection::write(const char* ptr, size_t size) {
  if (size == 0) return 0;
  for (;;) {
    if (wait(POLLOUT, timeouts_.write_timeout_s, writeDeadline()) != Wait::kReady) return -1;
    const ssize_t n = ::send(socket_, ptr, size, MSG_DONTWAIT | MSG_NOSIGNAL);
    if (n >= 0 || (errno != EAGAIN && errno != EWOULDBLOCK && errno != EINTR)) return n;
  }
}

void GuardedConnection::get_remote_ip_and_port(std::string& ip, int& port) const { addressOf(socket_, true, ip, port); }

void GuardedConnection::get_local_ip_and_port(std::string& ip, int& port) const { addressOf(socket_, false, ip, port); }

}  // namespace skyroute
