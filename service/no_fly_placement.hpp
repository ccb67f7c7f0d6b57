// Where a no-fly zone lies against the terrain it is given for. A zone that lies entirely off the
// DEM keeps nothing out of any plan (no route is planned there), so accepting it would only say
// "in force" and do nothing: it is refused, saying where the DEM is, or that latitude and
// longitude look swapped when the zone with them exchanged does lie on the DEM (as the mission
// point check says of points, mission_point_check.hpp). A zone partly on the DEM is on it.
#pragma once

#include <optional>
#include <string>

#include "planning/core/result.hpp"
#include "service/no_fly_zone_data.hpp"
#include "terrain/heightfield.hpp"
#include "terrain/no_fly_zone.hpp"

namespace skyroute {

// Why the zone (in the terrain's ENU frame, its ring checked) is off the terrain: "lies entirely
// outside the DEM (lat 46.9..47.0, lon 15.0..15.1)" or "lies outside the DEM, but on it with
// latitude and longitude exchanged: ..."; nullopt when some of it lies over the DEM. O(n).
std::optional<std::string> zoneOffTerrainReason(const NoFlyZone& zone, const Heightfield& terrain);

// A published zone on this terrain: converted and checked (toNoFlyZone), then refused
// (kInvalidArgument, field "ring", the message naming the zone) when it lies entirely off the DEM.
Result<NoFlyZone> placeNoFlyZone(const NoFlyZoneData& data, const Heightfield& terrain);

}  // namespace skyroute
