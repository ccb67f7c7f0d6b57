// What the subcommands share beyond DDS: the parsing and output helpers (cli_parse.hpp), the
// vehicle-limit options, and the shared configuration (--config FILE, --print-config: the same
// TOML keys, defaults and text as skyrouted's).
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "planning/core/result.hpp"
#include "service/cli/cli_parse.hpp"
#include "service/daemon_config.hpp"
#include "service/mission_types.hpp"

namespace CLI {
class App;
class Option;
}

namespace skyroute::cli {

// The vehicle limits a command line may set; each overrides its field of VehicleLimitsData (the
// mission file's, or the defaults) only when given.
struct VehicleLimitArgs {
  std::optional<double> clearance_m, ceiling_m;  // the flight band
  std::optional<double> vref_mps, max_speed_mps, max_accel_mps2, max_climb_mps, max_descent_mps, min_turn_radius_m;
};
// --clearance-m and --ceiling-m; `note` ends their help (e.g. what they mean on a grid).
std::vector<CLI::Option*> addFlightBandOptions(CLI::App& cmd, VehicleLimitArgs& args, const std::string& note = "");
// --vref-mps, --max-speed-mps, --max-accel-mps2, --max-climb-mps, --max-descent-mps, --min-turn-radius-m.
std::vector<CLI::Option*> addVehicleDynamicsOptions(CLI::App& cmd, VehicleLimitArgs& args);
void applyVehicleLimits(const VehicleLimitArgs& args, VehicleLimitsData& limits);
// The option that sets a request's limit field ("limits.max_speed_mps" -> "--max-speed-mps") when
// it was given, "" otherwise (or for any other field).
std::string givenLimitOption(const VehicleLimitArgs& args, const std::string& field);
// A limit field as messages name it: the option when given, else the field with where its value
// came from ("limits.v_ref_mps (default; --vref-mps sets it)"); "" for any other field.
std::string limitSource(const VehicleLimitArgs& args, const std::string& field);

// A subcommand's --config FILE and --print-config.
struct ConfigArgs {
  std::string path;
  bool print = false;
};
void addConfigOptions(CLI::App& cmd, ConfigArgs& args);

// The configuration from --config (defaults without one). An unreadable file fails with
// kExitBadInput naming it, an invalid key with kExitBadInput naming the file and the key.
DaemonConfig loadConfig(const std::string& tool, const ConfigArgs& args);
// With --print-config: prints the configuration, as skyrouted --print-config does, and returns
// true (the caller then stops).
bool printConfigIfAsked(const ConfigArgs& args, const DaemonConfig& config);

// The DEM to load: the configuration's terrain.dem, or the embedded default terrain (shipped data,
// service/shipped_data.hpp). Without either, fails with kExitBadInput naming the folders searched.
std::string demPathOf(const std::string& tool, const DaemonConfig& config);

}  // namespace skyroute::cli
