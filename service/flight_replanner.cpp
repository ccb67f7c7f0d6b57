#include "service/flight_replanner.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <limits>
#include <string>

#include <Eigen/Geometry>
#include <spdlog/spdlog.h>

#include "trajectory/trajectory_splice.hpp"

namespace skyroute {

namespace {

// Room a hold keeps from every obstacle where it comes to rest, when it can, and that a plan
// leaving a clear hold keeps from every obstacle within the horizon (m).
constexpr double kHoldRoomM = 30.0;
// Share of a replan's wall-clock budget that local repair may use before the whole replan.
constexpr double kLocalBudgetShare = 0.5;

std::string formatRoomM(double room_m) {
  char text[32];
  std::snprintf(text, sizeof text, "%.1f", room_m);
  return text;
}

Status validateReplanOptions(const ReplanOptions& options) {
  if (!(options.period_s > 0.0) || !(options.horizon_s > 0.0) || !(options.check_step_s > 0.0)) {
    return make_error(ErrorCode::kInvalidArgument, "replan", "period, horizon and check step must be positive");
  }
  if (!(options.replan_budget_ms >= 0.0)) {
    return make_error(ErrorCode::kInvalidArgument, "replan_budget_ms", "must be zero (none) or positive");
  }
  if (options.replan_budget_attempts < 0) {
    return make_error(ErrorCode::kInvalidArgument, "replan_budget_attempts", "must be zero (none) or positive");
  }
  if (!(options.max_commit_s >= 0.0) || !std::isfinite(options.max_commit_s)) {
    return make_error(ErrorCode::kInvalidArgument, "max_commit_s", "must be zero (none) or positive and finite");
  }
  if (!(options.calm_accel_share >= 0.0) || !(options.calm_jerk_mps3 > 0.0)) {
    return make_error(ErrorCode::kInvalidArgument, "calm_accel_share",
                      "must be >= 0, and calm_jerk_mps3 positive");
  }
  if (!(options.replan_accel_fraction > 0.0 && options.replan_accel_fraction <= 1.0)) {
    return make_error(ErrorCode::kInvalidArgument, "replan_accel_fraction", "must be in (0, 1]");
  }
  if (!(options.loiter_radius_margin >= 1.0) || !std::isfinite(options.loiter_radius_margin)) {
    return make_error(ErrorCode::kInvalidArgument, "loiter_radius_margin", "must be >= 1 and finite");
  }
  return Status::success();
}

}  // namespace

Result<std::unique_ptr<FlightReplanner>> FlightReplanner::start(std::shared_ptr<const CollisionWorld> world,
                                                                std::vector<Eigen::Vector3d> points_m,
                                                                const VehicleLimits& limits,
                                                                const ReplanOptions& options, double start_world_s,
                                                                const LegPathPlanner& first_legs) {
  if (Status s = validateReplanOptions(options); !s) return s.error();
  std::unique_ptr<FlightReplanner> r(new FlightReplanner());
  r->world_ = std::move(world);
  r->limits_ = limits;
  r->options_ = options;
  TerminationCondition stop;
  if (options.cancel) stop.withCancelFlag(options.cancel);
  auto first = r->bestCandidate([&](int attempt) { return std::optional<AttemptPlan>(r->wholePlan(points_m, {}, attempt)); },
                                start_world_s, nullptr, stop, false, first_legs);
  if (!first.ok()) return first.error();
  if (auto refused = r->auditRefusal(first->route.built.trajectory, start_world_s, start_world_s, 0)) return *refused;
  r->adopt(std::move(first->route), std::move(first->points), start_world_s);
  return r;
}

Result<std::unique_ptr<FlightReplanner>> FlightReplanner::startWithRoute(std::shared_ptr<const CollisionWorld> world,
                                                                         std::vector<Eigen::Vector3d> points_m,
                                                                         const VehicleLimits& limits,
                                                                         const ReplanOptions& options,
                                                                         double start_world_s, PlannedRoute route) {
  if (Status s = validateReplanOptions(options); !s) return s.error();
  if (route.legs.size() + 1 != points_m.size() || route.built.knots.empty()) {
    return make_error(ErrorCode::kInvalidArgument, "route", "must have one leg per pair of points and a trajectory");
  }
  std::unique_ptr<FlightReplanner> r(new FlightReplanner());
  r->world_ = std::move(world);
  r->limits_ = limits;
  r->options_ = options;
  if (auto refused = r->auditRefusal(route.built.trajectory, start_world_s, start_world_s, 0)) return *refused;
  r->adopt(std::move(route), std::move(points_m), start_world_s);
  return r;
}

RouteOptions FlightReplanner::attemptOptions(const std::vector<Eigen::Vector3d>& points, double at_world_s,
                                             const TrajectoryState* state, int attempt, int variant,
                                             double conflict_in_s, const std::optional<Rejoin>& rejoin) const {
  RouteOptions route = withVehiclePathAngles(options_.route, limits_);
  // A cycle after a failed one draws other paths (the same seeds would repeat its failure).
  route.seed = options_.route.seed + 1000ULL * revision_ + 100ULL * static_cast<std::uint64_t>(failed_cycles_) +
               static_cast<std::uint64_t>(attempt);
  if (state) {
    if (options_.replan_leg_max_iterations > 0) route.leg_max_iterations = options_.replan_leg_max_iterations;
    if (options_.replan_max_repair_rounds >= 0) {
      route.trajectory.max_repair_rounds = std::min(route.trajectory.max_repair_rounds, options_.replan_max_repair_rounds);
    }
  }
  // Attempts look further ahead first (a path clear of where the obstacles will be), then less far
  // and with less room (a vehicle already near an obstacle must be allowed to start there).
  // Variant 2 keeps the window and the margin but blocks each place only while the vehicle can
  // be there (a time band round its distance from the takeover point): an obstacle that will
  // sweep the vehicle's current position later in the window then no longer walls it in.
  static constexpr double kWindowScale[] = {1.0, 2.0, 1.0, 0.0};
  static constexpr double kMarginScale[] = {1.0, 1.0, 1.0, 0.0};
  static constexpr bool kTimeBand[] = {false, false, true, false};
  const int k = std::clamp(variant, 0, 3);
  ObstacleSnapshot snapshot;
  snapshot.time_s = at_world_s;
  snapshot.margin_m = kMarginScale[k] * options_.margin_m;
  // The obstacles block at least up to the conflict the replan is for: an obstacle that meets
  // the vehicle further ahead than the window would otherwise be invisible to the planner, which
  // would find the current path again.
  snapshot.window_s = kWindowScale[k] * std::max(options_.window_s, conflict_in_s + options_.reaction_delay_s);
  // Only obstacles the vehicle can meet within the horizon matter now.
  snapshot.focus_m = points.front();
  double fastest = 0.0;
  for (const Obstacle& o : world_->obstacles()) {
    if (o.moving()) fastest = std::max(fastest, o.motion->speed_mps);
  }
  snapshot.focus_radius_m = (limits_.max_speed_mps + fastest) * options_.horizon_s;
  if (kTimeBand[k]) {
    snapshot.band_fast_mps = limits_.max_speed_mps;
    snapshot.band_slow_mps = options_.band_slow_factor * limits_.v_ref_mps;
    snapshot.band_slack_s = options_.band_slack_s;
  }
  route.snapshot = snapshot;
  route.trajectory_start_world_s = at_world_s;
  if (options_.rrt_tree_reuse) {
    route.keep_first_leg_tree = true;
    if (state) route.first_leg_tree = leg_tree_;
  }
  route.moving_check_horizon_s = 0.0;  // conflicts in time are judged here, over the horizon
  // The new curve continues the flown one up to the jerk, and a local stretch ends in the state
  // the current trajectory has where it joins it again.
  if (state) {
    route.trajectory.time_allocation.accel_fraction =
        std::min(route.trajectory.time_allocation.accel_fraction, options_.replan_accel_fraction);
    route.trajectory.boundary.start.velocity_mps = state->velocity_mps;
    route.trajectory.boundary.start.acceleration_mps2 = state->acceleration_mps2;
    route.trajectory.boundary.start.jerk_mps3 = state->jerk_mps3;
  }
  if (rejoin) {
    const TrajectoryState end = route_.built.trajectory.stateAt(rejoin->time_s);
    route.trajectory.boundary.end.velocity_mps = end.velocity_mps;
    route.trajectory.boundary.end.acceleration_mps2 = end.acceleration_mps2;
    route.trajectory.boundary.end.jerk_mps3 = end.jerk_mps3;
  }
  return route;
}

namespace {

bool samePath(const std::vector<Eigen::Vector3d>& a, const std::vector<Eigen::Vector3d>& b) {
  if (a.size() != b.size()) return false;
  for (std::size_t i = 0; i < a.size(); ++i) {
    if ((a[i] - b[i]).norm() > 1e-6) return false;
  }
  return true;
}

}  // namespace

Result<FlightReplanner::Candidate> FlightReplanner::bestCandidate(
    const std::function<std::optional<AttemptPlan>(int)>& plan_of, double at_world_s, const TrajectoryState* state,
    const TerminationCondition& outer_stop, bool first_only, const LegPathPlanner& legs) const {
  std::optional<Candidate> best;
  std::optional<Error> last_error;
  std::vector<std::vector<Eigen::Vector3d>> tried;
  // With an attempt budget, a deadline already passed once the cycle's attempts are spent.
  TerminationCondition expired = TerminationCondition::after(std::chrono::nanoseconds(0));
  if (outer_stop.cancelFlag()) expired.withCancelFlag(outer_stop.sharedCancelFlag());
  for (int attempt = 0; attempt < std::max(1, options_.max_attempts); ++attempt) {
    const TerminationCondition& stop = deadlinePassed(outer_stop) ? expired : outer_stop;
    if (auto reason = stop.reason(); reason != TerminationCondition::Reason::kNone) {
      std::string message = "stopped after " + std::to_string(attempt) + " attempts";
      if (last_error) message += " (last: " + last_error->describe() + ")";
      last_error = make_error(reason == TerminationCondition::Reason::kCancelled ? ErrorCode::kCancelled : ErrorCode::kTimeout,
                              "replan", message);
      break;
    }
    std::optional<AttemptPlan> plan = plan_of(attempt);
    if (!plan) continue;
    ++cycle_attempts_;
    const RouteOptions route =
        attemptOptions(plan->points, at_world_s, state, attempt, plan->variant, plan->conflict_in_s, plan->rejoin);
    const auto attempt_started = std::chrono::steady_clock::now();
    const bool retime = plan->retime_speed_factor < 1.0;
    const bool own_legs = legs && !plan->rejoin;  // local stretches are RRT*'s
    Result<PlannedRoute> candidate = retime     ? currentStretch(*plan)
                                     : own_legs ? legs(world_, plan->points, route, stop)
                                                : planRoutePaths(world_, plan->points, route, stop);
    VehicleLimits limits = limits_;
    limits.v_ref_mps *= plan->retime_speed_factor;
    const auto planned = std::chrono::steady_clock::now();
    auto same = [&](const std::vector<Eigen::Vector3d>& path) { return samePath(path, candidate->waypoints_m); };
    if (!retime && candidate.ok() && (same(plan->current_path) || std::any_of(tried.begin(), tried.end(), same))) {
      continue;  // the same path again: the same trajectory and the same conflict
    }
    // Past the deadline a path in hand is only worth building when nothing better is.
    if (candidate.ok() && best && stop.shouldStop()) break;
    if (candidate.ok()) {
      if (!retime) tried.push_back(candidate->waypoints_m);
      // With a hold to fall back on, the cycle's deadline stops the trajectory build too: a
      // build that runs on past it (a long repair on a loaded machine) would make the answer
      // late, where the hold answers within the cycle and the next cycle plans again.
      RouteOptions build_route = route;
      const bool deadline_stops_build = deadline_holds_;
      if (deadline_stops_build) {
        build_route.trajectory.feasibility.stop_requested = [cancelled = route.trajectory.feasibility.stop_requested,
                                                             &stop] {
          return (cancelled && cancelled()) || stop.reason() == TerminationCondition::Reason::kDeadline;
        };
      }
      Status built = buildRouteTrajectory(world_, plan->points, limits, build_route, *candidate);
      if (!built.ok()) candidate = built.error();
      const bool cancelled = route.trajectory.feasibility.stop_requested && route.trajectory.feasibility.stop_requested();
      if (!built.ok() && built.error().code == ErrorCode::kCancelled && deadline_stops_build && !cancelled) {
        candidate = make_error(ErrorCode::kTimeout, "replan", "the cycle's deadline passed while building the trajectory");
      }
    }
    if (!candidate.ok()) {
      spdlog::debug("event=replan_attempt attempt={} local={} ms={:.1f} error=\"{}\"", attempt, plan->rejoin.has_value(),
                    std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - attempt_started).count(),
                    candidate.error().describe());
      last_error = candidate.error();
      if (candidate.error().code == ErrorCode::kInvalidArgument || candidate.error().code == ErrorCode::kCancelled) {
        break;
      }
      continue;
    }
    Candidate c = plan->rejoin ? splice(std::move(candidate.value()), *plan->rejoin, plan->route_points)
                               : Candidate{std::move(candidate.value()), plan->route_points, 0.0};
    // A built trajectory was checked whole against what stays in force (the build's motion check
    // beyond moving_check_horizon_s = 0: every zone, the terrain, fixed obstacles), so only the
    // horizon is left to check; a spliced one goes on along the current trajectory, checked whole.
    c.conflict_s = plan->rejoin ? firstConflictS(c.route.built.trajectory, at_world_s, at_world_s, options_.horizon_s)
                                : conflictWithinS(c.route.built.trajectory, at_world_s, at_world_s, options_.horizon_s);
    spdlog::debug("event=replan_attempt attempt={} local={} speed_factor={} plan_ms={:.1f} build_ms={:.1f} repair_rounds={} "
                  "conflict_in_s={:.1f}",
                  attempt, plan->rejoin.has_value(), plan->retime_speed_factor,
                  std::chrono::duration<double, std::milli>(planned - attempt_started).count(),
                  std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - planned).count(),
                  c.route.built.report.repair_rounds, c.conflict_s - at_world_s);
    const double conflict = c.conflict_s;
    if (!best || conflict > best->conflict_s) best.emplace(std::move(c));
    if (std::isinf(conflict) || first_only) break;
  }
  if (!best) {
    return last_error.value_or(
        make_error(ErrorCode::kUnreachable, "replan", "every attempt found the path the vehicle is already on"));
  }
  return std::move(*best);
}

