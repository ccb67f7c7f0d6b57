// A no-fly zone as it travels (DDS, ground stations): WGS84 ring, heights AMSL, UTC window, keyed
// by an id. The planners' NoFlyZone (terrain/no_fly_zone.hpp) is the same zone in a terrain's ENU
// frame; these convert between the two.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "planning/core/result.hpp"
#include "terrain/local_frame.hpp"
#include "terrain/no_fly_zone.hpp"

namespace skyroute {

struct NoFlyZoneData {
  std::string zone_id;
  std::vector<GeoPoint> ring;          // latitude and longitude (alt_amsl_m unused)
  double floor_amsl_m = 0.0;
  double ceiling_amsl_m = 0.0;
  std::int64_t valid_from_utc_ns = 0;  // 0 = always
  std::int64_t valid_until_utc_ns = 0; // 0 = until lifted
  bool remove = false;                 // the zone is lifted (other fields ignored)
};

// The zone in the frame, named by its id, checked (checkNoFlyZone): errors kInvalidArgument with
// the member as the field ("ring" for the ring's faults: more than kMaxNoFlyZoneVertices vertices,
// counted first, a self-intersection, zero area; "ring[3]" for a vertex out of -90..90 /
// -180..180) and a message that names the zone ("zone 'tower': ..."); the heights and window
// name the zone as the field.
Result<NoFlyZone> toNoFlyZone(const NoFlyZoneData& data, const LocalFrame& frame);
// The zone back in WGS84 and AMSL, its name as the id.
NoFlyZoneData toNoFlyZoneData(const NoFlyZone& zone, const LocalFrame& frame);

}  // namespace skyroute
