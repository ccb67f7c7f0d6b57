#include "service/route_planner.hpp"

#include <chrono>
#include <algorithm>
#include <cmath>
#include <string_view>

#include <spdlog/spdlog.h>

#include "planning/core/polyline.hpp"
#include "planning/sampling/leg_sampling_regions.hpp"
#include "service/number_text.hpp"
#include "service/planner_status.hpp"
#include "service/trajectory_world_check.hpp"

namespace skyroute {
namespace {

// Every trajectory-stage failure starts its message with this.
constexpr std::string_view kNoTrajectory = "the trajectory cannot be flown: ";

// "acceleration 14.2 m/s^2 over the limit 8 m/s^2 at t=31.0 s", from the checked values.
std::string violationText(const Violation& v) {
  const char* unit = "m/s";
  switch (v.kind) {
    case ViolationKind::kAcceleration: unit = "m/s^2"; break;
    case ViolationKind::kTurnRadius: unit = "m"; break;
    case ViolationKind::kBankAngle:
    case ViolationKind::kClimbAngle:
    case ViolationKind::kDescentAngle: unit = "deg"; break;
    case ViolationKind::kLoadFactor: unit = "g"; break;
    default: break;
  }
  const std::string at = " at t=" + numberText(v.time_s, 4) + " s";
  if (v.kind == ViolationKind::kCollision) return "the curve collides (terrain or obstacle)" + at;
  const char* relation = underLimitIsViolation(v.kind) ? " under the limit " : " over the limit ";
  return std::string(to_string(v.kind)) + " " + numberText(v.value, 4) + " " + unit + relation +
         numberText(v.limit, 4) + " " + unit + at;
}

// Guided search beyond the corridor, tuned on the hard legs of bench/rrt_star_bench.cpp (a
// steering range of 2 km there: every leg solved at a 10 ms cap, against 14 of 20 with the
// automatic range).
constexpr double kGuideBias = 0.5;
constexpr double kGuidedStepsPerBlock = 10.0;
constexpr int kBeyondCorridorLospoVertices = 300;

// The regions' way under the ceiling (LegSamplingRegions::wayUnderCeiling) when every piece of it
// is a valid motion for this validator (terrain, obstacles, zones); nothing otherwise.
std::optional<std::vector<Eigen::Vector3d>> clearWayUnderCeiling(const MotionValidator& validator,
                                                                 const LegSamplingRegions& regions) {
  std::vector<Eigen::Vector3d> way = regions.wayUnderCeiling();
  if (way.size() < 2) return std::nullopt;
  for (std::size_t k = 1; k < way.size(); ++k) {
    if (!validator.isMotionValid(way[k - 1], way[k])) return std::nullopt;
  }
  return way;
}
}  // namespace

RouteOptions withVehiclePathAngles(RouteOptions options, const VehicleLimits& limits) {
  options.max_path_climb_deg = limits.fixedWing() ? kPathAngleShare * limits.max_climb_angle_deg : 0.0;
  options.max_path_descent_deg = limits.fixedWing() ? kPathAngleShare * limits.max_descent_angle_deg : 0.0;
  return options;
}

bool isTrajectoryStageError(const Error& error) {
  return error.field == "trajectory" || error.message.rfind(kNoTrajectory, 0) == 0;
}

Status checkRoutePoint(const CollisionWorld& world, const Eigen::Vector3d& p_m, const std::string& name,
                       std::optional<ObstacleSnapshot> snapshot) {
  if (!p_m.allFinite()) return make_error(ErrorCode::kInvalidArgument, name, "is not a finite position");
  const Heightfield& terrain = world.terrain();
  if (!terrain.inside(p_m.x(), p_m.y()) || !terrain.boundsEn().contains(p_m.head<2>())) {
    return make_error(ErrorCode::kOutsideMap, name, enuText(p_m) + " is outside the terrain");
  }
  const double ground = terrain.heightAt(p_m.x(), p_m.y());
  if (std::isnan(ground)) {
    return make_error(ErrorCode::kOutsideMap, name, enuText(p_m) + " is over unknown terrain (a DEM void)");
  }
  const auto& o = world.options();
  if (p_m.z() > o.ceiling_m) {
    return make_error(ErrorCode::kInvalidArgument, name,
                      "altitude " + numberText(p_m.z(), 7) + " m is above the ceiling " + numberText(o.ceiling_m, 7) + " m");
  }
  if (!world.isTerrainValid(p_m)) {
    return make_error(ErrorCode::kOccupied, name,
                      "altitude " + numberText(p_m.z(), 7) + " m is under the ground plus clearance (ground " +
                          numberText(ground, 7) + " m + " + numberText(o.min_clearance_m) + " m)");
  }
  if (auto zone = world.noFlyZoneAt(p_m, snapshot ? std::optional<double>(snapshot->time_s) : std::nullopt)) {
    return make_error(ErrorCode::kOccupied, name, enuText(p_m) + " is inside no-fly zone '" + *zone + "'");
  }
  const bool clear = snapshot ? world.isPointValid(p_m, *snapshot) : world.isPointValid(p_m);
  if (!clear) return make_error(ErrorCode::kOccupied, name, enuText(p_m) + " is inside an obstacle");
  return Status::success();
}

Result<PlannedRoute> planRoute(std::shared_ptr<const CollisionWorld> world, const std::vector<Eigen::Vector3d>& points_m,
                               const VehicleLimits& limits, const RouteOptions& options,
                               const TerminationCondition& stop) {
  const auto started = std::chrono::steady_clock::now();
  auto route = planRoutePaths(world, points_m, withVehiclePathAngles(options, limits), stop);
  if (!route.ok()) return route.error();
  Status built = buildRouteTrajectory(world, points_m, limits, options, *route);
  if (!built.ok()) return built.error();
  route->planning_ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - started).count();
  return route;
}

