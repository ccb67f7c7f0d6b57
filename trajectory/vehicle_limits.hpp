// The vehicle's dynamic limits, with units. Defaults: the seed's V_ref = 50 m/s (seed 003,
// section 3-2) and the rest chosen for a fast fixed-wing-class UAV.
// Two vehicle models: a multirotor (may hover and turn on the spot; only the limits below the
// model's fields apply) and a fixed wing (seed 003 section 1: stall speed, turn radius and load
// factor). A fixed wing never flies slower than its minimum airspeed (stall speed x margin),
// banks at most max_bank_deg, so it turns no tighter than V^2 / (g tan(bank)) at speed V and
// pulls at most the load factor 1 / cos(bank), and climbs and descends at most at its path angles.
#pragma once

#include <optional>
#include <string_view>

#include "planning/core/result.hpp"

namespace skyroute {

enum class VehicleModel { kMultirotor, kFixedWing };
std::string_view to_string(VehicleModel model);  // "multirotor", "fixed_wing"
std::optional<VehicleModel> parseVehicleModel(std::string_view text);

inline constexpr double kStandardGravityMps2 = 9.80665;

struct VehicleLimits {
  double v_ref_mps = 50.0;          // reference (cruise) speed of eq. 3, > 0, <= max_speed_mps
  double max_speed_mps = 60.0;      // largest 3D speed, > 0
  double max_accel_mps2 = 10.0;     // largest 3D acceleration magnitude, > 0
  double max_climb_mps = 15.0;      // largest upward speed, > 0
  double max_descent_mps = 15.0;    // largest downward speed (positive number), > 0
  double min_turn_radius_m = 0.0;   // smallest radius of curvature of the flown curve; 0 = no limit
  // The turn radius is checked only where the vehicle flies at least this fast (a hovering
  // vehicle's curvature is meaningless).
  double turn_check_min_speed_mps = 1.0;

  VehicleModel model = VehicleModel::kMultirotor;
  // Fixed wing only (a multirotor ignores them).
  double stall_speed_mps = 0.0;        // > 0 for a fixed wing
  double stall_margin = 1.3;           // minimum airspeed = stall speed x margin, in [1, 3]
  double max_bank_deg = 30.0;          // in (0, 80)
  double max_climb_angle_deg = 15.0;   // flight path angle above the horizontal, in (0, 60]
  double max_descent_angle_deg = 15.0; // below the horizontal (positive number), in (0, 60]

  bool fixedWing() const { return model == VehicleModel::kFixedWing; }
  // Fixed wing: stall speed x margin; a multirotor: 0 (it may hover).
  double minAirspeedMps() const;
  // Fixed wing: the tightest level turn at speed_mps, V^2 / (g tan(max bank)); 0 for a multirotor.
  double turnRadiusAtM(double speed_mps) const;
  // Fixed wing: 1 / cos(max bank), the load factor of a level turn at the largest bank.
  double maxLoadFactor() const;
  // The radius the geometry must hold: min_turn_radius_m, and for a fixed wing at least the
  // tightest turn at cruise speed.
  double effectiveMinTurnRadiusM() const;

  // Error (kInvalidArgument) naming the field, e.g. "limits.v_ref_mps", when a value is out of range.
  Status validate() const;
};

}  // namespace skyroute