FlightReplanner::AttemptPlan FlightReplanner::wholePlan(const std::vector<Eigen::Vector3d>& route_points,
                                                       const std::vector<Eigen::Vector3d>& current_path, int attempt) const {
  AttemptPlan plan;
  plan.points = route_points;
  plan.current_path = current_path;
  plan.route_points = route_points;
  // After failed cycles the later variants come first: the deadline may leave room for few.
  plan.variant = std::min(attempt + failed_cycles_, 3);
  return plan;
}

Result<PlannedRoute> FlightReplanner::currentStretch(const AttemptPlan& plan) const {
  // The current path split into legs at the stretch's points (each is one of its vertices).
  PlannedRoute route;
  route.waypoints_m = plan.current_path;
  std::size_t at = 0;
  for (std::size_t i = 0; i + 1 < plan.points.size(); ++i) {
    RouteLeg leg;
    leg.from_point = i;
    leg.to_point = i + 1;
    leg.path_m.push_back(plan.current_path[at]);
    while (++at < plan.current_path.size()) {
      leg.path_m.push_back(plan.current_path[at]);
      if ((plan.current_path[at] - plan.points[i + 1]).norm() < 1e-6) break;
    }
    if (at >= plan.current_path.size()) {
      return make_error(ErrorCode::kInternal, "replan", "the stretch's points are not on the current path");
    }
    route.legs.push_back(std::move(leg));
  }
  return route;
}

