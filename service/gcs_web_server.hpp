// The ground station's web map: an HTTP server (cpp-httplib) on a thread of its own that serves
// one page and what it needs, all from the binary (no internet):
//   GET /               the page (gcs_web_assets.hpp), /gcs.js and /gcs.css beside it
//   GET /hillshade.png  the terrain, on the WGS84 grid whose bounds the state gives
//   GET /state.json     the current state (GcsMapState), header X-State-Version
//   GET /events         Server-Sent Events: the state now, then again at every new version
// It binds only the address it is given.
#pragma once

#include <memory>
#include <string>
#include <thread>

#include "service/gcs_map_state.hpp"
#include "planning/core/result.hpp"

namespace httplib {
class Server;
}

namespace skyroute {

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

class GcsWebServer {
 public:
  static Result<std::unique_ptr<GcsWebServer>, ServeError> start(const ServeAddress& address,
                                                                  std::shared_ptr<GcsMapState> state);
  ~GcsWebServer();
  GcsWebServer(const GcsWebServer&) = delete;
  GcsWebServer& operator=(const GcsWebServer&) = delete;

  int port() const { return port_; }  // the bound port (the chosen one when asked for 0)
  std::string url() const;            // http://HOST:PORT/
  // Closes the state (open event streams end) and stops serving; the destructor does it too.
  void stop();

 private:
  GcsWebServer(ServeAddress address, std::shared_ptr<GcsMapState> state);
  void addRoutes();

  ServeAddress address_;
  int port_ = 0;
  std::shared_ptr<GcsMapState> state_;
  std::unique_ptr<httplib::Server> server_;
  std::thread thread_;
};

}  // namespace skyroute
