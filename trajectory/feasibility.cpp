#include "trajectory/feasibility.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <numbers>
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
    case ViolationKind::kBelowMinAirspeed: return "below_min_airspeed";
    case ViolationKind::kBankAngle: return "bank_angle";
    case ViolationKind::kLoadFactor: return "load_factor";
    case ViolationKind::kClimbAngle: return "climb_angle";
    case ViolationKind::kDescentAngle: return "descent_angle";
  }
  return "unknown";
}

bool underLimitIsViolation(ViolationKind kind) {
  return kind == ViolationKind::kTurnRadius || kind == ViolationKind::kBelowMinAirspeed;
}

FixedWingState fixedWingState(const Eigen::Vector3d& v, const Eigen::Vector3d& a) {
  constexpr double kDeg = 180.0 / std::numbers::pi;
  FixedWingState state;
  const double horizontal = v.head<2>().norm();
  const double speed = v.norm();
  if (horizontal > 1e-9) {
    const double lateral = std::abs(v.x() * a.y() - v.y() * a.x()) / horizontal;
    state.bank_deg = std::atan(lateral / kStandardGravityMps2) * kDeg;
  }
  state.path_angle_deg = std::atan2(v.z(), horizontal) * kDeg;
  if (speed > 1e-9) {
    const Eigen::Vector3d along = v / speed;
    const Eigen::Vector3d lift = a + Eigen::Vector3d(0.0, 0.0, kStandardGravityMps2);
    state.load_factor = (lift - lift.dot(along) * along).norm() / kStandardGravityMps2;
  }
  return state;
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
  constexpr std::size_t kKinds = kViolationKinds;
  const double turn_radius_limit_m = limits.effectiveMinTurnRadiusM();
  const double min_airspeed_mps = limits.minAirspeedMps();
  const double max_load_factor = limits.maxLoadFactor();

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
        if (turn_radius_limit_m > 0.0 && radius * slack < turn_radius_limit_m)
          record(ViolationKind::kTurnRadius, t, radius, turn_radius_limit_m, true);
      }
      if (limits.fixedWing()) {
        const FixedWingState state = fixedWingState(v, a);
        report.min_speed_mps = std::min(report.min_speed_mps, speed);
        report.max_bank_deg = std::max(report.max_bank_deg, state.bank_deg);
        report.max_load_factor = std::max(report.max_load_factor, state.load_factor);
        report.max_climb_angle_deg = std::max(report.max_climb_angle_deg, state.path_angle_deg);
        report.max_descent_angle_deg = std::max(report.max_descent_angle_deg, -state.path_angle_deg);
        if (speed * slack < min_airspeed_mps)
          record(ViolationKind::kBelowMinAirspeed, t, speed, min_airspeed_mps, true);
        if (state.bank_deg > limits.max_bank_deg * slack)
          record(ViolationKind::kBankAngle, t, state.bank_deg, limits.max_bank_deg, false);
        if (state.load_factor > max_load_factor * slack)
          record(ViolationKind::kLoadFactor, t, state.load_factor, max_load_factor, false);
        if (state.path_angle_deg > limits.max_climb_angle_deg * slack)
          record(ViolationKind::kClimbAngle, t, state.path_angle_deg, limits.max_climb_angle_deg, false);
        if (-state.path_angle_deg > limits.max_descent_angle_deg * slack)
          record(ViolationKind::kDescentAngle, t, -state.path_angle_deg, limits.max_descent_angle_deg, false);
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
