// One client connection of the web map, as cpp-httplib's Stream: the server
// (service/gcs_web_server.cpp) reads the request head through it within its time and size bounds,
// then lets httplib parse the same bytes and write the reply through it. Every wait on the socket
// also wakes on the server's stop, so that stopping never waits for a client; every wait is
// bounded: the head must arrive within the request timeout, a blocked write gives up after the
// write timeout, and a connection that is not an event stream ends when its life is over.
// Included by gcs_web_server.cpp only: it brings <httplib.h>.
#pragma once

#include <chrono>
#include <optional>
#include <string>
#include <string_view>

#include <httplib.h>

#include "service/gcs_http_head.hpp"

namespace skyroute {

// Raised once when the server stops: an eventfd that stays readable from then on, so a poll on it
// beside a socket returns at once.
class StopSignal {
 public:
  StopSignal();
  ~StopSignal();
  StopSignal(const StopSignal&) = delete;
  StopSignal& operator=(const StopSignal&) = delete;
  void raise();
  bool raised() const;
  int fd() const { return fd_; }

 private:
  int fd_ = -1;
};

struct ConnectionTimeouts {
  double request_timeout_s = 10.0;   // the whole head, from the connection's start
  double write_timeout_s = 5.0;      // one write that cannot go on
  double connection_life_s = 60.0;   // the whole connection, unless it is an event stream
  double linger_s = 0.5;             // after the reply: what the client still sends is read, then closed
};

class GuardedConnection final : public httplib::Stream {
 public:
  // Takes the socket: closes it (close()) when destroyed.
  GuardedConnection(int socket, const StopSignal& stop, const ConnectionTimeouts& timeouts);
  ~GuardedConnection() override;
  GuardedConnection(const GuardedConnection&) = delete;
  GuardedConnection& operator=(const GuardedConnection&) = delete;

  // Reads until the head is complete (kComplete; head() gives it), over a bound (kRefused), or the
  // request timeout passes (kRefused with 408). Nothing when the client left, the socket failed
  // or the server stops: then there is nobody to answer.
  std::optional<HttpHeadScan> readHead(const HttpHeadLimits& limits);
  std::string_view head() const { return std::string_view(received_).substr(0, head_bytes_); }

  // An event stream lives as long as its client reads it (writes still time out).
  void exemptFromLifeCap() { life_capped_ = false; }

  // Answers with the refusal's status and message (text/plain; extra_header: "Name: value" or "").
  void refuse(const HttpRefusal& refusal, std::string_view extra_header = "");
  // Says that no more is sent, reads what the client still sends for at most linger_s, closes.
  void close();

  // httplib::Stream. Reads give the bytes already received first. is_writable() (which httplib
  // asks only on behalf of a content provider: the event stream, between events) is also false
  // once the client has ended its side: the map's clients send nothing after their request, so
  // an end means the page is gone, and its stream can end before its next write.
  bool is_readable() const override;
  bool is_writable() const override;
  ssize_t read(char* ptr, size_t size) override;
  ssize_t write(const char* ptr, size_t size) override;
  void get_remote_ip_and_port(std::string& ip, int& port) const override;
  void get_local_ip_and_port(std::string& ip, int& port) const override;
  socket_t socket() const override { return socket_; }

 private:
  using Clock = std::chrono::steady_clock;
  enum class Wait { kReady, kTimedOut, kStopped, kFailed };
  // Waits for `events` on the socket for at most timeout_s, and never past the deadline given.
  Wait wait(short events, double timeout_s, Clock::time_point deadline) const;
  Clock::time_point writeDeadline() const;
  bool peerLeft() const;

  int socket_ = -1;
  const StopSignal& stop_;
  ConnectionTimeouts timeouts_;
  Clock::time_point started_;
  bool life_capped_ = true;
  std::string received_;        // the head, and whatever came with it
  std::size_t head_bytes_ = 0;
  std::size_t replayed_ = 0;    // of received_, given to httplib so far
};

}  // namespace skyroute
