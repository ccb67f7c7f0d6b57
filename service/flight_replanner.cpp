#include "service/flight_replanner.hpp"

#include <algorithm>
#include <chrono>
#include <limits>

namespace skyroute {

Result<std::unique_ptr<FlightReplanner>> FlightReplanner::start(std::shared_ptr<const CollisionWorld> world,
                                                                std::vector<Eigen::Vector3d> points_m,
                                                                const VehicleLimits& limits,
                                                                const ReplanOptions& options, double start_world_s) {
  if (!(options.period_s > 0.0) || !(options.horizon_s > 0.0) || !(options.check_step_s > 0.0)) {
    return make_error(ErrorCode::kInvalidArgument, "replan", "period, horizon and check step must be positive");
  }
  std::unique_ptr<FlightReplanner> r(new FlightReplanner());
  r->world_ = std::move(world);
  r->limits_ = limits;
  r->options_ = options;
  auto first = r->bestCandidate(points_m, start_world_s, nullptr);
  if (!first.ok()) return first.error();
  r->adopt(std::move(first->first), std::move(points_m), start_world_s);
  return r;
}

Result<PlannedRoute> FlightReplanner::planFrom(const std::vector<Eigen::Vector3d>& points, double at_world_s,
                                               const TrajectoryState* state, int attempt) const {
  RouteOptions route = options_.route;
  route.seed = options_.route.seed + 1000ULL * revision_ + static_cast<std::uint64_t>(attempt);
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
  TerminationCondition stop;
  if (options_.cancel) stop.withCancelFlag(options_.cancel);
  return planRoute(world_, points, limits_, route, stop);
}

Result<std::pair<PlannedRoute, double>> FlightReplanner::bestCandidate(const std::vector<Eigen::Vector3d>& points,
                                                                       double at_world_s,
                                                                       const TrajectoryState* state) const {
  std::optional<std::pair<PlannedRoute, double>> best;
  std::optional<Error> last_error;
  for (int attempt = 0; attempt < std::max(1, options_.max_attempts); ++attempt) {
    auto candidate = planFrom(points, at_world_s, state, attempt);
    if (!candidate.ok()) {
      last_error = candidate.error();
      if (candidate.error().code == ErrorCode::kInvalidArgument ||
          candidate.error().code == ErrorCode::kCancelled)
        break;
      continue;
    }
    const double conflict = firstConflictS(candidate->built.trajectory, at_world_s, at_world_s, options_.horizon_s);
    if (!best || conflict > best->second) best.emplace(std::move(candidate.value()), conflict);
    if (std::isinf(conflict)) break;
  }
  if (!best) return last_error.value_or(make_error(ErrorCode::kInternal, "replan", "no attempt made"));
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

double FlightReplanner::firstConflictS(const Trajectory& trajectory, double start_world_s, double from_s,
                                       double horizon_s) const {
  const double end = std::min(from_s + horizon_s, start_world_s + trajectory.duration_s());
  for (double t = from_s; t < end; t += options_.check_step_s) {
    const double t1 = std::min(t + options_.check_step_s, end);
    const Eigen::Vector3d a = trajectory.evaluate(t - start_world_s, Derivative::kPosition);
    const Eigen::Vector3d b = trajectory.evaluate(t1 - start_world_s, Derivative::kPosition);
    if (!world_->isSegmentValidDuring(a, t, b, t1)) return t;
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
  auto best = bestCandidate(points, takeover_s, &state);
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
