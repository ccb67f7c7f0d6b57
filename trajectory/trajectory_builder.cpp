#include "trajectory/trajectory_builder.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <map>
#include <set>

namespace skyroute {

std::string_view to_string(TrajectoryStatus status) {
  switch (status) {
    case TrajectoryStatus::kFeasible: return "feasible";
    case TrajectoryStatus::kRepaired: return "repaired";
    case TrajectoryStatus::kInfeasible: return "infeasible";
  }
  return "unknown";
}

namespace {

std::string format(const char* fmt, double a, double b = 0.0, double c = 0.0, double d = 0.0) {
  char buffer[256];
  std::snprintf(buffer, sizeof(buffer), fmt, a, b, c, d);
  return buffer;
}

std::string describe(const Violation& v) {
  const std::string kind(to_string(v.kind));
  if (v.kind == ViolationKind::kCollision)
    return "collision in segment " + std::to_string(v.segment) + format(" at t=%.2f s", v.time_s);
  return kind + " in segment " + std::to_string(v.segment) +
         format(" at t=%.2f s: %.3f (limit %.3f)", v.time_s, v.value, v.limit);
}

// How much longer a segment must take to bring the violation within its limit (> 1), or 0 when
// stretching time cannot fix it.
double stretchFactor(const Violation& v) {
  switch (v.kind) {
    case ViolationKind::kSpeed:
    case ViolationKind::kClimbRate:
    case ViolationKind::kDescentRate: return v.value / v.limit;
    case ViolationKind::kAcceleration: return std::sqrt(v.value / v.limit);
    case ViolationKind::kTurnRadius:
    case ViolationKind::kCollision: return 0.0;
  }
  return 0.0;
}

Status validateOptions(const TrajectoryOptions& o) {
  auto bad = [](const char* field, const std::string& why) { return make_error(ErrorCode::kInvalidArgument, field, why); };
  if (!std::isfinite(o.waypoint_spacing_m) || o.waypoint_spacing_m < 0.0)
    return bad("options.waypoint_spacing_m", "must be >= 0 and finite (0 = no extra waypoints)");
  if (!std::isfinite(o.feasibility.dt_s) || o.feasibility.dt_s <= 0.0)
    return bad("options.feasibility.dt_s", "must be positive and finite");
  if (!std::isfinite(o.feasibility.relative_tolerance) || o.feasibility.relative_tolerance < 0.0)
    return bad("options.feasibility.relative_tolerance", "must be >= 0 and finite");
  if (o.max_repair_rounds < 0) return bad("options.max_repair_rounds", "must be >= 0");
  if (!std::isfinite(o.min_waypoint_separation_m) || o.min_waypoint_separation_m < 0.0)
    return bad("options.min_waypoint_separation_m", "must be >= 0 and finite");
  if (!std::isfinite(o.min_split_length_m) || o.min_split_length_m <= 0.0)
    return bad("options.min_split_length_m", "must be positive and finite");
  const std::pair<const char*, const Eigen::Vector3d*> ends[] = {
      {"boundary.start.velocity_mps", &o.boundary.start.velocity_mps},
      {"boundary.start.acceleration_mps2", &o.boundary.start.acceleration_mps2},
      {"boundary.start.jerk_mps3", &o.boundary.start.jerk_mps3},
      {"boundary.end.velocity_mps", &o.boundary.end.velocity_mps},
      {"boundary.end.acceleration_mps2", &o.boundary.end.acceleration_mps2},
      {"boundary.end.jerk_mps3", &o.boundary.end.jerk_mps3}};
  for (const auto& [name, value] : ends)
    if (!value->allFinite()) return bad(name, "is NaN or infinite");
  return Status::success();
}

}  // namespace

Result<BuiltTrajectory> buildTrajectory(const std::vector<Eigen::Vector3d>& waypoints, const VehicleLimits& limits,
                                        const TrajectoryOptions& options, const MotionCheck* collision) {
  const auto started = std::chrono::steady_clock::now();
  if (Status s = validateWaypoints(waypoints, options.min_waypoint_separation_m); !s) return s.error();
  if (Status s = limits.validate(); !s) return s.error();
  if (Status s = validateOptions(options); !s) return s.error();

  DensifiedPath path = densifyWaypoints(waypoints, options.waypoint_spacing_m);
  std::vector<Eigen::Vector3d> knots = std::move(path.points);
  TimeAllocationOptions allocation = options.time_allocation;
  allocation.start_speed_mps = options.boundary.start.velocity_mps.norm();
  allocation.end_speed_mps = options.boundary.end.velocity_mps.norm();
  Result<std::vector<double>> allocated = allocateTimes(knots, limits, allocation);
  if (!allocated) return allocated.error();
  std::vector<double> durations = std::move(allocated.value());

  BuiltTrajectory built;
  TrajectoryBuildReport& report = built.report;
  report.input_waypoints = waypoints.size();
  const int local_rounds = options.max_repair_rounds / 2;  // then stretch everything uniformly

  for (int round = 0;; ++round) {
    Result<std::vector<Segment>> segments = solveMinimumSnapSpline(knots, durations, options.boundary);
    if (!segments) return segments.error();
    built.trajectory = Trajectory(std::move(segments.value()));
    report.final_check = checkFeasibility(built.trajectory, limits, options.feasibility, collision);
    report.repair_rounds = round;
    if (report.final_check.ok()) {
      report.status = round == 0 ? TrajectoryStatus::kFeasible : TrajectoryStatus::kRepaired;
      break;
    }
    report.status = TrajectoryStatus::kInfeasible;
    const std::vector<Violation>& violations = report.final_check.violations;
    if (!options.repair) {
      report.failure_reason = "repair disabled; first violation: " + describe(violations.front());
      break;
    }
    if (round >= options.max_repair_rounds) {
      report.failure_reason = "still infeasible after " + std::to_string(round) +
                              " repair rounds; first violation: " + describe(violations.front());
      break;
    }

    // Collisions: split the segment at the middle of its chord. Knots lie on the input polyline and
    // no input waypoint lies between two consecutive knots, so the chord is part of the input path;
    // if the chord itself is blocked no amount of splitting helps.
    std::set<std::size_t> to_split;
    std::map<std::size_t, double> stretch;  // segment -> factor
    std::string unrepairable;
    const std::vector<double>& t = built.trajectory.knotTimes();
    for (const Violation& v : violations) {
      if (v.kind == ViolationKind::kCollision) {
        const std::size_t s = v.segment;
        if (collision && !(*collision)(knots[s], t[s], knots[s + 1], t[s + 1])) {
          unrepairable = "the straight path between knots " + std::to_string(s) + " and " + std::to_string(s + 1) +
                         format(" (t=%.2f..%.2f s) is itself blocked (terrain or obstacle): the path needs replanning",
                                t[s], t[s + 1]);
          break;
        }
        if ((knots[s + 1] - knots[s]).norm() < 2.0 * options.min_split_length_m) {
          unrepairable = "the curve in segment " + std::to_string(s) +
                         " still leaves the clear corridor after splitting it down to " +
                         format("%.2f m", (knots[s + 1] - knots[s]).norm());
          break;
        }
        to_split.insert(s);
      } else if (v.kind == ViolationKind::kTurnRadius) {
        unrepairable = describe(v) +
                       ": the path's corner is too sharp for this vehicle (stretching time does not widen a turn); "
                       "the path needs smoothing or replanning";
        break;
      } else {
        stretch[v.segment] = std::max(stretch[v.segment], stretchFactor(v));
      }
    }
    if (!unrepairable.empty()) {
      report.failure_reason = unrepairable;
      break;
    }

    // Stretch first (indices refer to the current segments), then split from the back.
    if (!stretch.empty()) {
      double worst = 1.0;
      for (const auto& [s, f] : stretch) worst = std::max(worst, f);
      const double margin = 1.03;
      if (round < local_rounds) {
        std::vector<double> factor(durations.size(), 1.0);
        for (const auto& [s, f] : stretch) {
          const double k = std::min(4.0, f * margin);
          factor[s] = std::max(factor[s], k);
          // Neighbours share the joint's derivatives; stretch them part way so the joint eases too.
          if (s > 0) factor[s - 1] = std::max(factor[s - 1], std::sqrt(k));
          if (s + 1 < factor.size()) factor[s + 1] = std::max(factor[s + 1], std::sqrt(k));
        }
        for (std::size_t s = 0; s < durations.size(); ++s) durations[s] *= factor[s];
        report.repairs.push_back("stretched " + std::to_string(stretch.size()) + " segment(s) in time by up to " +
                                 format("%.1f%%", (std::min(4.0, worst * margin) - 1.0) * 100.0) + " (" +
                                 describe(*std::find_if(violations.begin(), violations.end(), [](const Violation& v) {
                                   return v.kind != ViolationKind::kCollision;
                                 })) +
                                 ")");
      } else {
        const double k = worst * margin;
        for (double& d : durations) d *= k;
        report.repairs.push_back("stretched the whole trajectory in time by " + format("%.1f%%", (k - 1.0) * 100.0));
      }
    }
    if (!to_split.empty()) {
      for (auto it = to_split.rbegin(); it != to_split.rend(); ++it) {
        const std::size_t s = *it;
        const Eigen::Vector3d middle = 0.5 * (knots[s] + knots[s + 1]);
        const double half = 0.5 * durations[s];
        knots.insert(knots.begin() + static_cast<std::ptrdiff_t>(s + 1), middle);
        durations[s] = half;
        durations.insert(durations.begin() + static_cast<std::ptrdiff_t>(s + 1), half);
      }
      report.repairs.push_back("added " + std::to_string(to_split.size()) +
                               " waypoint(s) on the checked path where the curve collided (first in segment " +
                               std::to_string(*to_split.begin()) + ")");
    }
  }
  built.knots = std::move(knots);
  report.knots = built.knots.size();
  report.build_ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - started).count();
  return built;
}

}  // namespace skyroute
