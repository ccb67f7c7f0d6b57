#include "service/gcs_web_server.hpp"

#include <arpa/inet.h>
#include <netdb.h>
#include <sys/socket.h>
#include <unistd.h>

#include <atomic>
#include <cerrno>
#include <chrono>
#include <cmath>
#include <cstring>
#include <optional>

#include "service/gcs_allowed_hosts.hpp"
#include "service/gcs_web_assets.hpp"
// Last: httplib brings <resolv.h>, whose _res macro breaks Eigen's declarations (gcs_map_state.hpp).
#include "service/gcs_web_connection.hpp"

namespace skyroute {

// httplib's server with every connection read through a GuardedConnection: the head is read and
// checked (size, fields, body, ranges, Host) before httplib parses it, and one request is served
// per connection, so that no connection waits between requests on a thread.
class GuardedHttpServer final : public httplib::Server {
 public:
  explicit GuardedHttpServer(const GcsWebLimits& limits);
  // The names served; set once the port is known, before serving.
  void allowHosts(AllowedHosts hosts) { hosts_.emplace(std::move(hosts)); }
  // Every connection's waits end now (before httplib's stop(), which waits for its threads).
  void stopConnections() { stop_.raise(); }

 private:
  bool process_and_close_socket(socket_t sock) override;

  GcsWebLimits limits_;
  ConnectionTimeouts timeouts_;
  std::optional<AllowedHosts> hosts_;
  StopSignal stop_;
};

namespace {

constexpr double kKeepAliveInterval_s = 15.0;  // an SSE comment this often finds browsers that cannot be reached
constexpr double kPeerCheckInterval_s = 1.0;   // how soon an event stream notices its page is gone
constexpr double kLinger_s = 0.5;              // after a reply, what the client still sends is read this long
constexpr std::size_t kHostShownBytes = 100;   // of a refused Host field, in the reply

template <class Seconds>
std::chrono::microseconds microseconds(Seconds s) {
  return std::chrono::duration_cast<std::chrono::microseconds>(std::chrono::duration<double>(s));
}

// The /events streams open at once, at most max; a slot is given back when its last holder goes
// (the stream's content provider, destroyed with its response, whatever ended the stream).
class EventStreamBudget : public std::enable_shared_from_this<EventStreamBudget> {
 public:
  explicit EventStreamBudget(int max) : max_(max) {}
  class Slot {
   public:
    explicit Slot(std::shared_ptr<EventStreamBudget> budget) : budget_(std::move(budget)) {}
    ~Slot() { --budget_->open_; }
    Slot(const Slot&) = delete;
    Slot& operator=(const Slot&) = delete;

   private:
    std::shared_ptr<EventStreamBudget> budget_;
  };
  std::shared_ptr<Slot> take() {
    int open = open_.load();
    do {
      if (open >= max_) return nullptr;
    } while (!open_.compare_exchange_weak(open, open + 1));
    return std::make_shared<Slot>(shared_from_this());
  }
  int max() const { return max_; }

