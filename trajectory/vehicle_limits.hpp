// The vehicle's dynamic limits, with units. Defaults: the seed's V_ref = 50 m/s (seed 003,
// section 3-2) and the rest chosen for a fast fixed-wing-class UAV.
#pragma once

#include "planning/core/result.hpp"

namespace skyroute {

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

  // Error (kInvalidArgument) naming the field, e.g. "limits.v_ref_mps", when a value is out of range.
  Status validate() const;
};

}  // namespace skyroute
