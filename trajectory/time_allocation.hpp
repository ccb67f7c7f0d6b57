// Time allocation, its own step before the spline solve (as in mav_trajectory_generation).
// - kConstantSpeed: seed 003 eq. 3, T_j = |P_j - P_{j-1}| / V_ref.
// - kTrapezoidal: the speed along the polyline follows a trapezoidal profile per segment: it
//   accelerates and brakes at a share of the acceleration limit, cruises at V_ref (lowered on
//   segments steeper than the climb or descent limit allows), starts and ends at the given speeds
//   (rest by default), and slows before sharp turns to the speed at which the turn's lateral
//   acceleration stays within that share.
// Extra waypoints: seed 003 section 3-1 inserts waypoints between the original ones at the LOSPO
// spacing so that the curve stays close to the checked straight path.
#pragma once

#include <cstddef>
#include <string_view>
#include <vector>

#include <Eigen/Core>
#include <Eigen/Geometry>

#include "planning/core/result.hpp"
#include "trajectory/vehicle_limits.hpp"

namespace skyroute {

enum class TimeAllocationMethod { kConstantSpeed, kTrapezoidal };
std::string_view to_string(TimeAllocationMethod method);

struct TimeAllocationOptions {
  TimeAllocationMethod method = TimeAllocationMethod::kTrapezoidal;
  // Share of max_accel_mps2 the trapezoids (and the turn speeds) use, in (0, 1]: the smooth spline
  // through the profile peaks at about 3x a trapezoid's constant acceleration. Measured on 20 random
  // LOSPO-like paths: 0.3 keeps every spline within the limit with no repair; the default 0.5
  // leaves a few segments over it for the repair pass to stretch, and flies ~18% faster overall.
  double accel_fraction = 0.5;
  double start_speed_mps = 0.0;  // speed at the first waypoint (>= 0)
  double end_speed_mps = 0.0;    // speed at the last waypoint (>= 0)
};

// Segment durations (seconds), one per consecutive pair of waypoints. Errors name the field:
// "waypoints", "waypoints[i]" (NaN, or same place as the previous one), "limits.*",
// "time_allocation.*".
Result<std::vector<double>> allocateTimes(const std::vector<Eigen::Vector3d>& waypoints, const VehicleLimits& limits,
                                          const TimeAllocationOptions& options = {});

// Checks shared by every entry point: at least 2 waypoints, finite, no two consecutive closer than
// min_separation_m.
Status validateWaypoints(const std::vector<Eigen::Vector3d>& waypoints, double min_separation_m = 1e-3);

struct DensifiedPath {
  std::vector<Eigen::Vector3d> points;        // original and extra waypoints, in order
  std::vector<std::size_t> original_indices;  // position in `points` of each original waypoint
};

// Splits each leg into ceil(length / spacing_m) equal pieces; spacing_m <= 0 keeps the path.
DensifiedPath densifyWaypoints(const std::vector<Eigen::Vector3d>& waypoints, double spacing_m);

// Speed (m/s) the trapezoidal allocation allows at each waypoint (exposed for tests and reports).
std::vector<double> waypointSpeedLimits(const std::vector<Eigen::Vector3d>& waypoints, const VehicleLimits& limits,
                                        const TimeAllocationOptions& options);

}  // namespace skyroute
