// Feasibility of a trajectory: the vehicle's limits checked on the densely sampled trajectory, and
// (optionally) every piece of the sampled curve re-checked against the world through a motion
// check, so the flown curve, not only the planner's straight path, is known to be clear.
#pragma once

#include <cstddef>
#include <functional>
#include <limits>
#include <string_view>
#include <vector>

#include <Eigen/Core>
#include <Eigen/Geometry>

#include "trajectory/trajectory.hpp"
#include "trajectory/vehicle_limits.hpp"

namespace skyroute {

// Is the straight motion a -> b, flown from trajectory time t_a_s to t_b_s, clear of terrain and
// obstacles? (service/trajectory_world_check.hpp makes one from a CollisionWorld.)
using MotionCheck =
    std::function<bool(const Eigen::Vector3d& a_m, double t_a_s, const Eigen::Vector3d& b_m, double t_b_s)>;

// The fixed-wing kinds (below_min_airspeed, bank_angle, load_factor, climb_angle,
// descent_angle) are checked for a fixed wing only (VehicleLimits::model).
enum class ViolationKind {
  kSpeed,
  kAcceleration,
  kClimbRate,
  kDescentRate,
  kTurnRadius,
  kCollision,
  kBelowMinAirspeed,
  kBankAngle,
  kLoadFactor,
  kClimbAngle,
  kDescentAngle,
};
inline constexpr std::size_t kViolationKinds = 11;
std::string_view to_string(ViolationKind kind);
// Whether the value is bad for being under its limit (turn radius, airspeed), not over it.
bool underLimitIsViolation(ViolationKind kind);

// What a fixed wing needs at one instant, from its velocity and acceleration (ENU, z up):
// the bank angle of the coordinated turn that flies the horizontal curvature, atan(a_lat / g)
// with a_lat the horizontal acceleration across the horizontal velocity; the load factor, the
// lift needed over the weight, |a_perp + g z_perp| / g across the velocity; and the flight path
// angle above the horizontal (negative descending).
struct FixedWingState {
  double bank_deg = 0.0;
  double load_factor = 1.0;
  double path_angle_deg = 0.0;
};
FixedWingState fixedWingState(const Eigen::Vector3d& velocity_mps, const Eigen::Vector3d& acceleration_mps2);

// The worst violation of one kind in one segment.
struct Violation {
  ViolationKind kind = ViolationKind::kSpeed;
  std::size_t segment = 0;
  double time_s = 0.0;  // where it is worst (collision: start of the first blocked piece)
  double value = 0.0;   // m/s, m/s^2, m, degrees or the load factor (collision: 0)
  double limit = 0.0;
};

struct FeasibilityOptions {
  // Sampling step of the checks (per segment, never coarser). The re-check sweeps the chords
  // between samples; a chord strays from the curve by at most |a| dt^2 / 8 (1.3 cm at 10 m/s^2).
  double dt_s = 0.1;
  double relative_tolerance = 1e-6;   // a value above limit * (1 + tolerance) is a violation
  // Asked before each segment; when it says stop, the check ends with `stopped` set (a long
  // trajectory's check can take seconds, and a service must be able to cancel it).
  std::function<bool()> stop_requested;
};

struct FeasibilityReport {
  std::vector<Violation> violations;  // by segment, then kind
  double max_speed_mps = 0.0;
  double max_accel_mps2 = 0.0;
  double max_climb_mps = 0.0;
  double max_descent_mps = 0.0;
  double min_turn_radius_m = std::numeric_limits<double>::infinity();  // where speed >= the check speed
  // Fixed wing only (left at these values for a multirotor).
  double min_speed_mps = std::numeric_limits<double>::infinity();
  double max_bank_deg = 0.0;
  double max_load_factor = 0.0;
  double max_climb_angle_deg = 0.0;
  double max_descent_angle_deg = 0.0;
  std::size_t samples = 0;
  std::size_t motions_checked = 0;
  bool stopped = false;               // ended early by stop_requested: nothing is proven

  bool ok() const { return violations.empty() && !stopped; }
  bool has(ViolationKind kind) const;
};

// collision may be null (limits only).
FeasibilityReport checkFeasibility(const Trajectory& trajectory, const VehicleLimits& limits,
                                   const FeasibilityOptions& options = {}, const MotionCheck* collision = nullptr);

}  // namespace skyroute
