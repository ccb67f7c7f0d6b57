// `skyroute gcs --serve`: the live web map beside the ground station's DDS loop. Loads the DEM,
// shades it, and starts the web server (service/gcs_web_server.hpp) on its own thread; the DDS
// handlers feed state(). Fails with the exit-code table: a bad --serve address or --allow-host
// name 2, an unreadable --dem 3, a port in use 4.
#pragma once

#include <memory>
#include <string>

#include "service/gcs_map_state.hpp"
#include "service/gcs_web_server.hpp"

namespace skyroute::cli {

class GcsLiveMap {
 public:
  // serve: HOST:PORT as --serve gives it; dem_path: "" for the embedded terrain; limits: the
  // server's bounds, with allowed_hosts as --allow-host gives them (checked here, exit 2).
  static std::unique_ptr<GcsLiveMap> start(const std::string& tool, const std::string& serve, const std::string& dem_path,
                                           GcsWebLimits limits);
  GcsMapState& state() { return *state_; }
  // Prints "live map on URL". The caller says it once Ctrl-C is handled, so that whoever reads the
  // line (a user, a test) may stop the program cleanly from then on.
  void announce() const;

 private:
  std::shared_ptr<GcsMapState> state_;
  std::unique_ptr<GcsWebServer> server_;  // declared last: stops before the state goes
};

}  // namespace skyroute::cli
