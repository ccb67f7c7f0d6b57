#include "service/cli/cli_common.hpp"

#include <algorithm>
#include <iostream>
#include <span>
#include <sstream>

#include <CLI/CLI.hpp>

#include "service/shipped_data.hpp"

namespace skyroute::cli {

namespace {

// One vehicle-limit option: its spelling, where the command line keeps it, the request field it
// sets (named as the mission JSON names it) and its help.
struct LimitOption {
  const char* name;
  std::optional<double> VehicleLimitArgs::*arg;
  double VehicleLimitsData::*field;
  const char* key;
  const char* help;
};

constexpr LimitOption kFlightBand[] = {
    {"--clearance-m", &VehicleLimitArgs::clearance_m, &VehicleLimitsData::min_clearance_agl_m,
     "min_clearance_agl_m", "Minimum height above ground, m"},
    {"--ceiling-m", &VehicleLimitArgs::ceiling_m, &VehicleLimitsData::ceiling_amsl_m, "ceiling_amsl_m",
     "Highest altitude, m AMSL"},
};
constexpr LimitOption kDynamics[] = {
    {"--vref-mps", &VehicleLimitArgs::vref_mps, &VehicleLimitsData::v_ref_mps, "v_ref_mps", "Cruise speed V_ref, m/s"},
    {"--max-speed-mps", &VehicleLimitArgs::max_speed_mps, &VehicleLimitsData::max_speed_mps, "max_speed_mps",
     "Speed limit, m/s"},
    {"--max-accel-mps2", &VehicleLimitArgs::max_accel_mps2, &VehicleLimitsData::max_accel_mps2, "max_accel_mps2",
     "Acceleration limit, m/s^2"},
    {"--max-climb-mps", &VehicleLimitArgs::max_climb_mps, &VehicleLimitsData::max_climb_rate_mps, "max_climb_rate_mps",
     "Climb rate limit, m/s"},
    {"--max-descent-mps", &VehicleLimitArgs::max_descent_mps, &VehicleLimitsData::max_descent_rate_mps,
     "max_descent_rate_mps", "Descent rate limit, m/s"},
    {"--min-turn-radius-m", &VehicleLimitArgs::min_turn_radius_m, &VehicleLimitsData::min_turn_radius_m,
     "min_turn_radius_m", "Minimum turn radius, m; 0 = none"},
};

constexpr std::span<const LimitOption> kLimitTables[] = {kFlightBand, kDynamics};

const LimitOption* findLimitOption(const std::string& field) {
  for (std::span<const LimitOption> table : kLimitTables) {
    for (const LimitOption& o : table) {
      if (field == std::string("limits.") + o.key) return &o;
    }
  }
  return nullptr;
}

std::vector<CLI::Option*> addLimitOptions(CLI::App& cmd, VehicleLimitArgs& args, std::span<const LimitOption> options,
                                          const std::string& note) {
  const VehicleLimitsData defaults;
  std::vector<CLI::Option*> added;
  for (const LimitOption& o : options) {
    // The default is shown, not set: an option left out keeps the mission file's value.
    added.push_back(cmd.add_option(o.name, args.*o.arg, std::string(o.help) + " (limits." + o.key + ")" + note)
                        ->default_str(numberText(defaults.*o.field)));
  }
  return added;
}

}  // namespace

std::vector<CLI::Option*> addFlightBandOptions(CLI::App& cmd, VehicleLimitArgs& args, const std::string& note) {
  return addLimitOptions(cmd, args, kFlightBand, note);
}
std::vector<CLI::Option*> addVehicleDynamicsOptions(CLI::App& cmd, VehicleLimitArgs& args) {
  return addLimitOptions(cmd, args, kDynamics, "");
}

void applyVehicleLimits(const VehicleLimitArgs& args, VehicleLimitsData& limits) {
  for (std::span<const LimitOption> table : kLimitTables) {
    for (const LimitOption& o : table) {
      if (const auto& given = args.*o.arg) limits.*o.field = *given;
    }
  }
}

std::string givenLimitOption(const VehicleLimitArgs& args, const std::string& field) {
  const LimitOption* o = findLimitOption(field);
  return o && (args.*o->arg).has_value() ? o->name : "";
}

std::string limitSource(const VehicleLimitArgs& args, const std::string& field) {
  const LimitOption* o = findLimitOption(field);
  if (o == nullptr) return "";
  if ((args.*o->arg).has_value()) return o->name;
  return field + " (default; " + o->name + " sets it)";
}

void addConfigOptions(CLI::App& cmd, ConfigArgs& args) {
  cmd.add_option("--config", args.path,
                 "TOML configuration file: the same keys and defaults as skyrouted (--print-config lists them)");
  cmd.add_flag("--print-config", args.print,
               "Print the effective configuration as TOML (the same text as skyrouted --print-config) and exit");
}

DaemonConfig loadConfig(const std::string& tool, const ConfigArgs& args) {
  if (args.path.empty()) return DaemonConfig{};
  auto loaded = loadDaemonConfig(args.path);
  if (!loaded.ok()) fail(tool, kExitBadInput, "--config " + loaded.error().describe());
  return std::move(*loaded);
}

bool printConfigIfAsked(const ConfigArgs& args, const DaemonConfig& config) {
  if (!args.print) return false;
  std::cout << describeDaemonConfig(config);
  return true;
}

std::string demPathOf(const std::string& tool, const DaemonConfig& config) {
  if (!config.dem_path.empty()) return config.dem_path;
  auto shipped = defaultTerrainPath();
  if (!shipped) fail(tool, kExitBadInput, shipped.error().describe());
  return *shipped;
}

}  // namespace skyroute::cli