 private:
  const int max_;
  std::atomic<int> open_{0};
};

ServeError badAddress(const std::string& message) { return {ServeError::Kind::kBadAddress, message}; }

bool isNumericAddress(const std::string& host) {
  unsigned char buffer[sizeof(in6_addr)];
  return inet_pton(AF_INET, host.c_str(), buffer) == 1 || inet_pton(AF_INET6, host.c_str(), buffer) == 1;
}

// Binds a throw-away socket the way the server will, to tell the reasons apart (httplib only
// says that binding failed): a taken port, an address not on this machine, a privileged port.
std::optional<ServeError> probeBind(const ServeAddress& address) {
  addrinfo hints{};
  hints.ai_socktype = SOCK_STREAM;
  hints.ai_flags = AI_NUMERICHOST | AI_NUMERICSERV | AI_PASSIVE;
  addrinfo* found = nullptr;
  const std::string port = std::to_string(address.port);
  if (const int rc = getaddrinfo(address.host.c_str(), port.c_str(), &hints, &found); rc != 0) {
    return badAddress(address.host + " is not a numeric address: " + gai_strerror(rc));
  }
  std::optional<ServeError> problem;
  const int fd = socket(found->ai_family, found->ai_socktype, found->ai_protocol);
  if (fd < 0) {
    problem = ServeError{ServeError::Kind::kFailed, std::string("cannot open a socket: ") + std::strerror(errno)};
  } else {
    const int yes = 1;
    setsockopt(fd, SOL_SOCKET, SO_REUSEADDR, &yes, sizeof yes);
    if (bind(fd, found->ai_addr, found->ai_addrlen) != 0) {
      const int e = errno;
      const std::string where = address.host + ":" + port;
      if (e == EADDRINUSE) {
        problem = ServeError{ServeError::Kind::kPortInUse, "port " + port + " on " + address.host +
                                                               " is already in use by another program"};
      } else if (e == EADDRNOTAVAIL) {
        problem = badAddress(address.host + " is not an address of this machine");
      } else if (e == EACCES) {
        problem = badAddress("port " + port + " needs privileges (use a port above 1023)");
      } else {
        problem = ServeError{ServeError::Kind::kFailed, "cannot bind " + where + ": " + std::strerror(e)};
      }
    }
    ::close(fd);
  }
  freeaddrinfo(found);
  return problem;
}

// Only SO_REUSEADDR (restarts while old connections linger), not httplib's default SO_REUSEPORT,
// which would let a second server share a port that is in use instead of failing.
void reuseAddressOnly(socket_t sock) {
  const int yes = 1;
  setsockopt(sock, SOL_SOCKET, SO_REUSEADDR, &yes, sizeof yes);
}

std::string sseEvent(const GcsMapState::Snapshot& snapshot) {
  return "id: " + std::to_string(snapshot.version) + "\ndata: " + *snapshot.json + "\n\n";
}

}  // namespace

Result<ServeAddress, ServeError> parseServeAddress(const std::string& text) {
  const std::string usage = "'" + text + "' is not HOST:PORT (e.g. 127.0.0.1:8080 or [::1]:8080)";
  const std::size_t colon = text.rfind(':');
  if (colon == std::string::npos || colon == 0) return badAddress(usage);
  ServeAddress address;
  address.host = text.substr(0, colon);
  const std::string port = text.substr(colon + 1);
  if (address.host.size() > 2 && address.host.front() == '[' && address.host.back() == ']') {
    address.host = address.host.substr(1, address.host.size() - 2);
    if (address.host.find(':') == std::string::npos) return badAddress(usage);
  } else if (address.host.find(':') != std::string::npos) {
    return badAddress(usage + ": an IPv6 address goes in brackets");
  }
  if (address.host == "localhost") address.host = "127.0.0.1";
  if (!isNumericAddress(address.host)) {
    return badAddress(usage + ": '" + address.host + "' is not an IPv4 or IPv6 address");
  }
  if (port.empty() || port.size() > 5 || port.find_first_not_of("0123456789") != std::string::npos ||
      std::stoi(port) > 65535) {
    return badAddress(usage + ": the port must be a number in [0, 65535]");
  }
  address.port = std::stoi(port);
  return address;
}

GuardedHttpServer::GuardedHttpServer(const GcsWebLimits& limits)
    : limits_(limits),
      timeouts_{limits.request_timeout_s, limits.write_timeout_s, limits.connection_life_s, kLinger_s} {
  // httplib's own settings where it has them. Its threads: the event streams' budget plus the
  // workers for the rest, so that streams never hold them all.
  const auto threads = static_cast<std::size_t>(limits.max_event_streams + limits.request_workers);
  new_task_queue = [threads] { return new httplib::ThreadPool(threads); };
  set_payload_max_length(limits.head.max_body_bytes);
  set_read_timeout(microseconds(limits.request_timeout_s));
  set_write_timeout(microseconds(limits.write_timeout_s));
  set_keep_alive_max_count(1);
}

bool GuardedHttpServer::process_and_close_socket(socket_t sock) {
  GuardedConnection connection(sock, stop_, timeouts_);  // closes the socket when it goes
  const std::optional<HttpHeadScan> scan = connection.readHead(limits_.head);
  if (!scan) return false;
  if (scan->state == HttpHeadScan::State::kRefused) {
    connection.refuse(scan->refusal);
    return false;
  }
  auto head = parseRequestHead(connection.head(), limits_.head);
  if (!head) {
    connection.refuse(head.error(), head.error().status == 405 ? "Allow: GET, HEAD" : "");
    return false;
  }
  if (!hosts_ || !hosts_->allows(head->host)) {
    const std::string shown = head->host.substr(0, kHostShownBytes) + (head->host.size() > kHostShownBytes ? "..." : "");
    connection.refuse({421, "this live map is not served as '" + shown + "': it answers to " +
                                (hosts_ ? hosts_->describe() : std::string("nothing yet")) +
                                " (skyroute gcs --allow-host NAME adds a name)"});
    return false;
  }
  if (head->path == "/events") connection.exemptFromLifeCap();
  bool connection_closed = false;
  return process_request(connection, /*close_connection=*/true, connection_closed, nullptr);
}

GcsWebServer::GcsWebServer(ServeAddress address, std::shared_ptr<GcsMapState> state, const GcsWebLimits& limits)
    : address_(std::move(address)),
      limits_(limits),
      state_(std::move(state)),
      server_(std::make_unique<GuardedHttpServer>(limits)) {}

GcsWebServer::~GcsWebServer() { stop(); }

Result<std::unique_ptr<GcsWebServer>, ServeError> GcsWebServer::start(const ServeAddress& address,
                                                                       std::shared_ptr<GcsMapState> state,
                                                                       const GcsWebLimits& limits) {
  const auto positive = [](double s) { return std::isfinite(s) && s > 0; };
  if (limits.max_event_streams < 1 || limits.request_workers < 1 || !positive(limits.request_timeout_s) ||
      !positive(limits.write_timeout_s) || !positive(limits.connection_life_s)) {
    return ServeError{ServeError::Kind::kFailed,
                      "the web map's limits must be positive (event streams, workers, timeouts)"};
  }
  if (auto problem = probeBind(address)) return *problem;
  std::unique_ptr<GcsWebServer> web(new GcsWebServer(address, std::move(state), limits));
  web->server_->set_socket_options(reuseAddressOnly);
  web->addRoutes();
  if (address.port == 0) {
    web->port_ = web->server_->bind_to_any_port(address.host);
    if (web->port_ < 0) return ServeError{ServeError::Kind::kFailed, "cannot bind " + address.host + " to any port"};
  } else {
    // The probe passed, so a failure here is a port taken in between.
    if (!web->server_->bind_to_port(address.host, address.port)) {
      return ServeError{ServeError::Kind::kPortInUse,
                        "port " + std::to_string(address.port) + " on " + address.host + " was taken just now"};
    }
    web->port_ = address.port;
  }
  web->server_->allowHosts(AllowedHosts(address.host, web->port_, limits.allowed_hosts));
  auto ended = std::make_shared<std::atomic<bool>>(false);
  web->thread_ = std::thread([server = web->server_.get(), ended] {
    server->listen_after_bind();
    *ended = true;
  });
  // httplib's stop() does nothing before the loop runs, and the loop would then never end: wait
  // for it (it starts at once; the bound socket already queues connections meanwhile).
  while (!web->server_->is_running() && !*ended) std::this_thread::sleep_for(std::chrono::milliseconds(1));
  return web;
}

std::string GcsWebServer::url() const {
  const bool v6 = address_.host.find(':') != std::string::npos;
  return "http://" + (v6 ? "[" + address_.host + "]" : address_.host) + ":" + std::to_string(port_) + "/";
}

void GcsWebServer::stop() {
  if (!thread_.joinable()) return;
  server_->stopConnections();  // no connection waits on its client any more
  state_->close();             // event streams return, so their worker threads can be joined
  server_->stop();
  thread_.join();
}

void GcsWebServer::addRoutes() {
  auto asset = [](std::string_view body, const char* type) {
    return [body, type](const httplib::Request&, httplib::Response& res) {
      res.set_content(body.data(), body.size(), type);
    };
  };
  server_->Get("/", asset(web_assets::kIndexHtml, "text/html; charset=utf-8"));
  server_->Get("/gcs.js", asset(web_assets::kScript, "text/javascript; charset=utf-8"));
  server_->Get("/gcs.css", asset(web_assets::kStyle, "text/css; charset=utf-8"));

  std::shared_ptr<GcsMapState> state = state_;
  server_->Get("/hillshade.png", [state](const httplib::Request&, httplib::Response& res) {
    res.set_content(state->image().png, "image/png");
  });
  server_->Get("/state.json", [state](const httplib::Request&, httplib::Response& res) {
    const GcsMapState::Snapshot snapshot = state->snapshot();
    res.set_header("Cache-Control", "no-store");
    res.set_header("X-State-Version", std::to_string(snapshot.version));
    res.set_content(*snapshot.json, "application/json");
  });
  auto streams = std::make_shared<EventStreamBudget>(limits_.max_event_streams);
  server_->Get("/events", [state, streams](const httplib::Request&, httplib::Response& res) {
    res.set_header("Cache-Control", "no-store");
    std::shared_ptr<EventStreamBudget::Slot> slot = streams->take();
    if (!slot) {
      res.status = 503;
      res.set_header("Retry-After", "5");
      res.set_content("this live map has " + std::to_string(streams->max()) +
                          " event streams open, its most (skyroute gcs --serve-streams); close a page or try again\n",
                      "text/plain; charset=utf-8");
      return;
    }
    auto sent = std::make_shared<std::uint64_t>(0);  // the version this stream last sent
    res.set_chunked_content_provider("text/event-stream", [state, sent, slot](std::size_t, httplib::DataSink& sink) {
      // Each call sends one thing: the state when it changed, else a keep-alive comment. While it
      // waits it asks every second whether the page is still there, so that a closed page gives
      // its slot of the budget back at once.
      const auto keep_alive_at = std::chrono::steady_clock::now() + microseconds(kKeepAliveInterval_s);
      std::uint64_t version = state->waitForVersionAbove(*sent, 0.0);
      while (*sent != 0 && version <= *sent && !state->closed() && std::chrono::steady_clock::now() < keep_alive_at) {
        if (!sink.is_writable()) return false;
        version = state->waitForVersionAbove(*sent, kPeerCheckInterval_s);
      }
      if (state->closed()) {
        sink.done();
        return true;
      }
      if (version > *sent) {
        const GcsMapState::Snapshot snapshot = state->snapshot();
        *sent = snapshot.version;
        const std::string event = sseEvent(snapshot);
        return sink.write(event.data(), event.size());
      }
      static constexpr std::string_view kComment = ": keep-alive\n\n";
      return sink.write(kComment.data(), kComment.size());
    });
  });
}

}  // namespace skyroute