Result<PlannedRoute> planRoutePaths(std::shared_ptr<const CollisionWorld> world,
                                    const std::vector<Eigen::Vector3d>& points_m, const RouteOptions& options,
                                    const TerminationCondition& stop) {
  const auto started = std::chrono::steady_clock::now();
  if (!world) return make_error(ErrorCode::kInvalidArgument, "world", "is null");
  if (points_m.size() < 2) return make_error(ErrorCode::kInvalidArgument, "points", "needs at least two points");
  for (std::size_t i = 0; i < points_m.size(); ++i) {
    Status s = checkRoutePoint(*world, points_m[i], "points[" + std::to_string(i) + "]", options.snapshot);
    if (!s.ok()) return s.error();
    if (i > 0 && (points_m[i] - points_m[i - 1]).norm() < 1.0) {
      return make_error(ErrorCode::kInvalidArgument, "points[" + std::to_string(i) + "]",
                        "is within 1 m of the point before it");
    }
  }
  PlannedRoute route;
  for (std::size_t i = 0; i + 1 < points_m.size(); ++i) {
    const std::string leg_name = "legs[" + std::to_string(i) + "]";
    if (auto reason = stop.reason(); reason != TerminationCondition::Reason::kNone) {
      return plannerError(stoppedStatus(reason), leg_name, "stopped before planning this leg");
    }
    // A leg whose ends the terrain cannot join below the ceiling needs no search: say so, and
    // what ceiling could join them. Otherwise RRT* samples its corridor first, then larger
    // regions (LegSamplingRegions) before the leg is given up.
    LegSamplingRegions regions(*world, points_m[i], points_m[i + 1], options.corridor_margin_m);
    if (!regions.connected()) {
      const auto& o = world->options();
      const auto lowest = regions.lowestConnectingCeilingM();
      return plannerError(PlannerStatus::kNoPath, leg_name,
                          "no path: start and goal are not connected below the ceiling (" + numberText(o.ceiling_m, 7) +
                              " m with " + numberText(o.min_clearance_m) + " m clearance); " +
                              (lowest ? "the lowest ceiling that could connect them is " + numberText(*lowest, 7) + " m"
                                      : std::string("unknown terrain or the map's edge separates them at any ceiling")));
    }
    RrtStarOptions rrt_options = options.rrt;
    rrt_options.seed = options.seed + i;
    std::optional<WorldMotionValidator> validator;
    Result<RrtStarResult> rrt = make_error(ErrorCode::kInternal, leg_name, "no sampling region");
    std::uint64_t samples = 0;
    bool way_tried = false;
    const bool keep_tree = i == 0 && options.keep_first_leg_tree;
    RrtTree grown;
    std::size_t reused_nodes = 0;
    double reuse_ms = 0.0;
    bool kept_tree_stays = false;
    bool first_region = true;
    while (auto region = regions.next()) {
      validator.emplace(world, *region, options.snapshot);
      if (options.max_path_climb_deg > 0.0 || options.max_path_descent_deg > 0.0) {
        validator->limitPathAngles(options.max_path_climb_deg > 0.0 ? options.max_path_climb_deg : 90.0,
                                   options.max_path_descent_deg > 0.0 ? options.max_path_descent_deg : 90.0);
      }
      // The reused tree joins the leg's first region (its corridor) only: beyond it the leg
      // searches wide regions the tree was not grown for.
      // A straight first leg needs no tree (RRT* returns the motion at once): the kept tree is then
      // neither re-rooted (its motion checks would buy nothing) nor replaced, and stays for a
      // later replan that needs it.
      if (i == 0 && first_region && options.first_leg_tree && rrt_options.try_direct_first &&
          validator->isMotionValid(points_m[0], points_m[1])) {
        kept_tree_stays = true;
      }
      std::optional<RerootedTree> reused;
      if (i == 0 && first_region && options.first_leg_tree && !kept_tree_stays) {
        const auto reuse_started = std::chrono::steady_clock::now();
        auto rerooted = rerootTree(*options.first_leg_tree, points_m[0], *validator, options.tree_reuse, stop);
        reuse_ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - reuse_started).count();
        if (!rerooted.ok()) return rerooted.error();
        spdlog::debug("event=rrt_tree_reuse stored={} kept={} root_links={} blocked_edges={} motion_checks={} stopped={}",
                      options.first_leg_tree->size(), rerooted->kept_nodes, rerooted->root_links,
                      rerooted->blocked_edges, rerooted->motion_checks, rerooted->stopped);
        if (rerooted->kept_nodes > 0) reused.emplace(std::move(rerooted.value()));
      }
      first_region = false;
      // Beyond the corridor the region is wide and the way round may be narrow: half the samples
      // before the first path go near the flyable regions' shortest way, and the steering range
      // is a few blocks of it (a fifth of a wide region's diagonal is tens of kilometres, and
      // such long motions hardly ever fit a winding valley).
      if (!regions.guide().empty()) {
        rrt_options.guide_m = regions.guide();
        rrt_options.guide_bias = kGuideBias;
        rrt_options.guide_radius_m = regions.guideSpacingM();
        if (options.rrt.max_step_m == 0.0) rrt_options.max_step_m = kGuidedStepsPerBlock * regions.guideSpacingM();
      }
      RrtStar planner(*validator, rrt_options);
      TerminationCondition leg_stop = options.leg_budget_ms > 0.0
                                          ? TerminationCondition::afterMilliseconds(options.leg_budget_ms)
                                          : TerminationCondition();
      std::uint64_t iterations = options.leg_max_iterations;
      if (reused && iterations > 0) {
        const auto least = static_cast<std::uint64_t>(std::ceil(kReusedLegMinNewShare * static_cast<double>(iterations)));
        iterations = std::max(least, iterations - std::min<std::uint64_t>(iterations, reused->kept_nodes));
      }
      if (iterations > 0) leg_stop.withIterationBudget(iterations);
      RrtTree* tree_out = keep_tree ? &grown : nullptr;
      rrt = reused ? planner.planFromTree(reused->tree, points_m[i + 1], leg_stop, stop, tree_out)
                   : planner.plan(points_m[i], points_m[i + 1], leg_stop, stop, tree_out);
      reused_nodes = reused ? reused->kept_nodes : 0;
      if (!rrt.ok()) return rrt.error();
      samples += rrt->iterations;
      if (rrt->solved() || stop.reason() != TerminationCondition::Reason::kNone) break;
      // RRT* found nothing round the range in its budget (its first path on a long winding way
      // can take more samples than a short budget holds): fly the flyable regions' way under the
      // ceiling when every piece of it is clear, for LOSPO to straighten, before the whole terrain.
      if (!regions.guide().empty() && !way_tried) {
        way_tried = true;
        if (auto way = clearWayUnderCeiling(*validator, regions)) {
          rrt->path_m = std::move(*way);
          rrt->length_m = polylineLength(rrt->path_m);
          rrt->distance_to_goal_m = 0.0;
          rrt->status = PlannerStatus::kSolved;
          break;
        }
      }
    }
    if (!rrt.ok()) return rrt.error();
    if (!rrt->solved()) {
      // The caller's deadline or cancel flag, not the leg's own budget, stopped the search.
      if (auto reason = stop.reason(); reason != TerminationCondition::Reason::kNone) {
        return plannerError(stoppedStatus(reason), leg_name, "stopped while planning this leg");
      }
      // The leg is named by the error's field; the message says only what happened, so a caller
      // that names the leg's points its own way never contradicts it. The leg's own wall-clock
      // cap is part of its budget: no path within it.
      const std::string why = rrt->status == PlannerStatus::kTimeout ? "its time budget ran out"
                              : rrt->status == PlannerStatus::kBudgetExhausted ? "its iteration budget ran out"
                                                                               : std::string(to_string(rrt->status));
      const PlannerStatus status = isStopped(rrt->status) ? PlannerStatus::kBudgetExhausted : rrt->status;
      const std::string where = regions.tried() > 1 ? " in each of " + std::to_string(regions.tried()) +
                                                          " sampling regions, the last " +
                                                          (regions.wholeTerrainTried() ? "the whole terrain" : "the widest")
                                                    : std::string();
      return plannerError(status, leg_name,
                          "no path found: RRT* drew " + std::to_string(samples) + " samples before " + why + where);
    }
    // A path found beyond the corridor can be tens of kilometres of RRT* zigzag: LOSPO's O(n^2)
    // pass over vertices every spacing_m would take seconds, so it gets at most a few hundred.
    LospoOptions lospo_options = options.lospo;
    if (!regions.guide().empty() && lospo_options.max_vertices == 0) {
      lospo_options.max_vertices = kBeyondCorridorLospoVertices;
    }
    auto shortened = lospo(*validator, rrt->path_m, lospo_options, stop);
    if (!shortened.ok()) return shortened.error();
    RouteLeg leg;
    leg.from_point = i;
    leg.to_point = i + 1;
    leg.time_capped = options.leg_max_iterations > 0 && rrt->stop_reason == TerminationCondition::Reason::kDeadline &&
                      rrt->iterations < options.leg_max_iterations;
    leg.rrt = std::move(rrt.value());
    leg.reused_tree_nodes = reused_nodes;
    leg.tree_reuse_ms = reuse_ms;
    if (keep_tree && !kept_tree_stays) {
      leg.tree = std::make_shared<const RrtTree>(cheapestPart(grown, options.tree_reuse.max_nodes));
    }
    leg.lospo_length_m = shortened->length_m;
    leg.path_m = std::move(shortened->path_m);
    for (std::size_t k = (i == 0 ? 0 : 1); k < leg.path_m.size(); ++k) route.waypoints_m.push_back(leg.path_m[k]);
    route.legs.push_back(std::move(leg));
  }
  route.planning_ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - started).count();
  return route;
}

