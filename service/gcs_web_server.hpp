// The ground station's web map: an HTTP server (cpp-httplib) on a thread of its own that serves
// one page and what it needs, all from the binary (no internet):
//   GET /               the page (gcs_web_assets.hpp), /gcs.js and /gcs.css beside it
//   GET /hillshade.png  the terrain, on the WGS84 grid whose bounds the state gives
//   GET /state.json     the current state (GcsMapState), header X-State-Version
//   GET /events         Server-Sent Events: the state now, then again at every new version
// It binds only the address it is given, and answers only requests that name it (GcsWebLimits).
// Every request is held to bounds before httplib reads it (service/gcs_web_connection.hpp): its
// head's size, fields, body and ranges, the time it takes to arrive and the connection's life;
// event streams have a budget of their own, so that open pages never take the threads the page
// and its JSON are served by; stopping ends every connection at once.
#pragma once

#include <memory>
#include <string>
#include <thread>
#include <vector>

#include "service/gcs_http_head.hpp"
#include "service/gcs_map_state.hpp"
#include "planning/core/result.hpp"

namespace skyroute {

class GuardedHttpServer;

// Why the server could not start: the address is wrong (malformed, not a numeric address of this
// machine, or a port that needs privileges) or the port is taken by someone else.
struct ServeError {
  enum class Kind { kBadAddress, kPortInUse, kFailed };
  Kind kind = Kind::kFailed;
  std::string message;
};

// HOST:PORT with HOST an IPv4 address, [IPv6] address or "localhost" (127.0.0.1), and PORT in
// [0, 65535]; port 0 lets the system choose a free port.
struct ServeAddress {
  std::string host;
  int port = 0;
};
Result<ServeAddress, ServeError> parseServeAddress(const std::string& text);

// The web map's bounds; docs/gcs.md lists each with its option and default.
struct GcsWebLimits {
  // Host names served besides localhost, 127.0.0.1, [::1] and the bound address (--allow-host),
  // as canonicalHostName gives them; other Host fields are answered 421.
  std::vector<std::string> allowed_hosts;
  int max_event_streams = 8;        // /events open at once (--serve-streams); 503 beyond
  int request_workers = 8;          // threads for everything else, never taken by event streams
  double request_timeout_s = 10.0;  // the whole request head, from the connection's start (--serve-timeout; 408)
  double write_timeout_s = 5.0;     // a write the client does not take; then it is dropped
  double connection_life_s = 60.0;  // a connection that is not an event stream, whatever it does
  HttpHeadLimits head;              // head bytes and fields, body, byte ranges
};

class GcsWebServer {
 public:
  static Result<std::unique_ptr<GcsWebServer>, ServeError> start(const ServeAddress& address,
                                                                  std::shared_ptr<GcsMapState> state,
                                                                  const GcsWebLimits& limits = {});
  ~GcsWebServer();
  GcsWebServer(const GcsWebServer&) = delete;
  GcsWebServer& operator=(const GcsWebServer&) = delete;

  int port() const { return port_; }  // the bound port (the chosen one when asked for 0)
  std::string url() const;            // http://HOST:PORT/
  // Closes the state (open event streams end) and stops serving; the destructor does it too.
  void stop();

 private:
  GcsWebServer(ServeAddress address, std::shared_ptr<GcsMapState> state, const GcsWebLimits& limits);
  void addRoutes();

  ServeAddress address_;
  int port_ = 0;
  GcsWebLimits limits_;
  std::shared_ptr<GcsMapState> state_;
  std::unique_ptr<GuardedHttpServer> server_;
  std::thread thread_;
};

}  // namespace skyroute
