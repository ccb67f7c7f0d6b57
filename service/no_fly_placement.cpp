#include "service/no_fly_placement.hpp"

#include <cmath>
#include <vector>

#include "service/mission_point_check.hpp"

namespace skyroute {

std::optional<std::string> zoneOffTerrainReason(const NoFlyZone& zone, const Heightfield& terrain) {
  if (zone.touchesRectangle(terrain.boundsEn())) return std::nullopt;
  // The ring back in latitude and longitude, exchanged, and into the frame again.
  std::vector<double> lon, lat;
  lon.reserve(zone.ring_m.size());
  lat.reserve(zone.ring_m.size());
  for (const Eigen::Vector2d& v : zone.ring_m) {
    lon.push_back(v.x());
    lat.push_back(v.y());
  }
  terrain.frame().eastNorthToLonLat(lon.data(), lat.data(), lon.size());
  bool exchangeable = true;
  for (double lon_deg : lon) exchangeable = exchangeable && std::abs(lon_deg) <= 90.0;  // the latitude it would be
  if (exchangeable) {
    NoFlyZone swapped = zone;
    std::vector<double> east = lat, north = lon;
    terrain.frame().lonLatToEastNorth(east.data(), north.data(), east.size());
    for (std::size_t i = 0; i < swapped.ring_m.size(); ++i) swapped.ring_m[i] = Eigen::Vector2d(east[i], north[i]);
    if (swapped.touchesRectangle(terrain.boundsEn())) {
      return "lies outside the DEM, but on it with latitude and longitude exchanged: latitude and longitude may be "
             "swapped (the DEM covers " +
             describe(terrainGeoBounds(terrain)) + ")";
    }
  }
  return "lies entirely outside the DEM (" + describe(terrainGeoBounds(terrain)) + "): it would keep nothing out";
}

}  // namespace skyroute

namespace skyroute {

Result<NoFlyZone> placeNoFlyZone(const NoFlyZoneData& data, const Heightfield& terrain) {
  auto zone = toNoFlyZone(data, terrain.frame());
  if (!zone.ok()) return zone;
  if (auto off = zoneOffTerrainReason(*zone, terrain)) {
    return make_error(ErrorCode::kInvalidArgument, "ring", "zone '" + data.zone_id + "': " + *off);
  }
  return zone;
}

}  // namespace skyroute