std::optional<FlightReplanner::AttemptPlan> FlightReplanner::localPlan(const std::vector<Eigen::Vector3d>& route_points,
                                                                       double takeover_s, double conflict_s,
                                                                       int attempt, bool static_conflict) const {
  // The attempts: new paths with the obstacles blocking further ahead or less (variants 0-3, as
  // whole replans), and, early because they are cheap and often what a crossing obstacle needs,
  // the current path flown slower so the obstacle passes first.
  struct Variant {
    int variant;
    double rejoin_scale;
    double speed_factor;
  };
  static constexpr Variant kVariants[] = {{0, 1.0, 1.0}, {0, 1.0, 0.6}, {1, 2.0, 1.0}, {0, 2.0, 0.4},
                                          {2, 1.0, 1.0}, {3, 3.0, 1.0}};
  const Variant v = kVariants[std::min<std::size_t>(static_cast<std::size_t>(attempt), std::size(kVariants) - 1)];
  if (v.speed_factor < 1.0 && (!options_.local_retime || static_conflict)) return std::nullopt;
  // A fixed wing cannot wait for an obstacle by flying slower than its minimum airspeed.
  if (v.speed_factor < 1.0 && limits_.v_ref_mps * v.speed_factor < limits_.minAirspeedMps()) return std::nullopt;
  const auto& knots = route_.built.knots;
  const auto& times = route_.built.trajectory.knotTimes();
  if (knots.size() != times.size() || knots.size() < 2) return std::nullopt;
  const double target_s = conflict_s - start_world_s_ + v.rejoin_scale * options_.rejoin_after_s;
  std::size_t r = static_cast<std::size_t>(std::lower_bound(times.begin(), times.end(), target_s) - times.begin());
  // A rejoin inside what stays in force (a zone over the current path, the ground) can never be
  // reached: the first clear knot after it, or none.
  auto clear = [&](std::size_t k) {
    return world_->isStaticSegmentValid(knots[k], knots[k], start_world_s_ + times[k], 0.0);
  };
  while (r + 1 < knots.size() && !clear(r)) ++r;
  if (r + 1 >= knots.size()) return std::nullopt;  // the rejoin would be the goal: replan it all
  // Route points (after the first, the takeover position) the current trajectory reaches before
  // the rejoin knot: the local stretch goes through them; a route point past the conflict but
  // before the target becomes the rejoin itself (the stretch never skips a mission point).
  AttemptPlan plan;
  plan.route_points = route_points;
  plan.variant = v.variant;
  plan.retime_speed_factor = v.speed_factor;
  plan.conflict_in_s = conflict_s - takeover_s;
  plan.points.push_back(route_points.front());
  Rejoin rejoin;
  for (std::size_t i = 1; i < route_points.size(); ++i) {
    std::size_t k = 0;
    while (k < knots.size() && (knots[k] - route_points[i]).norm() > 1e-6) ++k;
    if (k >= knots.size()) return std::nullopt;  // not a knot: never splice blindly
    if (times[k] < times[r] - 1e-9) {
      plan.points.push_back(route_points[i]);
      ++rejoin.points_before;
      continue;
    }
    if (k == r) {
      plan.points.push_back(route_points[i]);
      ++rejoin.points_before;
      rejoin.at_point = true;
    }
    break;
  }
  if (!(times[r] > takeover_s - start_world_s_)) return std::nullopt;
  if (!rejoin.at_point) plan.points.push_back(knots[r]);
  rejoin.knot = r;
  rejoin.time_s = times[r];
  plan.rejoin = rejoin;
  // The current path over the same stretch: its waypoints between takeover and rejoin.
  plan.current_path.push_back(route_points.front());
  for (std::size_t i = 0; i < route_.waypoints_m.size() && i < waypoint_times_world_s_.size(); ++i) {
    const double t = waypoint_times_world_s_[i] - start_world_s_;
    const Eigen::Vector3d& w = route_.waypoints_m[i];
    if (waypoint_times_world_s_[i] > takeover_s && t < times[r] && (w - plan.current_path.back()).norm() > 1.0 &&
        (w - knots[r]).norm() > 1.0) {
      plan.current_path.push_back(w);
    }
  }
  plan.current_path.push_back(knots[r]);
  return plan;
}