Status buildRouteTrajectory(std::shared_ptr<const CollisionWorld> world, const std::vector<Eigen::Vector3d>& points_m,
                            const VehicleLimits& limits, const RouteOptions& options, PlannedRoute& route) {
  if (!world) return make_error(ErrorCode::kInvalidArgument, "world", "is null");
  MotionCheck check = collisionWorldMotionCheck(world, options.trajectory_start_world_s);
  if (options.trajectory_start_world_s) {
    check = [world, timed = check, horizon = options.moving_check_horizon_s](const Eigen::Vector3d& a, double ta,
                                                                            const Eigen::Vector3d& b, double tb) {
      return ta <= horizon ? timed(a, ta, b, tb) : world->isStaticSegmentValid(a, b);
    };
  }
  TrajectoryOptions trajectory_options = options.trajectory;
  // The route points (leg ends) stay knots of the spline, so corner rounding for the turn radius
  // never cuts a mission point, and the leg times below are read at them.
  std::vector<std::size_t> point_waypoints{0};  // route point k is waypoint point_waypoints[k]
  std::size_t leg_end = 0;
  for (const RouteLeg& leg : route.legs) {
    leg_end += leg.path_m.size() - 1;  // leg 0 adds all its points, later legs all but their first
    point_waypoints.push_back(leg_end);
  }
  trajectory_options.fixed_waypoints.insert(trajectory_options.fixed_waypoints.end(), point_waypoints.begin(),
                                            point_waypoints.end());
  spdlog::debug("event=trajectory_build waypoints={} legs={}", route.waypoints_m.size(), route.legs.size());
  auto built = buildTrajectory(route.waypoints_m, limits, trajectory_options, &check);
  if (!built.ok()) return built.error();
  // The route point a waypoint is (point_waypoints.size() when none), and the leg a waypoint
  // inside a leg belongs to.
  auto route_point = [&](std::size_t waypoint) {
    return static_cast<std::size_t>(std::find(point_waypoints.begin(), point_waypoints.end(), waypoint) -
                                    point_waypoints.begin());
  };
  auto leg_of = [&](std::size_t waypoint) {
    return static_cast<std::size_t>(std::upper_bound(point_waypoints.begin(), point_waypoints.end(), waypoint) -
                                    point_waypoints.begin()) - 1;
  };
  const TrajectoryBuildReport& report = built->report;
  // "2 of the points and 14 corners of the legs" (counts: the caller names points its own way).
  std::size_t point_stops = 0;
  std::size_t corner_stops = 0;
  for (const WaypointStop& stop : report.stops) (route_point(stop.waypoint) < point_waypoints.size() ? point_stops : corner_stops)++;
  std::string stopped;
  if (point_stops > 0) stopped = std::to_string(point_stops) + " of the points";
  if (corner_stops > 0) {
    stopped += (stopped.empty() ? "" : " and ") + std::to_string(corner_stops) + " corners of the legs";
  }
  if (report.status == TrajectoryStatus::kInfeasible) {
    std::string field = "trajectory";
    std::string limit;
    if (report.failure_violation) limit = violationText(*report.failure_violation) + "; ";
    if (report.failure_waypoint && route_point(*report.failure_waypoint) < point_waypoints.size()) {
      field = "points[" + std::to_string(route_point(*report.failure_waypoint)) + "]";
    }
    return make_error(ErrorCode::kUnreachable, field,
                      std::string(kNoTrajectory) + limit + "no feasible trajectory along the path" +
                          (stopped.empty() ? std::string() : " even with stops at " + stopped) + ": " +
                          report.failure_reason);
  }
  route.point_stops.clear();
  route.leg_corner_stops.clear();
  route.corner_stop_reason.clear();
  for (const WaypointStop& stop : report.stops) {
    const std::size_t point = route_point(stop.waypoint);
    if (point < point_waypoints.size()) {
      route.point_stops.push_back({point, stop.reason});
      continue;
    }
    if (route.leg_corner_stops.empty()) route.leg_corner_stops.assign(route.legs.size(), 0);
    if (leg_of(stop.waypoint) < route.leg_corner_stops.size()) ++route.leg_corner_stops[leg_of(stop.waypoint)];
    route.corner_stop_reason = stop.reason;
  }
  route.built = std::move(built.value());
  // Times at the route points: each is a knot of the spline, in order.
  const auto& knots = route.built.knots;
  const auto& times = route.built.trajectory.knotTimes();
  std::size_t k = 0;
  for (RouteLeg& leg : route.legs) {
    while (k < knots.size() && (knots[k] - points_m[leg.from_point]).norm() > 1e-6) ++k;
    leg.start_s = k < times.size() ? times[k] : 0.0;
    std::size_t e = k + 1;
    while (e < knots.size() && (knots[e] - points_m[leg.to_point]).norm() > 1e-6) ++e;
    leg.end_s = e < times.size() ? times[e] : route.built.trajectory.duration_s();
    k = e;
  }
  return Status::success();
}

}  // namespace skyroute
