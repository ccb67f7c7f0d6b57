#include "trajectory/feasibility.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <optional>

namespace skyroute {

std::string_view to_string(ViolationKind kind) {
  switch (kind) {
    case ViolationKind::kSpeed: return "speed";
    case ViolationKind::kAcceleration: return "acceleration";
    case ViolationKind::kClimbRate: return "climb_rate";
    case ViolationKind::kDescentRate: return "descent_rate";
    case ViolationKind::kTurnRadius: return "turn_radius";
    case ViolationKind::kCollision: return "collision";
  }
  return "unknown";
}

bool FeasibilityReport::has(ViolationKind kind) const {
  return std::any_of(violations.begin(), violations.end(), [&](const Violation& v) { return v.kind == kind; });
}

FeasibilityReport checkFeasibility(const Trajectory& trajectory, const VehicleLimits& limits,
                                   const FeasibilityOptions& options, const MotionCheck* collision) {
  FeasibilityReport report;
  const double dt = options.dt_s > 0.0 && std::isfinite(options.dt_s) ? options.dt_s : 0.05;
  const double slack = 1.0 + options.relative_tolerance;
  const auto& segments = trajectory.segments();
  const auto& knot_times = trajectory.knotTimes();
  constexpr std::size_t kKinds = 6;

  for (std::size_t s = 0; s < segments.size(); ++s) {
    if (options.stop_requested && options.stop_requested()) {
      report.stopped = true;
      return report;
    }
    const Segment& segment = segments[s];
    // Worst "excess" per kind in this segment: value (for turn radius the smallest radius).
    std::array<std::optional<Violation>, kKinds> worst;
    auto record = [&](ViolationKind kind, double t, double value, double limit, bool smaller_is_worse) {
      auto& w = worst[static_cast<std::size_t>(kind)];
      if (!w || (smaller_is_worse ? value < w->value : value > w->value)) w = Violation{kind, s, t, value, limit};
    };
    const int steps = std::max(1, static_cast<int>(std::ceil(segment.duration_s / dt)));
    Eigen::Vector3d previous_position = Eigen::Vector3d::Zero();
    double previous_time = 0.0;
    bool collision_found = false;
    for (int k = 0; k <= steps; ++k) {
      const double local = segment.duration_s * k / steps;
      const double t = knot_times[s] + local;
      Eigen::Vector3d p, v, a;
      const double tau = static_cast<double>(k) / steps;
      for (int axis = 0; axis < 3; ++axis) {
        double d[3];
        segment.axes[static_cast<std::size_t>(axis)].evaluateTimeUpTo(tau, 2, segment.duration_s, d);
        p(axis) = d[0];
        v(axis) = d[1];
        a(axis) = d[2];
      }
      ++report.samples;
      const double speed = v.norm();
      const double accel = a.norm();
      report.max_speed_mps = std::max(report.max_speed_mps, speed);
      report.max_accel_mps2 = std::max(report.max_accel_mps2, accel);
      report.max_climb_mps = std::max(report.max_climb_mps, v.z());
      report.max_descent_mps = std::max(report.max_descent_mps, -v.z());
      if (speed > limits.max_speed_mps * slack) record(ViolationKind::kSpeed, t, speed, limits.max_speed_mps, false);
      if (accel > limits.max_accel_mps2 * slack)
        record(ViolationKind::kAcceleration, t, accel, limits.max_accel_mps2, false);
      if (v.z() > limits.max_climb_mps * slack) record(ViolationKind::kClimbRate, t, v.z(), limits.max_climb_mps, false);
      if (-v.z() > limits.max_descent_mps * slack)
        record(ViolationKind::kDescentRate, t, -v.z(), limits.max_descent_mps, false);
      if (speed >= std::max(limits.turn_check_min_speed_mps, 1e-9)) {
        // Radius of curvature |v|^3 / |v x a|.
        const double cross = v.cross(a).norm();
        const double radius = cross > 0.0 ? speed * speed * speed / cross : std::numeric_limits<double>::infinity();
        report.min_turn_radius_m = std::min(report.min_turn_radius_m, radius);
        if (limits.min_turn_radius_m > 0.0 && radius * slack < limits.min_turn_radius_m)
          record(ViolationKind::kTurnRadius, t, radius, limits.min_turn_radius_m, true);
      }
      if (collision && k > 0 && !collision_found) {
        ++report.motions_checked;
        if (!(*collision)(previous_position, previous_time, p, t)) {
          record(ViolationKind::kCollision, previous_time, 0.0, 0.0, false);
          collision_found = true;  // one is enough to mark the segment
        }
      }
      previous_position = p;
      previous_time = t;
    }
    for (const auto& w : worst)
      if (w) report.violations.push_back(*w);
  }
  return report;
}

}  // namespace skyroute