FlightReplanner::Candidate FlightReplanner::splice(PlannedRoute local, const Rejoin& rejoin,
                                                   const std::vector<Eigen::Vector3d>& route_points) const {
  Candidate c;
  const Trajectory& current = route_.built.trajectory;
  const double local_s = local.built.trajectory.duration_s();
  const double shift_s = local_s - rejoin.time_s;  // current trajectory time -> new time, past the rejoin
  std::vector<Segment> segments = local.built.trajectory.segments();
  segments.insert(segments.end(), current.segments().begin() + static_cast<std::ptrdiff_t>(rejoin.knot),
                  current.segments().end());
  PlannedRoute& out = c.route;
  out.planning_ms = local.planning_ms;
  out.built.report = local.built.report;
  out.built.knots = local.built.knots;
  out.built.knots.insert(out.built.knots.end(), route_.built.knots.begin() + static_cast<std::ptrdiff_t>(rejoin.knot + 1),
                         route_.built.knots.end());
  out.built.trajectory = Trajectory(std::move(segments));
  out.waypoints_m = local.waypoints_m;
  for (std::size_t i = 0; i < route_.waypoints_m.size() && i < waypoint_times_world_s_.size(); ++i) {
    if (waypoint_times_world_s_[i] - start_world_s_ > rejoin.time_s + 1e-9) out.waypoints_m.push_back(route_.waypoints_m[i]);
  }
  // Legs: the local legs up to the last route point they reach, then the current ones, shifted.
  std::vector<double> point_s{0.0};
  for (std::size_t j = 0; j < rejoin.points_before; ++j) point_s.push_back(local.legs[j].end_s);
  for (std::size_t i = point_s.size(); i < route_points.size(); ++i) {
    double old_world_s = arrivalWorldS();
    for (std::size_t k = 1; k < points_.size(); ++k) {
      if ((points_[k] - route_points[i]).norm() < 1e-6 && point_times_world_s_[k] - start_world_s_ > rejoin.time_s - 1e-9) {
        old_world_s = point_times_world_s_[k];
        break;
      }
    }
    point_s.push_back(old_world_s - start_world_s_ + shift_s);
  }
  for (std::size_t j = 0; j + 1 < route_points.size(); ++j) {
    RouteLeg leg;
    leg.from_point = j;
    leg.to_point = j + 1;
    leg.start_s = point_s[j];
    leg.end_s = point_s[j + 1];
    if (j < local.legs.size()) {
      leg.rrt = local.legs[j].rrt;
      leg.lospo_length_m = local.legs[j].lospo_length_m;
      leg.path_m = local.legs[j].path_m;
      leg.tree = local.legs[j].tree;
      leg.reused_tree_nodes = local.legs[j].reused_tree_nodes;
      leg.tree_reuse_ms = local.legs[j].tree_reuse_ms;
    }
    out.legs.push_back(std::move(leg));
  }
  c.points = route_points;
  return c;
}

void FlightReplanner::adopt(PlannedRoute route, std::vector<Eigen::Vector3d> points, double start_world_s) {
  ++trajectory_changes_;
  loiter_circle_.reset();
  if (options_.rrt_tree_reuse && !route.legs.empty() && route.legs.front().tree) leg_tree_ = route.legs.front().tree;
  route_ = std::move(route);
  points_ = std::move(points);
  start_world_s_ = start_world_s;
  point_times_world_s_.clear();
  for (const RouteLeg& leg : route_.legs) {
    if (point_times_world_s_.empty()) point_times_world_s_.push_back(start_world_s + leg.start_s);
    point_times_world_s_.push_back(start_world_s + leg.end_s);
  }
  // Each waypoint is a knot of the spline, in order (extra knots lie between them).
  waypoint_times_world_s_.clear();
  const auto& knots = route_.built.knots;
  const auto& times = route_.built.trajectory.knotTimes();
  std::size_t k = 0;
  for (const Eigen::Vector3d& w : route_.waypoints_m) {
    while (k < knots.size() && (knots[k] - w).norm() > 1e-6) ++k;
    if (k >= knots.size() || k >= times.size()) {
      waypoint_times_world_s_.clear();  // not matched: never treat a path as the current one
      break;
    }
    waypoint_times_world_s_.push_back(start_world_s + times[k]);
  }
}

std::vector<Eigen::Vector3d> FlightReplanner::waypointsAhead(const Eigen::Vector3d& from, double world_s) const {
  std::vector<Eigen::Vector3d> out;
  if (waypoint_times_world_s_.size() != route_.waypoints_m.size()) return out;
  out.push_back(from);
  for (std::size_t i = 0; i < route_.waypoints_m.size(); ++i) {
    if (waypoint_times_world_s_[i] > world_s && (route_.waypoints_m[i] - from).norm() > 1.0) {
      out.push_back(route_.waypoints_m[i]);
    }
  }
  return out;
}

TrajectoryState FlightReplanner::stateAt(double world_s) const {
  TrajectoryState s = route_.built.trajectory.stateAt(world_s - start_world_s_);
  s.time_s = world_s;
  return s;
}

std::vector<Eigen::Vector3d> FlightReplanner::remainingPoints(double world_s) const {
  std::vector<Eigen::Vector3d> out;
  for (std::size_t i = 1; i < points_.size(); ++i) {
    if (i + 1 == points_.size() || point_times_world_s_[i] > world_s) out.push_back(points_[i]);
  }
  return out;
}

namespace {

// Half extents of the axis-aligned box round an obstacle's shape (the shapes are axis-aligned).
// Much tighter than the bounding sphere for the scenario's tall ellipsoids (600 m wide, 4 km tall).
Eigen::Vector3d halfExtents(const Obstacle& o) {
  switch (o.shape) {
    case ObstacleShape::kSphere: return Eigen::Vector3d::Constant(o.size_m.x());
    case ObstacleShape::kEllipsoid: return o.size_m;
    case ObstacleShape::kBox: return o.size_m;
    case ObstacleShape::kCylinder: return {o.size_m.x(), o.size_m.x(), o.size_m.z()};
  }
  return Eigen::Vector3d::Constant(o.boundingRadius());
}

}  // namespace

double FlightReplanner::firstConflictS(const Trajectory& trajectory, double start_world_s, double from_s,
                                       double horizon_s) const {
  const double within = conflictWithinS(trajectory, start_world_s, from_s, horizon_s);
  if (!std::isinf(within)) return within;
  return staticConflictAfterS(trajectory, start_world_s, from_s + std::max(0.0, horizon_s));
}

