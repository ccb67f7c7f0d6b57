// Stops at knots: a trajectory that comes to rest (zero velocity, acceleration and jerk) at some of
// its interior knots. Why: the spline must pass a mission point exactly (a fixed knot); at a sharp
// corner flown at speed it swings wide or breaks the acceleration or turn limits, and when no
// rounding fits, coming to rest there always works: the two sides become separate rest-to-rest
// pieces, and a rest-to-rest piece can always be slowed into the limits (a uniform stretch by k
// scales its speeds by 1/k and its accelerations by 1/k^2) with no corner flown at speed.
// The time allocation and the minimum-snap solve below work piece by piece between the stops.
#pragma once

#include <cstddef>
#include <optional>
#include <string_view>
#include <vector>

#include <Eigen/Core>

#include "planning/core/result.hpp"
#include "trajectory/segment.hpp"
#include "trajectory/spline7.hpp"
#include "trajectory/time_allocation.hpp"
#include "trajectory/vehicle_limits.hpp"

namespace skyroute {

// What the trajectory does at its interior fixed waypoints (a route's mission points).
// kPass: flies through at the speed the corner allows (the time allocation slows before a turn to
//   keep its lateral acceleration within the limit; a turn tighter than the vehicle's radius is
//   rounded by a pass-through), and comes to rest there only when that cannot be made to fly.
// kStop: comes to rest at every one.
enum class FixedWaypointMode { kPass, kStop };
std::string_view to_string(FixedWaypointMode mode);
std::optional<FixedWaypointMode> parseFixedWaypointMode(std::string_view text);

// Segment durations as allocateTimes gives them, with the vehicle at rest at each stop knot
// (indices into `knots`, interior ones; any order, duplicates ok). Errors as allocateTimes.
Result<std::vector<double>> allocateTimesWithStops(const std::vector<Eigen::Vector3d>& knots,
                                                   const VehicleLimits& limits, const TimeAllocationOptions& options,
                                                   const std::vector<std::size_t>& stop_knots);

// The minimum-snap spline through `knots` with velocity, acceleration and jerk zero at each stop
// knot: every piece between stops is solved on its own (the boundary's start on the first piece,
// its end on the last). Errors as solveMinimumSnapSpline.
Result<std::vector<Segment>> solveMinimumSnapSplineWithStops(const std::vector<Eigen::Vector3d>& knots,
                                                             const std::vector<double>& durations_s,
                                                             const SplineBoundary& boundary,
                                                             const std::vector<std::size_t>& stop_knots);

}  // namespace skyroute
