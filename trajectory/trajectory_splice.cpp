#include "trajectory/trajectory_splice.hpp"

#include <algorithm>
#include <cmath>

#include "trajectory/spline7.hpp"

namespace skyroute {

namespace {

constexpr double kKnotSnapS = 1e-9;

// x(u0 + (u1 - u0) s) as a polynomial in s: b_m = sum_k a_k C(k, m) u0^(k - m) (u1 - u0)^m.
Polynomial7 reexpand(const Polynomial7& p, double u0, double u1) {
  const double span = u1 - u0;
  Polynomial7::Coefficients b{};
  double span_power = 1.0;
  for (int m = 0; m <= Polynomial7::kDegree; ++m) {
    // sum_k a_k C(k, m) u0^(k - m), k >= m: the m-th tau derivative at u0 over m!.
    b[static_cast<std::size_t>(m)] = p.evaluateTau(u0, m) / Polynomial7::fallingFactorial(m, m) * span_power;
    span_power *= span;
  }
  return Polynomial7(b);
}

}  // namespace

Segment subSegment(const Segment& segment, double from_s, double to_s) {
  Segment out;
  out.duration_s = to_s - from_s;
  const double u0 = segment.duration_s > 0.0 ? from_s / segment.duration_s : 0.0;
  const double u1 = segment.duration_s > 0.0 ? to_s / segment.duration_s : 0.0;
  for (std::size_t axis = 0; axis < 3; ++axis) out.axes[axis] = reexpand(segment.axes[axis], u0, u1);
  return out;
}

std::vector<Segment> segmentsBetween(const Trajectory& trajectory, double from_s, double to_s) {
  std::vector<Segment> out;
  if (trajectory.empty()) return out;
  from_s = std::clamp(from_s, 0.0, trajectory.duration_s());
  to_s = std::clamp(to_s, 0.0, trajectory.duration_s());
  if (!(to_s - from_s > kKnotSnapS)) return out;
  const auto& segments = trajectory.segments();
  const auto& knots = trajectory.knotTimes();
  for (std::size_t i = trajectory.segmentIndexAt(from_s); i < segments.size() && knots[i] < to_s - kKnotSnapS; ++i) {
    const double a = std::max(from_s, knots[i]) - knots[i];
    const double b = std::min(to_s, knots[i + 1]) - knots[i];
    if (!(b - a > kKnotSnapS)) continue;
    const bool whole = a <= kKnotSnapS && b >= segments[i].duration_s - kKnotSnapS;
    out.push_back(whole ? segments[i] : subSegment(segments[i], a, b));
  }
  return out;
}

std::optional<Segment> stopSegment(const TrajectoryState& start, const VehicleLimits& limits, const StopOptions& options) {
  const double speed = start.velocity_mps.norm();
  const double brake = std::max(1e-6, options.brake_accel_share * limits.max_accel_mps2);
  // At least long enough for the start acceleration to ease off at the jerk it starts with.
  double duration_s = std::max({speed / brake, 1.0, start.acceleration_mps2.norm() / brake});
  FeasibilityOptions check;
  for (int k = 0; k < std::max(1, options.durations_tried); ++k, duration_s *= 1.3) {
    // Along a steady deceleration the stop covers v T / 2; the start acceleration adds its share.
    const Eigen::Vector3d end = start.position_m + start.velocity_mps * (0.5 * duration_s) +
                                start.acceleration_mps2 * (duration_s * duration_s / 12.0);
    KnotDerivatives from;
    from.velocity_mps = start.velocity_mps;
    from.acceleration_mps2 = start.acceleration_mps2;
    from.jerk_mps3 = start.jerk_mps3;
    if ((end - start.position_m).norm() < 1e-3) break;  // at rest already: nothing to stop
    auto segments = hermiteSpline({start.position_m, end}, {duration_s}, {from, KnotDerivatives{}});
    if (!segments.ok() || segments->size() != 1) return std::nullopt;
    if (checkFeasibility(Trajectory(segments.value()), limits, check).ok()) return segments->front();
  }
  return std::nullopt;
}

}  // namespace skyroute