double FlightReplanner::currentConflictS(double now_s) {
  const Trajectory& current = route_.built.trajectory;
  const double within = conflictWithinS(current, start_world_s_, now_s, options_.horizon_s);
  if (!std::isinf(within)) return within;
  const std::pair<std::uint64_t, std::uint64_t> key{world_->staticVersion(), trajectory_changes_};
  if (clear_beyond_ == key) return within;
  const double beyond = staticConflictAfterS(current, start_world_s_, now_s + options_.horizon_s);
  if (std::isinf(beyond)) clear_beyond_ = key;
  return beyond;
}

double FlightReplanner::staticConflictAfterS(const Trajectory& trajectory, double start_world_s, double from_s) const {
  const double end = start_world_s + trajectory.duration_s();
  if (!(end > from_s)) return std::numeric_limits<double>::infinity();
  // The same chords as within the horizon; each against the zones in force during it.
  double t0 = from_s;
  Eigen::Vector3d a = trajectory.evaluate(t0 - start_world_s, Derivative::kPosition);
  while (t0 < end) {
    const double t1 = std::min(end, t0 + options_.check_step_s);
    const Eigen::Vector3d b = trajectory.evaluate(t1 - start_world_s, Derivative::kPosition);
    if (!world_->isStaticSegmentValid(a, b, t0, t1 - t0)) return t0;
    a = b;
    t0 = t1;
  }
  return std::numeric_limits<double>::infinity();
}

std::optional<Error> FlightReplanner::auditRefusal(const Trajectory& trajectory, double start_world_s, double now_s,
                                                   std::uint32_t revision) const {
  if (!options_.audit) return std::nullopt;
  return options_.audit(trajectory, start_world_s, now_s, revision);
}

double FlightReplanner::conflictWithinS(const Trajectory& trajectory, double start_world_s, double from_s,
                                        double horizon_s) const {
  const double end = std::min(from_s + horizon_s, start_world_s + trajectory.duration_s());
  if (!(end > from_s)) return std::numeric_limits<double>::infinity();
  // The chords checked: positions at from_s, from_s + step, ... and end.
  std::vector<double> times;
  for (double t = from_s; t < end; t += options_.check_step_s) times.push_back(t);
  times.push_back(end);
  std::vector<Eigen::Vector3d> points(times.size());
  for (std::size_t i = 0; i < times.size(); ++i) {
    points[i] = trajectory.evaluate(times[i] - start_world_s, Derivative::kPosition);
  }
  // Coarse first: a run of chords whose bounding box stays clear of every moving obstacle's box
  // (round the stretch of track it covers meanwhile, grown by the vehicle radius) needs
  // no moving-obstacle check at all, only the static one (terrain, ceiling, fixed obstacles), which
  // is what isSegmentValidDuring would do there too. Only chords that may come close pay for the
  // exact check in time (conservative advancement on FCL distances).
  const std::vector<Obstacle> obstacles = world_->obstacles();
  const double clearance = world_->options().vehicle_radius_m + 1.0;
  auto mayMeet = [&](std::size_t i0, std::size_t i1) {  // chords i0 .. i1 - 1
    Eigen::AlignedBox3d chords;
    for (std::size_t i = i0; i <= i1; ++i) chords.extend(points[i]);
    for (const Obstacle& o : obstacles) {
      if (!o.moving()) continue;
      const auto [from, to] = o.trackDuring(times[i0], times[i1]);
      Eigen::AlignedBox3d swept(from);
      swept.extend(to);
      const Eigen::Vector3d grow = halfExtents(o) + Eigen::Vector3d::Constant(clearance);
      swept.min() -= grow;
      swept.max() += grow;
      if (swept.intersects(chords)) return true;
    }
    return false;
  };
  constexpr std::size_t kRun = 16;  // chords per coarse test (4 s at the default step)
  const std::size_t chords = times.size() - 1;
  for (std::size_t i0 = 0; i0 < chords; i0 += kRun) {
    const std::size_t i1 = std::min(chords, i0 + kRun);
    const bool near = mayMeet(i0, i1);
    for (std::size_t i = i0; i < i1; ++i) {
      const bool valid = near && mayMeet(i, i + 1)
                             ? world_->isSegmentValidDuring(points[i], times[i], points[i + 1], times[i + 1])
                             : world_->isStaticSegmentValid(points[i], points[i + 1], times[i], times[i + 1] - times[i]);
      if (!valid) return times[i];
    }
  }
  return std::numeric_limits<double>::infinity();
}

double FlightReplanner::roomAlong(const Trajectory& trajectory, double start_world_s, double from_s, double horizon_s,
                                  double cap_m) const {
  const double end = std::min(from_s + horizon_s, start_world_s + trajectory.duration_s());
  const std::vector<Obstacle> obstacles = world_->obstacles();
  // Coarse first, as firstConflictS: a chord whose box stays clear of every obstacle's box round
  // the stretch of track it covers meanwhile, grown by the vehicle radius and the cap (and a
  // metre for the curve's bulge off the chord), has at least the cap; only the others are sampled.
  const double grow_m = world_->options().vehicle_radius_m + cap_m + 1.0;
  // Fine enough that the room between two samples is at most a few metres less than at them
  // (the vehicle and the obstacles close in at up to about 150 m/s in the seed-003 scenario).
  const double fine_step_s = options_.check_step_s / 10.0;
  auto at = [&](double t) { return trajectory.evaluate(t - start_world_s, Derivative::kPosition); };
  double room_m = cap_m;
  for (double t0 = from_s; t0 < end; t0 += options_.check_step_s) {
    const double t1 = std::min(t0 + options_.check_step_s, end);
    Eigen::AlignedBox3d chord(at(t0));
    chord.extend(at(t1));
    bool near = false;
    for (const Obstacle& o : obstacles) {
      const auto [a, b] = o.trackDuring(t0, t1);
      Eigen::AlignedBox3d swept(a);
      swept.extend(b);
      const Eigen::Vector3d grow = halfExtents(o) + Eigen::Vector3d::Constant(grow_m);
      swept.min() -= grow;
      swept.max() += grow;
      near = near || swept.intersects(chord);
    }
    if (!near) continue;
    for (double t = t0; t <= t1 + 1e-9; t += fine_step_s) {
      const double s = std::min(t, t1);
      room_m = std::min(room_m, world_->obstacleDistance(at(s), s));
    }
  }
  return room_m;
}

bool FlightReplanner::clearAhead(double now_s, double horizon_s) const {
  return std::isinf(firstConflictS(route_.built.trajectory, start_world_s_, now_s, horizon_s));
}

