// FlightReplanner::reroute: the rest of a flight planned again through its points in a new order
// (the daemon's live re-ordering, mission_reorder.hpp). Kept apart from the conflict-driven
// cycle in flight_replanner.cpp: it shares the attempts, the takeover and the adoption, not the
// decision of when to replan.
#include <chrono>
#include <cmath>

#include "service/flight_replanner.hpp"

namespace skyroute {

double FlightReplanner::takeoverS(double now_s) const {
  return takeoverTime(now_s, firstConflictS(route_.built.trajectory, start_world_s_, now_s, options_.horizon_s));
}

ReplanStep FlightReplanner::reroute(double now_s, const std::vector<Eigen::Vector3d>& points_m) {
  ReplanStep result;
  const auto started = std::chrono::steady_clock::now();
  auto done = [&](std::optional<Error> failure) {
    result.failure = std::move(failure);
    result.latency_ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - started).count();
    return result;
  };
  if (finished(now_s)) return done(make_error(ErrorCode::kInvalidArgument, "reroute", "the flight has ended"));
  const double current_conflict = currentConflictS(now_s);
  deadline_holds_ = false;  // a new order is no reason to hold
  result.conflict_ahead = !std::isinf(current_conflict);
  const double takeover_s = takeoverTime(now_s, current_conflict);
  result.takeover_s = takeover_s;
  const TrajectoryState state = stateAt(takeover_s);
  std::vector<Eigen::Vector3d> points{state.position_m};
  for (const Eigen::Vector3d& p : points_m) {
    if ((p - state.position_m).norm() > 1.0) points.push_back(p);
  }
  if (points.size() < 2) return done(make_error(ErrorCode::kInvalidArgument, "reroute", "no point left to fly to"));
  TerminationCondition stop = cycleStop(started);
  cycle_attempts_ = 0;
  auto whole = [&](int attempt) {
    // The current path goes through the old order: no candidate can repeat it.
    AttemptPlan plan = wholePlan(points, {}, attempt);
    plan.conflict_in_s = current_conflict <= now_s + options_.horizon_s ? current_conflict - takeover_s : options_.window_s;
    return std::optional<AttemptPlan>(std::move(plan));
  };
  Result<Candidate> best = bestCandidate(whole, takeover_s, &state, stop);
  if (!best.ok() && best.error().code == ErrorCode::kTimeout && deadlinePassed(stop)) {
    TerminationCondition cancel_only;
    if (options_.cancel) cancel_only.withCancelFlag(options_.cancel);
    best = bestCandidate(whole, takeover_s, &state, cancel_only, true);
  }
  if (!best.ok()) return done(best.error());
  // Only a clear trajectory goes out (the audit publishes none known to meet an obstacle).
  if (!std::isinf(best->conflict_s)) {
    return done(make_error(ErrorCode::kUnreachable, "reroute", "the new order's trajectory meets an obstacle"));
  }
  Candidate adopted = withKeptPart(std::move(best.value()), std::max(now_s, start_world_s_), takeover_s);
  if (auto refused = auditRefusal(adopted.route.built.trajectory, std::max(now_s, start_world_s_), now_s,
                                      revision_ + 1)) {
    return done(refused);
  }
  adopt(std::move(adopted.route), std::move(adopted.points), std::max(now_s, start_world_s_));
  holding_ = false;
  ++revision_;
  failed_cycles_ = 0;
  result.replanned = true;
  return done(std::nullopt);
}

}  // namespace skyroute
