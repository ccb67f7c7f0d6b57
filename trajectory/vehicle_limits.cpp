#include "trajectory/vehicle_limits.hpp"

#include <cmath>
#include <string>

namespace skyroute {

Status VehicleLimits::validate() const {
  const std::pair<const char*, double> positive[] = {
      {"limits.v_ref_mps", v_ref_mps},         {"limits.max_speed_mps", max_speed_mps},
      {"limits.max_accel_mps2", max_accel_mps2}, {"limits.max_climb_mps", max_climb_mps},
      {"limits.max_descent_mps", max_descent_mps}};
  for (const auto& [name, value] : positive)
    if (!std::isfinite(value) || value <= 0.0)
      return make_error(ErrorCode::kInvalidArgument, name, "must be positive and finite, got " + std::to_string(value));
  if (!std::isfinite(min_turn_radius_m) || min_turn_radius_m < 0.0)
    return make_error(ErrorCode::kInvalidArgument, "limits.min_turn_radius_m",
                      "must be >= 0 and finite, got " + std::to_string(min_turn_radius_m));
  if (!std::isfinite(turn_check_min_speed_mps) || turn_check_min_speed_mps < 0.0)
    return make_error(ErrorCode::kInvalidArgument, "limits.turn_check_min_speed_mps",
                      "must be >= 0 and finite, got " + std::to_string(turn_check_min_speed_mps));
  if (v_ref_mps > max_speed_mps)
    return make_error(ErrorCode::kInvalidArgument, "limits.v_ref_mps",
                      "V_ref " + std::to_string(v_ref_mps) + " m/s exceeds limits.max_speed_mps " +
                          std::to_string(max_speed_mps) + " m/s");
  return Status::success();
}

}  // namespace skyroute