TerminationCondition FlightReplanner::cycleStop(std::chrono::steady_clock::time_point started, double share) const {
  const double budget_ms = share * options_.replan_budget_ms;
  TerminationCondition stop = options_.replan_budget_ms > 0.0
                                  ? TerminationCondition::after(std::chrono::duration_cast<std::chrono::nanoseconds>(
                                        started + std::chrono::duration<double, std::milli>(budget_ms) -
                                        std::chrono::steady_clock::now()))
                                  : TerminationCondition();
  if (options_.cancel) stop.withCancelFlag(options_.cancel);
  // An attempt budget alone still needs a deadline for the cycle to count attempts against.
  if (options_.replan_budget_attempts > 0 && !stop.hasDeadline()) stop.withDeadlineAfter(std::chrono::hours(24));
  return stop;
}

bool FlightReplanner::deadlinePassed(const TerminationCondition& stop) const {
  if (stop.reason() == TerminationCondition::Reason::kDeadline) return true;
  return stop.hasDeadline() && options_.replan_budget_attempts > 0 && cycle_attempts_ >= options_.replan_budget_attempts;
}

ReplanStep FlightReplanner::step(double now_s) {
  // A loiter about to end gets more turns first, so this cycle checks and plans on from it.
  const bool extended = extendLoiter(now_s);
  ReplanStep result = stepOnce(now_s);
  if (extended && !result.replanned && !result.holding) {
    ++revision_;
    result.holding = true;
    result.loiter = true;
  }
  return result;
}

ReplanStep FlightReplanner::stepOnce(double now_s) {
  ReplanStep result;
  const auto started = std::chrono::steady_clock::now();
  if (finished(now_s)) return result;
  const double current_conflict = currentConflictS(now_s);
  // A hold is clear but does not reach the goal: plan on from it every cycle.
  if (std::isinf(current_conflict) && !holding_) return result;
  result.conflict_ahead = !std::isinf(current_conflict);
  // A conflict beyond the horizon is with what stays in force (a no-fly zone far ahead): there is
  // time to plan round it, so no hold answers it; the replan goes on past the cycle's deadline
  // until a first candidate, and the vehicle flies on meanwhile.
  const bool conflict_in_horizon = current_conflict <= now_s + options_.horizon_s;
  deadline_holds_ = options_.hold_fallback && !holding_ && conflict_in_horizon;
  // The moving obstacles' planning window reaches the conflict when they cause it, not a far one.
  const auto conflict_in_s = [&](double takeover) {
    return std::isinf(current_conflict) || !conflict_in_horizon ? options_.window_s : current_conflict - takeover;
  };
  const double takeover_s = takeoverTime(now_s, current_conflict);
  result.takeover_s = takeover_s;
  // Whether the conflict is with what stays in force there (a zone, the ground, a fixed obstacle):
  // the chord where it is found fails the static check too.
  const bool static_conflict = !std::isinf(current_conflict) && [&] {
    const double t1 = std::min(arrivalWorldS(), current_conflict + options_.check_step_s);
    return !world_->isStaticSegmentValid(stateAt(current_conflict).position_m, stateAt(t1).position_m, current_conflict,
                                         t1 - current_conflict);
  }();
  const TrajectoryState state = stateAt(takeover_s);
  std::vector<Eigen::Vector3d> points{state.position_m};
  for (const Eigen::Vector3d& p : remainingPoints(takeover_s)) {
    if ((p - state.position_m).norm() > 1.0) points.push_back(p);
  }
  if (points.size() < 2) return result;  // already at the goal
  // The deadline counts from the start of the cycle: the check above is part of the latency.
  TerminationCondition stop = cycleStop(started);
  cycle_attempts_ = 0;
  const std::vector<Eigen::Vector3d> ahead = waypointsAhead(state.position_m, takeover_s);
  Result<Candidate> best = make_error(ErrorCode::kInternal, "replan", "not run");
  // A hold is no route to rejoin: plan the whole rest from it.
  if (options_.local_repair && !holding_) {
    // Local repair gets half the budget: the whole replan after it must have time for an attempt
    // (when local repair took it all, the whole replan "stopped after 0 attempts" and the vehicle
    // held where a whole replan found a route at once in the next cycle).
    best = bestCandidate(
        [&](int attempt) {
          std::optional<AttemptPlan> plan = localPlan(points, takeover_s, current_conflict, attempt, static_conflict);
          if (plan) plan->conflict_in_s = conflict_in_s(takeover_s);
          return plan;
        },
        takeover_s, &state, cycleStop(started, kLocalBudgetShare));
    result.local = best.ok() && std::isinf(best->conflict_s);
  }
  // What local repair came to, for the failure's message: it spends the budget first, so a whole
  // replan that then "stopped after 0 attempts" says where the budget went.
  std::string local_outcome;
  if (options_.local_repair && !holding_ && !result.local) {
    local_outcome = best.ok() ? fmt::format("local repair's best meets an obstacle {:.1f} s after the takeover",
                                            best->conflict_s - takeover_s)
                              : "local repair: " + best.error().describe();
  }
  auto whole = [&](int attempt) {
    AttemptPlan plan = wholePlan(points, ahead, attempt);
    plan.conflict_in_s = conflict_in_s(takeover_s);
    return std::optional<AttemptPlan>(std::move(plan));
  };
  TerminationCondition cancel_only;
  if (options_.cancel) cancel_only.withCancelFlag(options_.cancel);
  bool planned_past_deadline = false;
  if (!result.local) {
    best = bestCandidate(whole, takeover_s, &state, stop);
    // A hold is the answer within the cycle; once it is in force (or without holds, or for a
    // conflict beyond the horizon), late beats never: plan on past the deadline until a first
    // candidate, or the vehicle might wait at its hold for as long as the machine is too loaded
    // to plan within the budget.
    if (!deadline_holds_ && !best.ok() && best.error().code == ErrorCode::kTimeout && deadlinePassed(stop)) {
      // From a clear hold (safe to wait in) the first candidate built, as the next cycles plan
      // again; otherwise until a clear one (or every attempt): only a clear one is adopted.
      best = bestCandidate(whole, takeover_s, &state, cancel_only, holding_ && std::isinf(current_conflict));
      planned_past_deadline = true;
    }
  }
  // What may replace the current trajectory, as it would go out: clear of the obstacles (one that
  // still meets one, later, would not pass the audit, which publishes no trajectory known to meet
  // one), leaving a clear hold only with room, with the kept part from now to the takeover in
  // front, and passed by the audit.
  auto vetted = [&](Result<Candidate> best) -> Result<Candidate> {
    if (!best.ok()) return best;
    if (!std::isinf(best->conflict_s)) {
      return make_error(ErrorCode::kUnreachable, "replan",
                        fmt::format("no candidate is clear of the obstacles (the best meets one {:.1f} s after the "
                                    "takeover)",
                                    best->conflict_s - takeover_s));
    }
    // A clear hold is safe to wait in, so it is left only for a plan that keeps room from the
    // obstacles. The conflict check keeps the vehicle's radius and no more, and a hold plans again
    // every cycle: the first candidate it lets through is then typically one that slips past an
    // obstacle by a hair (after a replan cut short by its budget, plans leaving the hold passed
    // 0.1-5.2 m beyond the vehicle's radius from an obstacle in the seed-003 scenario).
    if (holding_ && std::isinf(current_conflict)) {
      const double room_m =
          roomAlong(best->route.built.trajectory, takeover_s, takeover_s, options_.horizon_s, kHoldRoomM);
      if (room_m < kHoldRoomM) {
        // Unless waiting comes closer still (an obstacle will pass the hold nearer than that).
        const double hold_room_m =
            roomAlong(route_.built.trajectory, start_world_s_, now_s, options_.horizon_s, kHoldRoomM);
        if (!(room_m > hold_room_m)) {
          return make_error(ErrorCode::kUnreachable, "replan",
                            "the candidate clear of the obstacles passes " + formatRoomM(room_m) +
                                " m from one, the hold " + formatRoomM(hold_room_m) + " m (a clear hold is left with " +
                                formatRoomM(kHoldRoomM) + " m, or more than it keeps)");
        }
      }
    }
    Candidate adopted = withKeptPart(std::move(best.value()), std::max(now_s, start_world_s_), takeover_s);
    if (auto refused = auditRefusal(adopted.route.built.trajectory, std::max(now_s, start_world_s_), now_s,
                                    revision_ + 1)) {
      return *refused;
    }
    return adopted;
  };
  best = vetted(std::move(best));
  if (!best.ok()) {
    result.failure = best.error();
    if (!local_outcome.empty() && best.error().field != "audit") {
      result.failure->message += "; before it, " + local_outcome;
    }
    ++failed_cycles_;
    // Within the horizon a hold answers (when it passes the audit too); a conflict beyond it
    // leaves the current trajectory in force while the next cycles plan on.
    const bool cancelled = best.error().code == ErrorCode::kCancelled;
    if (options_.hold_fallback && !std::isinf(current_conflict) && conflict_in_horizon && !cancelled) {
      // A fixed wing cannot stop and wait: it loiters.
      const bool held = limits_.fixedWing() ? adoptLoiter(now_s, takeover_s, current_conflict, result.hold_failure)
                                            : adoptHold(now_s, takeover_s, current_conflict);
      if (held) {
        ++revision_;
        result.holding = true;
        result.loiter = limits_.fixedWing();
        result.latency_ms =
            std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - started).count();
        return result;
      }
    }
    // No hold to answer with either, for a conflict the budget cut the search for: nothing better
    // than planning on past the deadline until a clear route (or every attempt).
    if (!std::isinf(current_conflict) && !cancelled && !planned_past_deadline && deadlinePassed(stop)) {
      best = vetted(bestCandidate(whole, takeover_s, &state, cancel_only));
    }
    if (!best.ok()) {
      result.latency_ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - started).count();
      return result;
    }
    result.failure.reset();
    result.hold_failure.reset();
  }
  if (!best->route.legs.empty()) result.reused_tree_nodes = best->route.legs.front().reused_tree_nodes;
  Candidate adopted = std::move(best.value());
  const double adopted_start_s = std::max(now_s, start_world_s_);
  adopt(std::move(adopted.route), std::move(adopted.points), adopted_start_s);
  holding_ = false;
  ++revision_;
  failed_cycles_ = 0;
  result.replanned = true;
  result.latency_ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - started).count();
  return result;
}

