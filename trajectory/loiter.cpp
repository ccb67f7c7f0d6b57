#include "trajectory/loiter.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>

namespace skyroute {

double LoiterCircle::turnS() const { return 2.0 * std::numbers::pi * radius_m / speed_mps; }

double LoiterCircle::arcAngleRad() const {
  return (turning_left ? 1.0 : -1.0) * 2.0 * std::numbers::pi / static_cast<double>(std::max(1, arcs_per_turn));
}

Eigen::Vector3d LoiterCircle::positionAt(double theta_rad) const {
  return center_m + radius_m * Eigen::Vector3d(std::cos(theta_rad), std::sin(theta_rad), 0.0);
}

KnotDerivatives LoiterCircle::derivativesAt(double theta_rad) const {
  const double side = turning_left ? 1.0 : -1.0;
  const Eigen::Vector3d radial(std::cos(theta_rad), std::sin(theta_rad), 0.0);
  const Eigen::Vector3d tangent = side * Eigen::Vector3d(-std::sin(theta_rad), std::cos(theta_rad), 0.0);
  const double omega = speed_mps / radius_m;
  KnotDerivatives d;
  d.velocity_mps = speed_mps * tangent;
  d.acceleration_mps2 = -speed_mps * omega * radial;
  d.jerk_mps3 = -omega * omega * d.velocity_mps;
  return d;
}

std::vector<Segment> loiterArcs(const LoiterCircle& circle, double from_rad, std::size_t arcs) {
  if (arcs == 0) return {};
  const double step = circle.arcAngleRad();
  const double arc_s = circle.turnS() / static_cast<double>(std::max(1, circle.arcs_per_turn));
  std::vector<Eigen::Vector3d> points;
  std::vector<KnotDerivatives> knots;
  for (std::size_t k = 0; k <= arcs; ++k) {
    const double theta = from_rad + step * static_cast<double>(k);
    points.push_back(circle.positionAt(theta));
    knots.push_back(circle.derivativesAt(theta));
  }
  auto segments = hermiteSpline(points, std::vector<double>(arcs, arc_s), knots);
  return segments.ok() ? std::move(segments.value()) : std::vector<Segment>{};
}

Result<LoiterPath> loiterFrom(const TrajectoryState& entry, const LoiterShape& shape, double circle_s) {
  const Eigen::Vector3d v0 = entry.velocity_mps;
  const double horizontal = std::hypot(v0.x(), v0.y());
  if (!(horizontal > 1e-3)) {
    return make_error(ErrorCode::kInvalidArgument, "loiter.entry", "no horizontal velocity to turn from");
  }
  if (!(shape.radius_m > 0.0) || !std::isfinite(shape.radius_m) || !(shape.speed_mps > 0.0) ||
      !std::isfinite(shape.speed_mps) || !(shape.join_turn_rad > 0.0) || !(shape.lead_m >= 0.0)) {
    return make_error(ErrorCode::kInvalidArgument, "loiter.shape",
                      "radius, speed and join turn must be positive and finite, the lead >= 0");
  }
  const double side = shape.turning_left ? 1.0 : -1.0;
  const Eigen::Vector3d along(v0.x() / horizontal, v0.y() / horizontal, 0.0);
  const Eigen::Vector3d inward = side * Eigen::Vector3d(-along.y(), along.x(), 0.0);
  LoiterPath out;
  LoiterCircle& c = out.circle;
  c.radius_m = shape.radius_m;
  c.speed_mps = shape.speed_mps;
  c.turning_left = shape.turning_left;
  c.arcs_per_turn = std::max(1, shape.arcs_per_turn);
  // The entry flies the lead and the joining arc at the mean of its end speeds.
  const double entry_m = shape.lead_m + shape.radius_m * shape.join_turn_rad;
  const double entry_s = entry_m / (0.5 * (v0.norm() + shape.speed_mps));
  const Eigen::Vector3d touch = entry.position_m + shape.lead_m * along;
  c.center_m = touch + shape.radius_m * inward;
  c.center_m.z() = entry.position_m.z() + 0.5 * v0.z() * entry_s;  // a climb or descent eased out
  const double touch_rad = std::atan2(-inward.y(), -inward.x());
  out.join_angle_rad = touch_rad + side * shape.join_turn_rad;
  KnotDerivatives from;
  from.velocity_mps = entry.velocity_mps;
  from.acceleration_mps2 = entry.acceleration_mps2;
  from.jerk_mps3 = entry.jerk_mps3;
  auto entering = hermiteSpline({entry.position_m, c.positionAt(out.join_angle_rad)}, {entry_s},
                                {from, c.derivativesAt(out.join_angle_rad)});
  if (!entering) return entering.error();
  out.segments = std::move(entering.value());
  const double arc_s = c.turnS() / static_cast<double>(c.arcs_per_turn);
  const auto arcs = static_cast<std::size_t>(std::max(1.0, std::ceil(std::max(0.0, circle_s) / arc_s)));
  std::vector<Segment> circling = loiterArcs(c, out.join_angle_rad, arcs);
  if (circling.empty()) return make_error(ErrorCode::kInternal, "loiter", "the circle's arcs could not be built");
  out.segments.insert(out.segments.end(), circling.begin(), circling.end());
  out.end_angle_rad = out.join_angle_rad + c.arcAngleRad() * static_cast<double>(arcs);
  return out;
}

}  // namespace skyroute
