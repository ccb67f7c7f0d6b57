// The leg pipeline of seed 003: for each pair of consecutive route points, RRT* in a corridor
// around the leg (grown when the terrain's way round lies beyond it), then LOSPO; the legs' waypoints joined into one minimum-snap degree-7 trajectory
// that is checked (limits, terrain, obstacles) and repaired. Used by `skyroute plan` and the engine.
#pragma once

#include <cstdint>
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "planning/core/termination.hpp"
#include "planning/sampling/lospo.hpp"
#include "planning/sampling/rrt_star.hpp"
#include "planning/sampling/rrt_tree_reuse.hpp"
#include "planning/sampling/world_motion_validator.hpp"
#include "terrain/collision_world.hpp"
#include "trajectory/trajectory_builder.hpp"

namespace skyroute {

// The trajectory stage's options for a route: a route whose legs are clear always gets a
// trajectory (as the last resort it rests at the legs' corners).
inline TrajectoryOptions routeTrajectoryOptions() {
  TrajectoryOptions options;
  options.stop_at_corners_as_last_resort = true;
  return options;
}

struct RouteOptions {
  std::uint64_t seed = 1;                // leg i plans with seed + i
  double leg_budget_ms = 200.0;          // RRT* time per leg; 0 = no deadline (then set iterations)
  std::uint64_t leg_max_iterations = 0;  // RRT* iteration budget per leg; 0 = none. With a budget
                                         // and no deadline the route is bit-identical per seed.
  double corridor_margin_m = 3000.0;     // RRT* samples within this distance of the leg's box first;
                                         // when no path lies there, round the terrain's shortest way
                                         // for the leg, then the whole terrain (each with the budget)
  RrtStarOptions rrt;                    // seed and budget fields are set per leg
  LospoOptions lospo;
  TrajectoryOptions trajectory = routeTrajectoryOptions();
  // Replanning: moving obstacles frozen at this world time with a margin for planning, and the
  // trajectory re-checked against their motion with the trajectory starting at this world time.
  std::optional<ObstacleSnapshot> snapshot;
  std::optional<double> trajectory_start_world_s;
  // With a start time, moving obstacles are checked in time up to this far into the trajectory;
  // beyond it only terrain and fixed obstacles (the replanning loop looks again as time goes on).
  double moving_check_horizon_s = 60.0;
  // RRT* tree reuse (replanning, seed 003 section 3-2): the first leg grows this tree instead of
  // a new one, re-rooted at points_m[0] against the leg's corridor and obstacles (rerootTree:
  // only what that point still reaches through valid motions is kept). The kept nodes count
  // against the leg's iteration budget: the search draws the rest, and at least
  // kReusedLegMinNewShare of it. nullptr = a new tree.
  std::shared_ptr<const RrtTree> first_leg_tree;
  TreeReuseOptions tree_reuse;  // its max_nodes also caps the tree kept in RouteLeg::tree
  // Keep the first leg's grown RRT* tree (its cheapest tree_reuse.max_nodes nodes) in
  // RouteLeg::tree, for a later replan's first_leg_tree. Not when first_leg_tree is given and the
  // straight first leg is valid: no tree is grown then, and the caller keeps the one it has.
  bool keep_first_leg_tree = false;
  // A fixed wing's legs climb and descend at most this steeply (degrees; 0 = any slope):
  // withVehiclePathAngles sets them from the vehicle's limits.
  double max_path_climb_deg = 0.0;
  double max_path_descent_deg = 0.0;
};

// Share of a fixed wing's path angle limits its legs' straight pieces may use: the curve through
// them steepens a little where it bends from one slope to the next.
inline constexpr double kPathAngleShare = 0.9;

// The options with the legs' path angles of this vehicle (a fixed wing's; a multirotor's: any).
RouteOptions withVehiclePathAngles(RouteOptions options, const VehicleLimits& limits);

// Share of a leg's iteration budget a search from a reused tree still draws, however many nodes
// it kept: the kept nodes were sampled for another start and goal.
inline constexpr double kReusedLegMinNewShare = 0.25;

struct RouteLeg {
  std::size_t from_point = 0;
  std::size_t to_point = 0;
  RrtStarResult rrt;
  // The leg's wall-clock cap stopped its search before its iteration budget: the path depends on
  // the machine's speed, so the plan is no longer reproducible from the seed alone.
  bool time_capped = false;
  double lospo_length_m = 0.0;
  std::vector<Eigen::Vector3d> path_m;  // after LOSPO
  // The leg's RRT* tree (RouteOptions::keep_first_leg_tree, first leg only), shared read-only.
  std::shared_ptr<const RrtTree> tree;
  // Nodes of RouteOptions::first_leg_tree the leg's search started with (0: a new tree).
  std::size_t reused_tree_nodes = 0;
  double tree_reuse_ms = 0.0;  // re-rooting it (wall time, not in rrt.time_s)
  double start_s = 0.0;                 // trajectory time at from_point
  double end_s = 0.0;                   // trajectory time at to_point
};

// A route point where the trajectory comes to rest (TrajectoryOptions::fixed_waypoint_mode).
struct RoutePointStop {
  std::size_t point = 0;  // index into the route's points
  std::string reason;     // the stop mode, or why the trajectory could not be made to fly without it
};

struct PlannedRoute {
  std::vector<RouteLeg> legs;
  std::vector<RoutePointStop> point_stops;  // by point
  // Per leg (when any): how many of its corners, not route points, the trajectory rests at (the
  // trajectory stage's last resort, knot_stops.hpp), and why.
  std::vector<std::size_t> leg_corner_stops;
  std::string corner_stop_reason;
  std::vector<Eigen::Vector3d> waypoints_m;  // the legs' LOSPO paths joined
  BuiltTrajectory built;
  double planning_ms = 0.0;
};

// points_m: the route's points in visiting order (at least two), ENU metres.
// Errors name the offending point ("points[i]") or leg ("legs[i]"): kOutsideMap, kOccupied,
// kUnreachable (proven: "no path: start and goal are not connected below the ceiling", with the
// lowest ceiling that could connect them; or no path within the budget in any sampling region),
// kTimeout / kCancelled from `stop`, kInvalidArgument.
// An infeasible trajectory after repair (every repair, and in the pass mode a stop at the points
// near the violation, tried) is kUnreachable naming the route point nearest the violation
// ("points[i]"), the limit and the value; isTrajectoryStageError tells it from a leg's error.
Result<PlannedRoute> planRoute(std::shared_ptr<const CollisionWorld> world, const std::vector<Eigen::Vector3d>& points_m,
                               const VehicleLimits& limits, const RouteOptions& options,
                               const TerminationCondition& stop = {});

// The two halves of planRoute, for callers that compare or reuse paths before paying for a
// trajectory (the replanner): planRoutePaths runs RRT* + LOSPO per leg (route.built stays empty;
// `stop` also bounds each leg's RRT*), buildRouteTrajectory joins the legs' waypoints into the
// checked trajectory and sets each leg's start and end times.
Result<PlannedRoute> planRoutePaths(std::shared_ptr<const CollisionWorld> world,
                                    const std::vector<Eigen::Vector3d>& points_m, const RouteOptions& options,
                                    const TerminationCondition& stop = {});
Status buildRouteTrajectory(std::shared_ptr<const CollisionWorld> world, const std::vector<Eigen::Vector3d>& points_m,
                            const VehicleLimits& limits, const RouteOptions& options, PlannedRoute& route);

// Whether an error of planRoute / buildRouteTrajectory comes from the trajectory stage (it may
// name a route point, as the legs' stage does).
bool isTrajectoryStageError(const Error& error);

// How a global planner finds the legs' paths through the route's points (in visiting order):
// planRoutePaths (RRT* + LOSPO) or a grid planner (grid_leg_planner.hpp); planner_registry.hpp
// names them. The trajectory stage after it is the same for every planner.
using LegPathPlanner = std::function<Result<PlannedRoute>(std::shared_ptr<const CollisionWorld> world,
                                                          const std::vector<Eigen::Vector3d>& points_m,
                                                          const RouteOptions& options, const TerminationCondition& stop)>;

// Checks a route point cheaply before any search: inside the DEM, above the ground by the
// clearance, under the ceiling, clear of obstacles. `name` is used in the error.
Status checkRoutePoint(const CollisionWorld& world, const Eigen::Vector3d& p_m, const std::string& name,
                       std::optional<ObstacleSnapshot> snapshot = std::nullopt);

}  // namespace skyroute
