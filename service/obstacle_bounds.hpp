// How big, how fast and where an obstacle may be, relative to the terrain the service plans on.
// An update outside these bounds describes nothing a vehicle could fly around (a sphere of radius
// 1e300 m covers every point; a speed of 1e300 m/s sweeps the map between two checks), so it is
// refused instead of making every later request fail "inside an obstacle".
//   L = the DEM's longer horizontal side, k = extent_factor:
//   - every size component the shape uses is at most k L;
//   - every position (centre, back-and-forth ends) lies within the DEM's east/north bounds grown
//     by k L on each side, and between its lowest height - k L and its highest height + k L;
//   - a speed (back-and-forth speed_mps, constant velocity's magnitude) is at most max_speed_mps.
#pragma once

#include <cstddef>
#include <optional>

#include "service/mission_types.hpp"
#include "terrain/heightfield.hpp"

namespace skyroute {

struct ObstacleBounds {
  double max_speed_mps = 400.0;  // faster than anything that flies low over terrain
  double extent_factor = 1.0;    // k above
  // Obstacles in force at most: each costs memory and every replanning check, so a feed of ever
  // new ids is refused beyond this instead of growing the daemon (updates of known ids go on).
  std::size_t max_obstacles = 4096;
};

// kLimitsOutOfRange naming the field ("size_m.x", "position_enu_m.z", "to_enu_m.x", "speed_mps",
// "velocity_enu_mps") with the bound and the value; nothing for a removal.
std::optional<PlanError> checkObstacleBounds(const ObstacleUpdateData& update, const Heightfield& terrain,
                                             const ObstacleBounds& bounds);

}  // namespace skyroute
