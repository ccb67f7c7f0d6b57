// What the subcommands share beyond DDS: the exit-code table and failing with it, parsing
// "LAT,LON,ALT" arguments, and the shared configuration (--config FILE, --print-config: the same
// TOML keys, defaults and text as skyrouted's).
#pragma once

#include <optional>
#include <string>

#include "service/cli/exit_codes.hpp"
#include "service/daemon_config.hpp"
#include "service/mission_types.hpp"
#include "planning/core/result.hpp"

namespace CLI {
class App;
}

namespace skyroute::cli {

// "LAT,LON,ALT" in degrees and metres AMSL; field names the option in errors.
Result<MissionPointData> parseGeoTriple(const std::string& text, const std::string& field);

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
