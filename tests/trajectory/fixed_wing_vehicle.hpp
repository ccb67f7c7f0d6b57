// The fixed wing of the trajectory-stage tests: 25 m/s cruise, stall 15 m/s x 1.3, bank 35
// degrees, path angles 15 degrees (the same vehicle as fixedWingTestLimits in
// tests/fixed_wing_sampler.hpp, in the trajectory stage's own limits).
#pragma once

#include "trajectory/vehicle_limits.hpp"

namespace skyroute::testing {

inline VehicleLimits fixedWingVehicle() {
  VehicleLimits l;
  l.model = VehicleModel::kFixedWing;
  l.v_ref_mps = 25.0;
  l.max_speed_mps = 35.0;
  l.max_accel_mps2 = 10.0;
  l.max_climb_mps = 8.0;
  l.max_descent_mps = 8.0;
  l.stall_speed_mps = 15.0;
  l.stall_margin = 1.3;
  l.max_bank_deg = 35.0;
  l.max_climb_angle_deg = 15.0;
  l.max_descent_angle_deg = 15.0;
  return l;
}

}  // namespace skyroute::testing
