#include "service/flight_replanner.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>

#include <Eigen/Geometry>

namespace skyroute {

Result<std::unique_ptr<FlightReplanner>> FlightReplanner::start(std::shared_ptr<const CollisionWorld> world,
                                                                std::vector<Eigen::Vector3d> points_m,
                                                                const VehicleLimits& limits,
                                                                const ReplanOptions& options, double start_world_s) {
  if (!(options.period_s > 0.0) || !(options.horizon_s > 0.0) || !(options.check_step_s > 0.0)) {
    return make_error(ErrorCode::kInvalidArgument, "replan", "period, horizon and check step must be positive");
  }
  if (!(options.replan_budget_ms >= 0.0)) {
    return make_error(ErrorCode::kInvalidArgument, "replan_budget_ms", "must be zero (none) or positive");
  }
  std::unique_ptr<FlightReplanner> r(new FlightReplanner());
  r->world_ = std::move(world);
  r->limits_ = limits;
  r->options_ = options;
  TerminationCondition stop;
  if (options.cancel) stop.withCancelFlag(options.cancel);
  auto first = r->bestCandidate(points_m, start_world_s, nullptr, stop, nullptr);
  if (!first.ok()) return first.error();
  r->adopt(std::move(first->first), std::move(points_m), start_world_s);
  return r;
}

Result<std::unique_ptr<FlightReplanner>> FlightReplanner::startWithRoute(std::shared_ptr<const CollisionWorld> world,
                                                                         std::vector<Eigen::Vector3d> points_m,
                                                                         const VehicleLimits& limits,
                                                                         const ReplanOptions& options,
                                                                         double start_world_s, PlannedRoute route) {
  if (!(options.period_s > 0.0) || !(options.horizon_s > 0.0) || !(options.check_step_s > 0.0)) {
    return make_error(ErrorCode::kInvalidArgument, "replan", "period, horizon and check step must be positive");
  }
  if (route.legs.size() + 1 != points_m.size() || route.built.knots.empty()) {
    return make_error(ErrorCode::kInvalidArgument, "route", "must have one leg per pair of points and a trajectory");
  }
  std::unique_ptr<FlightReplanner> r(new FlightReplanner());
  r->world_ = std::move(world);
  r->limits_ = limits;
  r->options_ = options;
  r->adopt(std::move(route), std::move(points_m), start_world_s);
  return r;
}

RouteOptions FlightReplanner::attemptOptions(const std::vector<Eigen::Vector3d>& points, double at_world_s,
                                             const TrajectoryState* state, int attempt) const {
  RouteOptions route = options_.route;
  route.seed = options_.route.seed + 1000ULL * revision_ + static_cast<std::uint64_t>(attempt);
  if (state) {
    if (options_.replan_leg_max_iterations > 0) route.leg_max_iterations = options_.replan_leg_max_iterations;
    if (options_.replan_max_repair_rounds >= 0) {
      route.trajectory.max_repair_rounds = std::min(route.trajectory.max_repair_rounds, options_.replan_max_repair_rounds);
    }
  }
  // Attempts look further ahead first (a path clear of where the obstacles will be), then less far
  // and with less room (a vehicle already near an obstacle must be allowed to start there).
  static constexpr double kWindowScale[] = {1.0, 2.0, 0.5, 0.0};
  static constexpr double kMarginScale[] = {1.0, 1.0, 0.5, 0.0};
  const int k = std::min(attempt, 3);
  ObstacleSnapshot snapshot;
  snapshot.time_s = at_world_s;
  snapshot.margin_m = kMarginScale[k] * options_.margin_m;
  snapshot.window_s = kWindowScale[k] * options_.window_s;
  // Only obstacles the vehicle can meet within the horizon matter now.
  snapshot.focus_m = points.front();
  double fastest = 0.0;
  for (const Obstacle& o : world_->obstacles()) {
    if (o.moving()) fastest = std::max(fastest, o.motion->speed_mps);
  }
  snapshot.focus_radius_m = (limits_.max_speed_mps + fastest) * options_.horizon_s;
  route.snapshot = snapshot;
  route.trajectory_start_world_s = at_world_s;
  route.moving_check_horizon_s = 0.0;  // conflicts in time are judged here, over the horizon
  if (state) {
    route.trajectory.boundary.start.velocity_mps = state->velocity_mps;
    route.trajectory.boundary.start.acceleration_mps2 = state->acceleration_mps2;
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

Result<std::pair<PlannedRoute, double>> FlightReplanner::bestCandidate(const std::vector<Eigen::Vector3d>& points,
                                                                       double at_world_s, const TrajectoryState* state,
                                                                       const TerminationCondition& stop,
                                                                       const std::vector<Eigen::Vector3d>* skip,
                                                                       bool first_only) const {
  std::optional<std::pair<PlannedRoute, double>> best;
  std::optional<Error> last_error;
  std::vector<std::vector<Eigen::Vector3d>> tried;
  if (skip) tried.push_back(*skip);
  for (int attempt = 0; attempt < std::max(1, options_.max_attempts); ++attempt) {
    if (auto reason = stop.reason(); reason != TerminationCondition::Reason::kNone) {
      std::string message = "stopped after " + std::to_string(attempt) + " attempts";
      if (last_error) message += " (last: " + last_error->describe() + ")";
      last_error = make_error(reason == TerminationCondition::Reason::kCancelled ? ErrorCode::kCancelled : ErrorCode::kTimeout,
                              "replan", message);
      break;
    }
    const RouteOptions route = attemptOptions(points, at_world_s, state, attempt);
    auto candidate = planRoutePaths(world_, points, route, stop);
    if (candidate.ok() && std::any_of(tried.begin(), tried.end(),
                                      [&](const auto& path) { return samePath(path, candidate->waypoints_m); })) {
      continue;  // the same path again: the same trajectory and the same conflict
    }
    // Past the deadline a path in hand is only worth building when nothing better is.
    if (candidate.ok() && best && stop.shouldStop()) break;
    if (candidate.ok()) {
      tried.push_back(candidate->waypoints_m);
      Status built = buildRouteTrajectory(world_, points, limits_, route, *candidate);
      if (!built.ok()) candidate = built.error();
    }
    if (!candidate.ok()) {
      last_error = candidate.error();
      if (candidate.error().code == ErrorCode::kInvalidArgument || candidate.error().code == ErrorCode::kCancelled) {
        break;
      }
      continue;
    }
    const double conflict = firstConflictS(candidate->built.trajectory, at_world_s, at_world_s, options_.horizon_s);
    if (!best || conflict > best->second) best.emplace(std::move(candidate.value()), conflict);
    if (std::isinf(conflict) || first_only) break;
  }
  if (!best) {
    return last_error.value_or(
        make_error(ErrorCode::kUnreachable, "replan", "every attempt found the path the vehicle is already on"));
  }
  return std::move(*best);
}

void FlightReplanner::adopt(PlannedRoute route, std::vector<Eigen::Vector3d> points, double start_world_s) {
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
      const bool valid = near && mayMeet(i, i + 1) ? world_->isSegmentValidDuring(points[i], times[i], points[i + 1], times[i + 1])
                                                   : world_->isStaticSegmentValid(points[i], points[i + 1]);
      if (!valid) return times[i];
    }
  }
  return std::numeric_limits<double>::infinity();
}

bool FlightReplanner::clearAhead(double now_s, double horizon_s) const {
  return std::isinf(firstConflictS(route_.built.trajectory, start_world_s_, now_s, horizon_s));
}

ReplanStep FlightReplanner::step(double now_s) {
  ReplanStep result;
  const auto started = std::chrono::steady_clock::now();
  if (finished(now_s)) return result;
  const double current_conflict = firstConflictS(route_.built.trajectory, start_world_s_, now_s, options_.horizon_s);
  if (std::isinf(current_conflict)) return result;
  result.conflict_ahead = true;
  const double takeover_s = now_s + options_.reaction_delay_s;
  const TrajectoryState state = stateAt(takeover_s);
  std::vector<Eigen::Vector3d> points{state.position_m};
  for (const Eigen::Vector3d& p : remainingPoints(takeover_s)) {
    if ((p - state.position_m).norm() > 1.0) points.push_back(p);
  }
  if (points.size() < 2) return result;  // already at the goal
  // The deadline counts from the start of the cycle: the check above is part of the latency.
  TerminationCondition stop = options_.replan_budget_ms > 0.0
                                  ? TerminationCondition::after(std::chrono::duration_cast<std::chrono::nanoseconds>(
                                        started + std::chrono::duration<double, std::milli>(options_.replan_budget_ms) -
                                        std::chrono::steady_clock::now()))
                                  : TerminationCondition();
  if (options_.cancel) stop.withCancelFlag(options_.cancel);
  const std::vector<Eigen::Vector3d> ahead = waypointsAhead(state.position_m, takeover_s);
  auto best = bestCandidate(points, takeover_s, &state, stop, ahead.empty() ? nullptr : &ahead);
  if (!best.ok() && best.error().code == ErrorCode::kTimeout && stop.reason() == TerminationCondition::Reason::kDeadline) {
    TerminationCondition cancel_only;
    if (options_.cancel) cancel_only.withCancelFlag(options_.cancel);
    best = bestCandidate(points, takeover_s, &state, cancel_only, ahead.empty() ? nullptr : &ahead, true);
  }
  result.latency_ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - started).count();
  if (!best.ok()) {
    result.failure = best.error();
    return result;
  }
  if (!(best->second > current_conflict)) {
    result.failure = make_error(ErrorCode::kUnreachable, "replan", "no candidate meets its first obstacle later than the current trajectory");
    return result;
  }
  adopt(std::move(best->first), std::move(points), takeover_s);
  ++revision_;
  result.replanned = true;
  return result;
}

}  // namespace skyroute
