#include "service/trajectory_audit.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <numbers>

#include "terrain/collision_world.hpp"
#include "terrain/heightfield.hpp"

namespace skyroute {
namespace {

std::string number(double value, int decimals = 1) {
  char text[48];
  std::snprintf(text, sizeof text, "%.*f", decimals, value);
  return text;
}

std::string where(const Eigen::Vector3d& p) {
  return "(" + number(p.x()) + ", " + number(p.y()) + ", " + number(p.z()) + ") m ENU";
}

// Point in polygon by the crossing number (even-odd rule), on the open ring.
bool insideRing(const std::vector<Eigen::Vector2d>& ring, const Eigen::Vector2d& p) {
  bool inside = false;
  for (std::size_t i = 0, j = ring.size() - 1; i < ring.size(); j = i++) {
    const Eigen::Vector2d& a = ring[i];
    const Eigen::Vector2d& b = ring[j];
    if ((a.y() > p.y()) != (b.y() > p.y())) {
      const double x = a.x() + (p.y() - a.y()) * (b.x() - a.x()) / (b.y() - a.y());
      if (p.x() < x) inside = !inside;
    }
  }
  return inside;
}

double segmentDistance2d(const Eigen::Vector2d& p, const Eigen::Vector2d& a, const Eigen::Vector2d& b) {
  const Eigen::Vector2d ab = b - a;
  const double length2 = ab.squaredNorm();
  const double f = length2 > 0.0 ? std::clamp((p - a).dot(ab) / length2, 0.0, 1.0) : 0.0;
  return (p - (a + f * ab)).norm();
}

// Euclidean distance from p to the zone's prism (0 inside it).
double prismDistance(const NoFlyZone& zone, const Eigen::Vector3d& p) {
  const Eigen::Vector2d en = p.head<2>();
  double horizontal = 0.0;
  if (!insideRing(zone.ring_m, en)) {
    horizontal = std::numeric_limits<double>::infinity();
    for (std::size_t i = 0, j = zone.ring_m.size() - 1; i < zone.ring_m.size(); j = i++) {
      horizontal = std::min(horizontal, segmentDistance2d(en, zone.ring_m[j], zone.ring_m[i]));
    }
  }
  const double vertical = std::max({zone.floor_m - p.z(), 0.0, p.z() - zone.ceiling_m});
  return std::hypot(horizontal, vertical);
}

bool zoneInForce(const NoFlyZone& zone, double world_s) {
  if (zone.valid_from_s && world_s < *zone.valid_from_s) return false;
  if (zone.valid_until_s && world_s >= *zone.valid_until_s) return false;
  return true;
}

// Distance from a point (relative to the ellipsoid's centre) to the axis-aligned ellipsoid with
// semi-axes `axes`; 0 inside. The closest point is axes_i^2 p_i / (axes_i^2 + s) for the root s > 0
// of sum (axes_i p_i / (axes_i^2 + s))^2 = 1, which decreases in s: bisection finds it.
double ellipsoidDistance(const Eigen::Vector3d& p, const Eigen::Vector3d& axes) {
  const Eigen::Vector3d q = p.cwiseAbs();
  auto level = [&](double s) {
    double sum = 0.0;
    for (int i = 0; i < 3; ++i) {
      const double term = axes(i) * q(i) / (axes(i) * axes(i) + s);
      sum += term * term;
    }
    return sum;
  };
  if (level(0.0) <= 1.0) return 0.0;
  double lo = 0.0;
  double hi = axes.maxCoeff() * q.norm();  // each term is at most axes_max q / s there: level <= 1
  for (int iteration = 0; iteration < 200 && hi - lo > 1e-12 * std::max(1.0, hi); ++iteration) {
    const double mid = 0.5 * (lo + hi);
    (level(mid) > 1.0 ? lo : hi) = mid;
  }
  const double s = 0.5 * (lo + hi);
  Eigen::Vector3d closest;
  for (int i = 0; i < 3; ++i) closest(i) = axes(i) * axes(i) * q(i) / (axes(i) * axes(i) + s);
  return (q - closest).norm();
}

// Distance from p to the obstacle's shape centred at c (0 inside).
double shapeDistance(const Obstacle& o, const Eigen::Vector3d& c, const Eigen::Vector3d& p) {
  const Eigen::Vector3d d = p - c;
  switch (o.shape) {
    case ObstacleShape::kSphere: return std::max(0.0, d.norm() - o.size_m.x());
    case ObstacleShape::kBox: return (d.cwiseAbs() - o.size_m).cwiseMax(0.0).norm();
    case ObstacleShape::kCylinder: {
      const double radial = std::max(0.0, d.head<2>().norm() - o.size_m.x());
      const double vertical = std::max(0.0, std::abs(d.z()) - o.size_m.z());
      return std::hypot(radial, vertical);
    }
    case ObstacleShape::kEllipsoid: return ellipsoidDistance(d, o.size_m);
  }
  return 0.0;
}

}  // namespace

std::string_view to_string(AuditCheck check) {
  switch (check) {
    case AuditCheck::kOutsideDem: return "outside_dem";
    case AuditCheck::kGroundClearance: return "ground_clearance";
    case AuditCheck::kCeiling: return "ceiling";
    case AuditCheck::kNoFlyZone: return "nofly_zone";
    case AuditCheck::kObstacle: return "obstacle";
    case AuditCheck::kSpeed: return "speed";
    case AuditCheck::kAcceleration: return "acceleration";
    case AuditCheck::kClimbRate: return "climb_rate";
    case AuditCheck::kDescentRate: return "descent_rate";
    case AuditCheck::kMinAirspeed: return "min_airspeed";
    case AuditCheck::kBankAngle: return "bank_angle";
    case AuditCheck::kNotFinite: return "not_finite";
  }
  return "unknown";
}

std::optional<Error> validateAuditOptions(const AuditOptions& o) {
  if (!(o.step_s > 0.0) || !(o.step_s <= 1.0)) {
    return make_error(ErrorCode::kInvalidArgument, "audit.step_s", "must be in (0, 1] s");
  }
  if (!(o.tolerance_m >= 0.0) || !(o.tolerance_m <= 5.0)) {
    return make_error(ErrorCode::kInvalidArgument, "audit.tolerance_m", "must be in [0, 5] m");
  }
  if (!(o.limit_tolerance >= 0.0) || !(o.limit_tolerance <= 0.5)) {
    return make_error(ErrorCode::kInvalidArgument, "audit.limit_tolerance", "must be in [0, 0.5]");
  }
  return std::nullopt;
}

AuditWorld auditWorldOf(const CollisionWorld& world, double moving_until_world_s) {
  AuditWorld out;
  out.terrain = world.terrainPtr();
  out.min_clearance_m = world.options().min_clearance_m;
  out.ceiling_m = world.options().ceiling_m;
  out.vehicle_radius_m = world.options().vehicle_radius_m;
  out.zones = world.noFlyZones();
  out.obstacles = world.obstacles();
  out.moving_until_world_s = moving_until_world_s;
  return out;
}

std::optional<AuditFinding> auditTrajectory(const Trajectory& trajectory, double start_world_s, const AuditWorld& world,
                                            const VehicleLimits& limits, const AuditOptions& options) {
  const double duration_s = trajectory.duration_s();
  if (trajectory.empty() || !std::isfinite(duration_s) || !std::isfinite(start_world_s)) {
    return AuditFinding{AuditCheck::kNotFinite, 0.0, "not_finite: the trajectory is empty or its times are not finite"};
  }
  const double step_s = options.step_s > 0.0 ? options.step_s : AuditOptions{}.step_s;
  const double slack = 1.0 + options.limit_tolerance;
  const double radius_m = world.vehicle_radius_m - options.tolerance_m;  // nearer than this is contact
  const double min_airspeed_mps = limits.minAirspeedMps() * (1.0 - options.limit_tolerance);
  const std::size_t steps = static_cast<std::size_t>(std::ceil(duration_s / step_s));
  for (std::size_t k = 0; k <= steps; ++k) {
    const double t = std::min(duration_s, static_cast<double>(k) * step_s);
    const double world_s = start_world_s + t;
    const Eigen::Vector3d p = trajectory.evaluate(t, Derivative::kPosition);
    const Eigen::Vector3d v = trajectory.evaluate(t, Derivative::kVelocity);
    const Eigen::Vector3d a = trajectory.evaluate(t, Derivative::kAcceleration);
    auto fail = [&](AuditCheck check, const std::string& what) {
      return AuditFinding{check, t, std::string(to_string(check)) + ": " + what + " at t = " + number(t, 2) + " s"};
    };
    if (!p.allFinite() || !v.allFinite() || !a.allFinite()) {
      return fail(AuditCheck::kNotFinite, "a sample is not finite");
    }
    if (world.terrain) {
      const double ground_m = world.terrain->heightAt(p.x(), p.y());
      if (!std::isfinite(ground_m)) {
        return fail(AuditCheck::kOutsideDem, where(p) + " has no DEM height (outside the DEM or over unknown cells)");
      }
      if (p.z() - ground_m < world.min_clearance_m - options.tolerance_m) {
        return fail(AuditCheck::kGroundClearance, number(p.z() - ground_m) + " m above the DEM at " + where(p) +
                                                      ", under the minimum clearance " + number(world.min_clearance_m) +
                                                      " m");
      }
    }
    if (p.z() > world.ceiling_m + options.tolerance_m) {
      return fail(AuditCheck::kCeiling,
                  "altitude " + number(p.z()) + " m is above the ceiling " + number(world.ceiling_m) + " m");
    }
    for (const NoFlyZone& zone : world.zones) {
      if (zone.ring_m.size() < 3 || !zoneInForce(zone, world_s)) continue;
      const double d = prismDistance(zone, p);
      if (d < radius_m) {
        return fail(AuditCheck::kNoFlyZone, "the vehicle at " + where(p) + " is " + number(d) +
                                                " m from no-fly zone '" + zone.name + "' (vehicle radius " +
                                                number(world.vehicle_radius_m) + " m)");
      }
    }
    for (const Obstacle& o : world.obstacles) {
      const bool moving = o.moving();
      if (moving && world_s > world.moving_until_world_s) continue;
      const double d = shapeDistance(o, o.centerAt(world_s), p);  // where its motion model predicts it
      if (d < radius_m) {
        return fail(AuditCheck::kObstacle, "the vehicle at " + where(p) + " is " + number(d) + " m from " +
                                               (moving ? "moving" : "fixed") + " obstacle " + std::to_string(o.id) +
                                               " (vehicle radius " + number(world.vehicle_radius_m) + " m)");
      }
    }
    const double speed = v.norm();
    if (speed > limits.max_speed_mps * slack) {
      return fail(AuditCheck::kSpeed,
                  number(speed, 2) + " m/s over the limit " + number(limits.max_speed_mps, 2) + " m/s");
    }
    if (a.norm() > limits.max_accel_mps2 * slack) {
      return fail(AuditCheck::kAcceleration,
                  number(a.norm(), 2) + " m/s^2 over the limit " + number(limits.max_accel_mps2, 2) + " m/s^2");
    }
    if (v.z() > limits.max_climb_mps * slack) {
      return fail(AuditCheck::kClimbRate,
                  number(v.z(), 2) + " m/s over the limit " + number(limits.max_climb_mps, 2) + " m/s");
    }
    if (-v.z() > limits.max_descent_mps * slack) {
      return fail(AuditCheck::kDescentRate,
                  number(-v.z(), 2) + " m/s over the limit " + number(limits.max_descent_mps, 2) + " m/s");
    }
    if (limits.fixedWing()) {
      if (speed < min_airspeed_mps) {
        return fail(AuditCheck::kMinAirspeed,
                    number(speed, 2) + " m/s under the minimum airspeed " + number(limits.minAirspeedMps(), 2) +
                        " m/s");
      }
      // The coordinated turn that flies the horizontal curvature: tan(bank) = a_lateral / g.
      const double horizontal = v.head<2>().norm();
      if (horizontal > 1e-9) {
        const double lateral = std::abs(v.x() * a.y() - v.y() * a.x()) / horizontal;
        const double bank_deg = std::atan(lateral / kStandardGravityMps2) * 180.0 / std::numbers::pi;
        if (bank_deg > limits.max_bank_deg * slack) {
          return fail(AuditCheck::kBankAngle,
                      number(bank_deg, 2) + " deg over the limit " + number(limits.max_bank_deg, 2) + " deg");
        }
      }
    }
  }
  return std::nullopt;
}

}  // namespace skyroute
