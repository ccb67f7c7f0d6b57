#include "service/cli/nofly_option.hpp"

#include <algorithm>
#include <iostream>

#include <CLI/CLI.hpp>

#include "service/cli/exit_codes.hpp"
#include "service/no_fly_geojson.hpp"

namespace skyroute::cli {

CLI::Option* addNoFlyOption(CLI::App& cmd, std::optional<std::string>& path) {
  return cmd.add_option("--nofly", path,
                 "GeoJSON no-fly zones (Polygon/MultiPolygon, floor_m and ceiling_m AMSL; docs/nofly.md); "
                 "config terrain.nofly");
}

std::size_t loadNoFlyZones(const std::string& tool, const std::optional<std::string>& option,
                           const DaemonConfig& config, WorldModel& world, double now_s) {
  const std::string path = option ? *option : config.nofly_path;
  if (path.empty()) return 0;
  auto zones = loadNoFlyGeoJson(path, world.frame(), &world.terrain());
  if (!zones.ok()) fail(tool, kExitBadInput, (option ? "--nofly " : "terrain.nofly ") + zones.error().describe());
  world.setNoFlyZones(std::move(*zones));
  world.expire(now_s);
  const std::size_t count = world.noFlyZones().size();
  std::cerr << "no-fly zones: " << count << " in force from " << path << std::endl;
  return count;
}

std::vector<NoFlyZoneData> loadNoFlyZoneData(const std::string& tool, const std::string& what,
                                             const std::string& path) {
  auto parse = [&](const LocalFrame& frame) {
    auto zones = loadNoFlyGeoJson(path, frame);
    if (!zones.ok()) fail(tool, kExitBadInput, what + " " + zones.error().describe());
    return std::move(*zones);
  };
  // Any frame carries a ring to ENU and back to the same latitudes and longitudes; one anchored on
  // the zones keeps the geometry checks free of the projection's distortion far from its centre.
  const LocalFrame anywhere = LocalFrame::create(0.0, 0.0).value();
  std::vector<NoFlyZone> zones = parse(anywhere);
  if (zones.empty()) return {};
  const GeoPoint first = anywhere.toGeo(Eigen::Vector3d(zones[0].ring_m[0].x(), zones[0].ring_m[0].y(), 0.0));
  const LocalFrame near = LocalFrame::create(std::clamp(first.lat_deg, -89.0, 89.0), first.lon_deg).value();
  std::vector<NoFlyZoneData> out;
  for (const NoFlyZone& zone : parse(near)) out.push_back(toNoFlyZoneData(zone, near));
  return out;
}

}  // namespace skyroute::cli
