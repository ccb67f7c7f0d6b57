// What a mission will cost before it is planned: a lower bound of its trajectory's duration and
// sample count from the points alone, and an estimate of the memory its planning takes, so a
// request that would exceed a bound is refused (kTooLarge) before any allocation proportional to
// it. Lower bound: every trajectory passes through the points, and the time allocation flies no
// stretch faster than v_ref, so it lasts at least (shortest route through the points) / v_ref.
#pragma once

#include <cstddef>
#include <cstdint>
#include <optional>
#include <vector>

#include <Eigen/Core>

#include "service/mission_types.hpp"

namespace skyroute {

struct FootprintOptions {
  double sample_dt_s = 0.2;             // published sample spacing
  TrajectorySizeBounds trajectory;      // the caps checked
  std::uint64_t leg_max_iterations = 0; // RRT* nodes of one leg at most (0: a time budget)
  double leg_budget_ms = 0.0;           // with no iteration budget, the nodes grown in this time
  double waypoint_spacing_m = 100.0;    // one spline knot per this much route
  int order_cells_per_axis = 200;       // the ordering grid
  double memory_share_bytes = 0.0;      // what one planning thread may use (0 = no memory guard)
};

struct RequestFootprint {
  double min_route_m = 0.0;      // shortest route through the points (straight lines)
  double min_duration_s = 0.0;   // min_route_m / v_ref
  std::size_t min_samples = 0;   // of the published trajectory, at least
  double memory_bytes = 0.0;     // planning estimate: samples, spline knots, RRT* tree, order grid
};

// points_m: begin, the mission points, end (ENU). fixed_order: the route visits them in this
// order; else any order (the bound is then the farthest detour through one point).
RequestFootprint estimateFootprint(const std::vector<Eigen::Vector3d>& points_m, bool fixed_order, double v_ref_mps,
                                   const FootprintOptions& options);

// kTooLarge naming the field to change ("limits.v_ref_mps" for the duration and sample caps,
// "points" for the memory share), with the numbers, or nothing.
std::optional<PlanError> checkFootprint(const RequestFootprint& footprint, double v_ref_mps,
                                        const FootprintOptions& options);

// The duration and sample caps on a built trajectory, before it is sampled ("trajectory").
std::optional<PlanError> checkTrajectorySize(double duration_s, double sample_dt_s, const TrajectorySizeBounds& bounds);

}  // namespace skyroute
