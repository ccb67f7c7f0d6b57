// skyrouted's configuration: a TOML file (every key optional; `skyrouted --print-config` prints
// them all with units and defaults), then command-line overrides. Unknown keys and values out of
// range are errors naming the key, so a typo never silently falls back to a default.
#pragma once

#include <string>

#include "planning/core/result.hpp"
#include "service/engine.hpp"
#include "service/world_model.hpp"

namespace skyroute {

struct DaemonConfig {
  // [terrain]
  std::string dem_path;                 // "" = the embedded default terrain
  std::string nofly_path;               // GeoJSON no-fly zones (service/no_fly_geojson.hpp); "" = none
  WorldModelOptions world;
  // [dds]
  int domain = 0;
  std::string service_id = "skyrouted";
  double heartbeat_period_s = 1.0;      // ServiceStatus period
  double flush_timeout_s = 0.5;         // on stop, writers wait this long (in all) for acknowledgements
  double startup_probe_s = 0.3;         // before serving, listen this long for another daemon with this service_id
  // [service]
  std::string state_dir;                // the state journal's folder (state_journal.hpp); "" = none
  // [security]
  std::string security_dir;             // DDS Security identity folder (scripts/make-pki.sh); "" = unsecured
  // [ros2]
  bool ros2_enabled = true;             // mirror trajectories on ROS 2 topics (dds/ros2_mirror.hpp)
  // [planning], [replanning], [bounds] (engine.bounds) and [obstacles] (engine.obstacles)
  EngineOptions engine;
  // [log]
  std::string log_level = "info";       // trace, debug, info, warn, error
  std::string log_format = "text";      // text or json (one object per line)
};

// Errors: kParseError naming the file and line, kInvalidArgument naming the key ("planning.seed").
Result<DaemonConfig> parseDaemonConfig(const std::string& toml_text, const std::string& source_name,
                                       DaemonConfig defaults = {});
Result<DaemonConfig> loadDaemonConfig(const std::string& path, DaemonConfig defaults = {});

// The configuration as a TOML document with every key, its unit and meaning in comments.
std::string describeDaemonConfig(const DaemonConfig& config);

}  // namespace skyroute
