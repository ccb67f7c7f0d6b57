// Where a fleet vehicle below its flight band (climbing over its begin, descending onto its end)
// steps to so that an obstacle coming over it goes by: a hover in place stays on the track of an
// obstacle that reaches the altitudes the vehicle passes through (a column reaches them all), and
// the band's detours only start once it is up there.
#pragma once

#include <vector>

#include <Eigen/Core>

#include "terrain/obstacle.hpp"

namespace skyroute {

// How far an obstacle reaches from its centre across (horizontally) and up or down.
double horizontalReachM(const Obstacle& o);
double verticalReachM(const Obstacle& o);

// A place to step to at the vehicle's altitude; with hold_until_s (world time) > 0, held there
// until the obstacle has gone by.
struct StepAside {
  Eigen::Vector2d xy;
  double hold_until_s = 0.0;
};

// The places for a vehicle at p_m (below band_m, at world time at_s) off the track of every
// obstacle that reaches the altitudes between p_m and the band and comes over p_m: across a
// moving obstacle's track, beyond its horizontal reach by room_m, the side p_m is on first, then
// the other (each without a hold, then held until the obstacle is room_m past p_m); straight away
// from a fixed obstacle's axis. Obstacles whose track passes by, or that have gone by, give none.
std::vector<StepAside> stepAsidesFrom(const std::vector<Obstacle>& obstacles, const Eigen::Vector3d& p_m,
                                      double band_m, double room_m, double at_s);

}  // namespace skyroute
