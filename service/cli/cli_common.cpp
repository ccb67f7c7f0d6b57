#include "service/cli/cli_common.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <regex>
#include <span>
#include <sstream>

#include <CLI/CLI.hpp>

#include "service/daemon_config.hpp"

namespace skyroute::cli {

void fail(const std::string& tool, int code, const std::string& message) {
  std::cerr << "skyroute " << tool << ": " << message << std::endl;
  throw CLI::RuntimeError(code);
}

std::string helpFooter(std::initializer_list<std::string> examples) {
  std::string text = examples.size() == 1 ? "Example:\n" : "Examples:\n";
  for (const std::string& line : examples) text += "  " + line + "\n";
  return text + "\n" + std::string(kExitCodeTable);
}

Result<MissionPointData> parseGeoTriple(const std::string& text, const std::string& field) {
  double v[3];
  std::istringstream in(text);
  std::string part;
  int n = 0;
  while (std::getline(in, part, ',')) {
    if (n == 3) return make_error(ErrorCode::kParseError, field, field + " '" + text + "' has more than 3 numbers (LAT,LON,ALT)");
    try {
      std::size_t used = 0;
      v[n] = std::stod(part, &used);
      if (part.find_first_not_of(" \t", used) != std::string::npos) throw std::invalid_argument(part);
    } catch (const std::exception&) {
      return make_error(ErrorCode::kParseError, field, field + " '" + text + "': '" + part + "' is not a number");
    }
    if (!std::isfinite(v[n])) return make_error(ErrorCode::kParseError, field, field + " '" + text + "': not finite");
    ++n;
  }
  if (n != 3) return make_error(ErrorCode::kParseError, field, field + " '" + text + "' must be LAT,LON,ALT (3 numbers)");
  return MissionPointData::wgs84(v[0], v[1], v[2]);
}

Result<GridCell> parseGridCell(const std::string& text, const std::string& field) {
  static const std::regex pattern(R"(\s*(-?\d{1,9})\s*,\s*(-?\d{1,9})\s*)");
  std::smatch m;
  if (!std::regex_match(text, m, pattern)) {
    return make_error(ErrorCode::kParseError, field, field + " '" + text + "' is not a cell X,Y (two integers: column, row)");
  }
  return GridCell{std::stoi(m[1].str()), std::stoi(m[2].str())};
}

std::string numberText(double v) {
  char text[32];
  std::snprintf(text, sizeof text, "%g", v);
  return text;
}

std::vector<std::string> splitList(const std::string& text) {
  std::vector<std::string> items;
  std::istringstream in(text);
  std::string item;
  while (std::getline(in, item, ';')) {
    const auto first = item.find_first_not_of(" \t");
    if (first == std::string::npos) continue;
    items.push_back(item.substr(first, item.find_last_not_of(" \t") - first + 1));
  }
  return items;
}

std::string lowerExtension(const std::string& path) {
  std::string ext = std::filesystem::path(path).extension().string();
  if (!ext.empty()) ext.erase(0, 1);
  for (char& c : ext) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return ext;
}

void checkOutputPath(const std::string& tool, const std::string& option, const std::string& path,
                     const std::vector<std::string>& formats) {
  if (path.empty()) return;
  const std::string ext = lowerExtension(path);
  if (std::find(formats.begin(), formats.end(), ext) == formats.end()) {
    std::string known;
    for (const auto& f : formats) known += (known.empty() ? "." : ", .") + f;
    fail(tool, kExitUsage, option + " " + path + ": unknown format '." + ext + "' (use " + known + ")");
  }
  const std::filesystem::path folder = std::filesystem::path(path).parent_path();
  if (!folder.empty() && !std::filesystem::is_directory(folder)) {
    fail(tool, kExitUsage, option + " " + path + ": the folder " + folder.string() + " does not exist");
  }
}

nlohmann::json readJsonFile(const std::string& tool, const std::string& option, const std::string& path) {
  std::ifstream in(path);
  if (!in) fail(tool, kExitBadInput, option + " " + path + ": cannot open the file");
  nlohmann::json j = nlohmann::json::parse(in, nullptr, false);
  if (j.is_discarded()) fail(tool, kExitBadInput, option + " " + path + ": not valid JSON");
  return j;
}

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

std::string demPathOf(const DaemonConfig& config) {
  return config.dem_path.empty() ? std::string(SKYROUTE_DEFAULT_DEM) : config.dem_path;
}

}  // namespace skyroute::cli