double FlightReplanner::takeoverTime(double now_s, double conflict_s) const {
  // From a clear loiter the new plan leaves the circle along its tangent, where it heads for the
  // next route point: a curve taking over elsewhere on the circle would have to turn back
  // tighter than the circle.
  if (holding_ && loiter_circle_ && std::isinf(conflict_s)) return loiterExitTime(now_s);
  const double earliest = now_s + options_.reaction_delay_s;
  double latest = earliest + std::max(0.0, options_.max_commit_s);
  // Never commit to much of the way to the obstacle: the new plan needs the room to turn away.
  if (!std::isinf(conflict_s)) latest = std::min(latest, earliest + 0.25 * std::max(0.0, conflict_s - earliest));
  latest = std::min(latest, arrivalWorldS());
  constexpr double kStepS = 0.1;
  double calmest_s = earliest;
  double calmest = std::numeric_limits<double>::infinity();
  for (double t = earliest; t <= latest + 1e-9; t += kStepS) {
    const TrajectoryState s = stateAt(t);
    // Turning is what a new curve cannot take over: speeding up or slowing down along the way
    // is (the new path starts along the velocity as often as not).
    const Eigen::Vector3d along = s.velocity_mps.norm() > 1e-6 ? s.velocity_mps.normalized() : Eigen::Vector3d::Zero();
    const Eigen::Vector3d lateral = s.acceleration_mps2 - s.acceleration_mps2.dot(along) * along;
    const double accel_share = lateral.norm() / limits_.max_accel_mps2;
    const double jerk_share = s.jerk_mps3.norm() / std::max(1e-9, options_.calm_jerk_mps3);
    if (accel_share <= options_.calm_accel_share && jerk_share <= 1.0) return t;
    const double score = accel_share / std::max(1e-9, options_.calm_accel_share) + jerk_share;
    if (score < calmest) {
      calmest = score;
      calmest_s = t;
    }
  }
  return calmest_s;
}

FlightReplanner::Candidate FlightReplanner::withKeptPart(Candidate c, double from_s, double takeover_s) const {
  std::vector<Segment> kept = segmentsBetween(route_.built.trajectory, from_s - start_world_s_, takeover_s - start_world_s_);
  if (kept.empty()) return c;
  double kept_s = 0.0;
  std::vector<Eigen::Vector3d> knots;
  for (const Segment& s : kept) {
    knots.push_back(s.evaluate(0.0, Derivative::kPosition));
    kept_s += s.duration_s;
  }
  std::vector<Segment> segments = std::move(kept);
  const std::vector<Segment>& planned = c.route.built.trajectory.segments();
  segments.insert(segments.end(), planned.begin(), planned.end());
  c.route.built.trajectory = Trajectory(std::move(segments));
  c.route.built.knots.insert(c.route.built.knots.begin(), knots.begin(), knots.end());
  c.route.waypoints_m.insert(c.route.waypoints_m.begin(), knots.front());
  for (std::size_t i = 0; i < c.route.legs.size(); ++i) {
    RouteLeg& leg = c.route.legs[i];
    if (i > 0) leg.start_s += kept_s;
    leg.end_s += kept_s;
  }
  if (!c.route.legs.empty()) c.route.legs.front().path_m.insert(c.route.legs.front().path_m.begin(), knots.front());
  if (!c.points.empty()) c.points.front() = knots.front();
  return c;
}

