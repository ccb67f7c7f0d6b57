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
  double flush_timeout_s = 0.5;         // on stop: the engine stops and writers are acknowledged by then
  double startup_probe_s = 0.3;         // before serving, listen this long for another daemon with this service_id
  // Hot standby (docs/dds.md): the ownership strength of the trajectory, status and heartbeat
  // writers in each role (the primary's must be the higher), and their liveliness lease.
  std::int64_t primary_strength = 100;
  std::int64_t standby_strength = 10;
  double liveliness_lease_s = 0.5;      // readers hand a silent writer's instances over after this
  // [service]
  std::string role = "primary";         // primary or standby (hot standby of the primary's service_id)
  std::string state_dir;                // the state journal's folder (state_journal.hpp); "" = none
  // Daemons with one non-empty shard group on a domain split the vehicles (shard_router.hpp);
  // "" = not sharded.
  std::string shard_group;
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

// The ownership strength of this daemon's owned writers: its role's.
std::int32_t ownershipStrength(const DaemonConfig& config);
// The keys that relate to each other: kInvalidArgument naming the key (dds.primary_strength not
// above dds.standby_strength; service.role neither primary nor standby; service.shard_group with
// service.role standby). parseDaemonConfig checks
// these too; the daemon checks again after its command-line overrides (--role).
Status validateDaemonConfig(const DaemonConfig& config);

// Errors: kParseError naming the file and line, kInvalidArgument naming the key ("planning.seed").
Result<DaemonConfig> parseDaemonConfig(const std::string& toml_text, const std::string& source_name,
                                       DaemonConfig defaults = {});
Result<DaemonConfig> loadDaemonConfig(const std::string& path, DaemonConfig defaults = {});

// The configuration as a TOML document with every key, its unit and meaning in comments.
std::string describeDaemonConfig(const DaemonConfig& config);

}  // namespace skyroute
