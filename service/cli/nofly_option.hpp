// `--nofly FILE.geojson`, shared by the commands that plan on a DEM (plan, mission, fleet): the
// no-fly zones every planner and the trajectory check keep out of (docs/nofly.md). The option
// overrides the configuration's terrain.nofly.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "service/daemon_config.hpp"
#include "service/no_fly_zone_data.hpp"
#include "service/world_model.hpp"

namespace CLI {
class App;
class Option;
}

namespace skyroute::cli {

CLI::Option* addNoFlyOption(CLI::App& cmd, std::optional<std::string>& path);

// Loads the zones of --nofly (else terrain.nofly; neither: none) into the world, dropping those
// whose window ended before now_s. A bad file fails with kExitBadInput naming the option, the
// file and the feature. Returns how many zones are in force.
std::size_t loadNoFlyZones(const std::string& tool, const std::optional<std::string>& option,
                           const DaemonConfig& config, WorldModel& world, double now_s);

// The zones of a GeoJSON file without a terrain, in WGS84 (to publish them, to show and export
// them at a ground station); every zone of the file, whatever its window. A bad file fails with
// kExitBadInput naming `what` (the option), the file and the feature.
std::vector<NoFlyZoneData> loadNoFlyZoneData(const std::string& tool, const std::string& what, const std::string& path);

}  // namespace skyroute::cli
