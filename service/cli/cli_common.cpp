#include "service/cli/cli_common.hpp"

#include <cmath>
#include <iostream>
#include <sstream>

#include <CLI/CLI.hpp>

#include "service/shipped_data.hpp"

namespace skyroute::cli {

void fail(const std::string& tool, int code, const std::string& message) {
  std::cerr << "skyroute " << tool << ": " << message << std::endl;
  throw CLI::RuntimeError(code);
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
