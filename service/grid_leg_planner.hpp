// Global planners on the grid layer at the flight band (seed 004): HAB-PP or Improved HAB-PP finds an any-angle path for each leg on a grid of the terrain's flight
// band; the path is lifted to 3D and goes through the same trajectory stage as RRT* + LOSPO paths
// (buildRouteTrajectory). Lifting: the vehicle climbs (or descends) over its leg's start to the
// band altitude, follows the grid path's vertices at that altitude, and changes altitude over the
// leg's end; where a straight climb or descent to the next vertex is clear, it is used instead.
#pragma once

#include <cstdint>
#include <memory>
#include <optional>
#include <string_view>
#include <vector>

#include <Eigen/Core>

#include "planning/colony/hab_pp.hpp"
#include "planning/core/termination.hpp"
#include "service/route_planner.hpp"
#include "terrain/collision_world.hpp"

namespace skyroute {

// The grid planners; planner_registry.hpp gives their names.
enum class GridGlobalPlanner { kHabPp, kHabPpRrt };

struct GridLegOptions {
  int max_cells_per_axis = 160;  // the grid's cell edge is the terrain extent / this (at least the DEM cell)
  double band_margin_m = 200.0;  // the band's top is this far above the leg's higher end (under the ceiling)
  // HAB-PP output stage: windowed re-planning of this many segments (HabPpParameters::
  // output_window_segments, whose default this is); 0: off.
  int output_window_segments = HabPpParameters{}.output_window_segments;
  // Wall-clock cap of one leg's search, seconds (0 = none): the colony stops with the best path
  // it has, and the leg says it was capped.
  double leg_time_cap_s = 0.0;
  // A fixed wing's path angles (RouteOptions::max_path_climb_deg, max_path_descent_deg; 0 = no
  // limit). The lifting climbs and descends over a leg's ends as steeply as the terrain needs,
  // so a lifted path steeper than these is refused (kInvalidArgument, field "planner") rather
  // than handed to a trajectory stage that cannot fly it.
  double max_path_climb_deg = 0.0;
  double max_path_descent_deg = 0.0;
};

// points_m: the route in visiting order (ENU). Returns legs with 3D paths and the joined waypoints
// (route.built empty). Errors name the leg ("legs[i]") or point ("points[i]"): kUnreachable when
// the planner finds no path or the lifted path is blocked, kCancelled / kTimeout from `stop`.
Result<PlannedRoute> planGridRoutePaths(std::shared_ptr<const CollisionWorld> world,
                                        const std::vector<Eigen::Vector3d>& points_m, GridGlobalPlanner planner,
                                        const GridLegOptions& options, std::uint64_t seed,
                                        const TerminationCondition& stop = {},
                                        std::optional<ObstacleSnapshot> snapshot = std::nullopt);

}  // namespace skyroute
