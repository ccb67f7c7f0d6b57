// What the subcommands share beyond DDS: the exit-code table and failing with it, --help footers,
// parsing "LAT,LON,ALT", "X,Y" and ";"-separated lists, checking output paths before any work,
// reading JSON files, the vehicle-limit options, and the shared configuration (--config FILE,
// --print-config: the same TOML keys, defaults and text as skyrouted's).
#pragma once

#include <initializer_list>
#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "service/cli/exit_codes.hpp"
#include "service/mission_types.hpp"
#include "terrain/grid_layer.hpp"
#include "terrain/result.hpp"

namespace CLI {
class App;
class Option;
}

namespace skyroute {
struct DaemonConfig;  // service/daemon_config.hpp (not included: grid tools need no engine types)
}

namespace skyroute::cli {

// A --help footer: the examples, one a line, then the exit-code table.
std::string helpFooter(std::initializer_list<std::string> examples);

// "LAT,LON,ALT" in degrees and metres AMSL; field names the option in errors.
Result<MissionPointData> parseGeoTriple(const std::string& text, const std::string& field);
// "X,Y": a grid cell (column, row); field names the option in errors.
Result<GridCell> parseGridCell(const std::string& text, const std::string& field);
// A number as --help shows a default ("%g": 30, 0.2, 1e+06).
std::string numberText(double v);
// The items of a list separated by ';', blanks around items trimmed, empty items dropped.
std::vector<std::string> splitList(const std::string& text);

// Each item of a ';'-separated list option through `parse`, named "option[i]" in errors; a bad
// item fails with kExitUsage.
template <class T>
std::vector<T> parseListOption(const std::string& tool, const std::string& option, const std::string& text,
                               Result<T> (*parse)(const std::string& item, const std::string& field)) {
  std::vector<T> values;
  const std::vector<std::string> items = splitList(text);
  for (std::size_t i = 0; i < items.size(); ++i) {
    auto value = parse(items[i], option + "[" + std::to_string(i) + "]");
    if (!value) fail(tool, kExitUsage, value.error().message);
    values.push_back(std::move(*value));
  }
  return values;
}

// The extension of a path, lower case, without the dot ("" when none).
std::string lowerExtension(const std::string& path);
// An output path, checked before any work: an extension among `formats` and a folder that exists.
// Fails with kExitUsage naming the option. An empty path passes (the output was not asked for).
void checkOutputPath(const std::string& tool, const std::string& option, const std::string& path,
                     const std::vector<std::string>& formats);
// A JSON file; fails with kExitBadInput naming the option and the file.
nlohmann::json readJsonFile(const std::string& tool, const std::string& option, const std::string& path);

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

// The DEM to load: the configuration's terrain.dem, or the embedded default terrain.
std::string demPathOf(const DaemonConfig& config);

}  // namespace skyroute::cli