bool FlightReplanner::adoptHold(double now_s, double takeover_s, double conflict_s) {
  const auto hold_started = std::chrono::steady_clock::now();
  const Trajectory& current = route_.built.trajectory;
  const double from_s = std::max(now_s, start_world_s_);
  // The latest stop that stays clear: try stopping later first (more of the current trajectory
  // kept), then earlier, down to the takeover.
  std::optional<Trajectory> best;
  double best_conflict = conflict_s;
  double best_stop_s = 0.0;
  double best_room_m = -1.0;
  bool best_off_tracks = false;
  std::vector<double> stop_times;
  // At most 6 stop times (the hold is built within the cycle, after the plan's deadline).
  const double step_s = std::max(1.0, (conflict_s - 2.0 - takeover_s) / 5.0);
  for (double t = conflict_s - 2.0; t > takeover_s && stop_times.size() < 5; t -= step_s) stop_times.push_back(t);
  stop_times.push_back(takeover_s);
  int stops_infeasible = 0;
  // Each stop time with a gentle stop first, then, when that meets an obstacle, with the hardest
  // the limits allow.
  std::vector<std::pair<double, double>> stops;  // (stop time, braking share of the limit)
  for (double stop_s : stop_times) {
    stops.emplace_back(stop_s, 0.5);
    stops.emplace_back(stop_s, 0.9);
  }
  bool gentle_clear = false;
  int tried = 0;
  for (const auto& [stop_s, brake_share] : stops) {
    if (brake_share > 0.5 && gentle_clear) continue;
    ++tried;
    StopOptions stop_options;
    stop_options.brake_accel_share = brake_share;
    const std::optional<Segment> stopping = stopSegment(stateAt(stop_s), limits_, stop_options);
    if (!stopping) {
      ++stops_infeasible;
      continue;
    }
    std::vector<Segment> segments = segmentsBetween(current, from_s - start_world_s_, stop_s - start_world_s_);
    segments.push_back(*stopping);
    // At rest at the end, for the horizon: the conflict check sees who comes by.
    Segment rest;
    rest.duration_s = options_.horizon_s;
    const Eigen::Vector3d end = stopping->evaluate(stopping->duration_s, Derivative::kPosition);
    for (std::size_t axis = 0; axis < 3; ++axis) {
      Polynomial7::Coefficients constant{};
      constant[0] = end(static_cast<Eigen::Index>(axis));
      rest.axes[axis] = Polynomial7(constant);
    }
    segments.push_back(rest);
    Trajectory hold(std::move(segments));
    // Up to the stop it is the current trajectory, clear until conflict_s: checked from there.
    const double conflict = firstConflictS(hold, from_s, stop_s, now_s + options_.horizon_s - stop_s);
    gentle_clear = brake_share <= 0.5 && std::isinf(conflict);
    // Among clear stops, the latest with room to spare where it comes to rest, else the one with
    // the most room (the latest clear stop tends to end as close as the check allows). First
    // those that rest off every moving obstacle's track (its whole sweep, with that room): the
    // vehicle may wait there longer than the horizon, and the latest clear stop tends to be at
    // the edge of the track an obstacle comes back along (after a replan cut by its budget,
    // resting vehicles were passed at 0.5 m beyond their radius).
    const double at_rest_s = from_s + hold.duration_s() - rest.duration_s;
    const bool clear = std::isinf(conflict);
    const double room_m = clear ? world_->obstacleDistance(end, at_rest_s) : -1.0;
    const bool off_tracks = clear && world_->isPointValid(end, std::nullopt, kHoldRoomM);
    const bool roomier = off_tracks != best_off_tracks ? off_tracks : room_m > best_room_m;
    if (conflict > best_conflict || (clear && roomier)) {
      best_conflict = conflict;
      best = std::move(hold);
      best_stop_s = stop_s;
      best_room_m = room_m;
      best_off_tracks = off_tracks;
      if (room_m >= kHoldRoomM && off_tracks) break;
    }
  }
  // Only a clear hold is put in force, and only when the audit passes it too.
  if (!best || !std::isinf(best_conflict)) {
    spdlog::debug("event=replan_no_hold stops_tried={} stops_infeasible={} conflict_in_s={:.1f}", stops.size(),
                  stops_infeasible, conflict_s - now_s);
    return false;
  }
  if (auditRefusal(*best, from_s, now_s, revision_ + 1)) return false;
  installHold(std::move(*best), from_s, best_stop_s);
  loiter_circle_.reset();
  spdlog::debug("event=replan_hold stop_in_s={:.1f} conflict_in_s={:.1f} room_m={:.0f} stops_tried={} ms={:.1f}",
                best_stop_s - now_s, best_conflict - now_s, best_room_m, tried,
                std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - hold_started).count());
  return true;
}

void FlightReplanner::installHold(Trajectory hold, double from_s, double kept_until_s) {
  ++trajectory_changes_;
  // The route points the kept part reaches keep their times; the others are not reached by the hold.
  std::vector<Eigen::Vector3d> points{hold.evaluate(0.0, Derivative::kPosition)};
  std::vector<double> times{from_s};
  for (std::size_t i = 1; i < points_.size(); ++i) {
    if (point_times_world_s_[i] <= from_s && i + 1 < points_.size()) continue;  // passed already
    points.push_back(points_[i]);
    times.push_back(point_times_world_s_[i] <= kept_until_s ? point_times_world_s_[i]
                                                            : std::numeric_limits<double>::infinity());
  }
  PlannedRoute route;
  route.built.trajectory = std::move(hold);
  for (const Segment& s : route.built.trajectory.segments()) route.built.knots.push_back(s.evaluate(0.0, Derivative::kPosition));
  route.built.knots.push_back(route.built.trajectory.evaluate(route.built.trajectory.duration_s(), Derivative::kPosition));
  route.built.report.status = TrajectoryStatus::kFeasible;
  route.waypoints_m = {route.built.knots.front()};
  route_ = std::move(route);
  points_ = std::move(points);
  point_times_world_s_ = std::move(times);
  waypoint_times_world_s_ = {from_s};
  start_world_s_ = from_s;
  holding_ = true;
}

}  // namespace skyroute
