#include "trajectory/time_allocation.hpp"

#include <algorithm>
#include <cmath>
#include <string>

#include "planning/core/enum_names.hpp"

namespace skyroute {

std::string_view to_string(TimeAllocationMethod method) {
  constexpr EnumName<TimeAllocationMethod> kNames[] = {{TimeAllocationMethod::kConstantSpeed, "constant_speed"},
                                                       {TimeAllocationMethod::kTrapezoidal, "trapezoidal"}};
  return enumName(kNames, method);
}

Status validateWaypoints(const std::vector<Eigen::Vector3d>& waypoints, double min_separation_m) {
  if (waypoints.size() < 2)
    return make_error(ErrorCode::kInvalidArgument, "waypoints",
                      "need at least 2 waypoints, got " + std::to_string(waypoints.size()));
  for (std::size_t i = 0; i < waypoints.size(); ++i) {
    const std::string field = "waypoints[" + std::to_string(i) + "]";
    if (!waypoints[i].allFinite())
      return make_error(ErrorCode::kInvalidArgument, field, "coordinate is NaN or infinite");
    if (i > 0 && (waypoints[i] - waypoints[i - 1]).norm() < min_separation_m)
      return make_error(ErrorCode::kInvalidArgument, field,
                        "duplicates waypoints[" + std::to_string(i - 1) + "] (closer than " +
                            std::to_string(min_separation_m) + " m)");
  }
  return Status::success();
}

namespace {

Status validateOptions(const TimeAllocationOptions& options) {
  if (!std::isfinite(options.accel_fraction) || options.accel_fraction <= 0.0 || options.accel_fraction > 1.0)
    return make_error(ErrorCode::kInvalidArgument, "time_allocation.accel_fraction",
                      "must be in (0, 1], got " + std::to_string(options.accel_fraction));
  if (!std::isfinite(options.start_speed_mps) || options.start_speed_mps < 0.0)
    return make_error(ErrorCode::kInvalidArgument, "time_allocation.start_speed_mps",
                      "must be >= 0 and finite, got " + std::to_string(options.start_speed_mps));
  if (!std::isfinite(options.end_speed_mps) || options.end_speed_mps < 0.0)
    return make_error(ErrorCode::kInvalidArgument, "time_allocation.end_speed_mps",
                      "must be >= 0 and finite, got " + std::to_string(options.end_speed_mps));
  return Status::success();
}

// Cruise speed of one leg: V_ref, lowered so the vertical component stays within the climb or
// descent limit.
double cruiseSpeed(const Eigen::Vector3d& a, const Eigen::Vector3d& b, const VehicleLimits& limits) {
  const double length = (b - a).norm();
  const double dz = b.z() - a.z();
  double cruise = limits.v_ref_mps;
  if (dz > 0.0) cruise = std::min(cruise, limits.max_climb_mps * length / dz);
  if (dz < 0.0) cruise = std::min(cruise, limits.max_descent_mps * length / -dz);
  return cruise;
}

// Time to cover length_m with speed min(cruise, accelerating from v0, braking to v1) at accel a.
double trapezoidTime(double length_m, double v0, double v1, double cruise, double accel) {
  // Faster than the cruise speed at the start (a replan taking over from a vehicle flying faster
  // than this segment allows, e.g. before a climb): it slows down to cruise first. Timing it as
  // if it started at cruise gave the segment too much time for its fixed start velocity, and
  // the curve overshot.
  if (v0 > cruise) {
    const double slowing_m = (v0 * v0 - cruise * cruise) / (2.0 * accel);
    if (slowing_m >= length_m) {
      const double end = std::sqrt(std::max(0.0, v0 * v0 - 2.0 * accel * length_m));
      return 2.0 * length_m / (v0 + end);
    }
    return (v0 - cruise) / accel + trapezoidTime(length_m - slowing_m, cruise, v1, cruise, accel);
  }
  v1 = std::min(v1, cruise);
  const double s_accel = (cruise * cruise - v0 * v0) / (2.0 * accel);
  const double s_brake = (cruise * cruise - v1 * v1) / (2.0 * accel);
  if (s_accel + s_brake <= length_m)
    return (cruise - v0) / accel + (length_m - s_accel - s_brake) / cruise + (cruise - v1) / accel;
  // Triangle: accelerate until the braking curve, then brake.
  const double s_meet = std::clamp((v1 * v1 - v0 * v0 + 2.0 * accel * length_m) / (4.0 * accel), 0.0, length_m);
  const double peak = std::sqrt(v0 * v0 + 2.0 * accel * s_meet);
  return std::max(0.0, (peak - v0) / accel) + std::max(0.0, (peak - v1) / accel);
}

}  // namespace

std::vector<double> waypointSpeedLimits(const std::vector<Eigen::Vector3d>& waypoints, const VehicleLimits& limits,
                                        const TimeAllocationOptions& options) {
  const std::size_t n = waypoints.size();
  std::vector<double> speed(n, limits.v_ref_mps);
  if (n < 2) return speed;
  const double accel = options.accel_fraction * limits.max_accel_mps2;
  std::vector<double> length(n - 1), cruise(n - 1);
  for (std::size_t j = 0; j + 1 < n; ++j) {
    length[j] = (waypoints[j + 1] - waypoints[j]).norm();
    cruise[j] = cruiseSpeed(waypoints[j], waypoints[j + 1], limits);
  }
  speed.front() = options.start_speed_mps;
  speed.back() = options.end_speed_mps;
  for (std::size_t i = 1; i + 1 < n; ++i) {
    double v = std::min(cruise[i - 1], cruise[i]);
    // Turn: the largest arc tangent to both legs within half the shorter leg has radius
    // d / tan(deflection / 2); its lateral acceleration v^2 / r stays within `accel`.
    const Eigen::Vector3d in = (waypoints[i] - waypoints[i - 1]).normalized();
    const Eigen::Vector3d out = (waypoints[i + 1] - waypoints[i]).normalized();
    const double deflection = std::atan2(in.cross(out).norm(), in.dot(out));
    if (deflection > 1e-9) {
      const double half_leg = 0.5 * std::min(length[i - 1], length[i]);
      const double radius = half_leg / std::tan(0.5 * deflection);
      v = std::min(v, std::sqrt(accel * std::max(0.0, radius)));
    }
    speed[i] = v;
  }
  // Reachability: forward (accelerating) and backward (braking) passes.
  for (std::size_t i = 1; i < n; ++i)
    speed[i] = std::min(speed[i], std::sqrt(speed[i - 1] * speed[i - 1] + 2.0 * accel * length[i - 1]));
  for (std::size_t i = n - 1; i-- > 0;)
    speed[i] = std::min(speed[i], std::sqrt(speed[i + 1] * speed[i + 1] + 2.0 * accel * length[i]));
  return speed;
}

Result<std::vector<double>> allocateTimes(const std::vector<Eigen::Vector3d>& waypoints, const VehicleLimits& limits,
                                          const TimeAllocationOptions& options) {
  if (Status s = validateWaypoints(waypoints); !s) return s.error();
  if (Status s = limits.validate(); !s) return s.error();
  if (Status s = validateOptions(options); !s) return s.error();
  std::vector<double> durations(waypoints.size() - 1);
  if (options.method == TimeAllocationMethod::kConstantSpeed) {
    // Seed 003 eq. 3.
    for (std::size_t j = 0; j < durations.size(); ++j)
      durations[j] = (waypoints[j + 1] - waypoints[j]).norm() / limits.v_ref_mps;
    return durations;
  }
  const std::vector<double> speed = waypointSpeedLimits(waypoints, limits, options);
  const double accel = options.accel_fraction * limits.max_accel_mps2;
  for (std::size_t j = 0; j < durations.size(); ++j) {
    durations[j] = trapezoidTime((waypoints[j + 1] - waypoints[j]).norm(), speed[j], speed[j + 1],
                                 cruiseSpeed(waypoints[j], waypoints[j + 1], limits), accel);
  }
  return durations;
}

DensifiedPath densifyWaypoints(const std::vector<Eigen::Vector3d>& waypoints, double spacing_m) {
  DensifiedPath out;
  if (waypoints.empty()) return out;
  out.points.push_back(waypoints.front());
  out.original_indices.push_back(0);
  for (std::size_t j = 1; j < waypoints.size(); ++j) {
    const Eigen::Vector3d& a = waypoints[j - 1];
    const Eigen::Vector3d& b = waypoints[j];
    const double length = (b - a).norm();
    int pieces = 1;
    if (spacing_m > 0.0 && std::isfinite(length))
      pieces = std::max(1, static_cast<int>(std::ceil(length / spacing_m - 1e-9)));
    for (int k = 1; k < pieces; ++k) out.points.push_back(a + (b - a) * (static_cast<double>(k) / pieces));
    out.points.push_back(b);
    out.original_indices.push_back(out.points.size() - 1);
  }
  return out;
}

}  // namespace skyroute
