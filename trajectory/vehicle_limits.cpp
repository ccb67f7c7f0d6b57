#include "trajectory/vehicle_limits.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <string>

#include "planning/core/enum_names.hpp"

namespace skyroute {

namespace {

constexpr EnumName<VehicleModel> kModelNames[] = {{VehicleModel::kMultirotor, "multirotor"},
                                                  {VehicleModel::kFixedWing, "fixed_wing"}};

double radians(double deg) { return deg * std::numbers::pi / 180.0; }

// The fixed-wing fields' ranges (a multirotor ignores them).
Status validateFixedWing(const VehicleLimits& l) {
  auto bad = [](const char* field, const std::string& why) { return make_error(ErrorCode::kInvalidArgument, field, why); };
  if (!std::isfinite(l.stall_speed_mps) || l.stall_speed_mps <= 0.0)
    return bad("limits.stall_speed_mps", "must be positive and finite for a fixed wing, got " + std::to_string(l.stall_speed_mps));
  if (!std::isfinite(l.stall_margin) || l.stall_margin < 1.0 || l.stall_margin > 3.0)
    return bad("limits.stall_margin", "must be within [1, 3], got " + std::to_string(l.stall_margin));
  if (!std::isfinite(l.max_bank_deg) || l.max_bank_deg <= 0.0 || l.max_bank_deg >= 80.0)
    return bad("limits.max_bank_deg", "must be within (0, 80) degrees, got " + std::to_string(l.max_bank_deg));
  const std::pair<const char*, double> angles[] = {{"limits.max_climb_angle_deg", l.max_climb_angle_deg},
                                                   {"limits.max_descent_angle_deg", l.max_descent_angle_deg}};
  for (const auto& [name, value] : angles)
    if (!std::isfinite(value) || value <= 0.0 || value > 60.0)
      return bad(name, "must be within (0, 60] degrees, got " + std::to_string(value));
  if (l.v_ref_mps < l.minAirspeedMps())
    return bad("limits.v_ref_mps", "V_ref " + std::to_string(l.v_ref_mps) +
                                       " m/s is below the fixed wing's minimum airspeed " +
                                       std::to_string(l.minAirspeedMps()) + " m/s (stall_speed_mps x stall_margin)");
  return Status::success();
}

}  // namespace

std::string_view to_string(VehicleModel model) { return enumName(kModelNames, model); }

std::optional<VehicleModel> parseVehicleModel(std::string_view text) { return enumNamed(kModelNames, text); }

double VehicleLimits::minAirspeedMps() const { return fixedWing() ? stall_speed_mps * stall_margin : 0.0; }

double VehicleLimits::turnRadiusAtM(double speed_mps) const {
  if (!fixedWing()) return 0.0;
  return speed_mps * speed_mps / (kStandardGravityMps2 * std::tan(radians(max_bank_deg)));
}

double VehicleLimits::maxLoadFactor() const { return 1.0 / std::cos(radians(max_bank_deg)); }

double VehicleLimits::effectiveMinTurnRadiusM() const {
  return fixedWing() ? std::max(min_turn_radius_m, turnRadiusAtM(v_ref_mps)) : min_turn_radius_m;
}

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
  if (model != VehicleModel::kMultirotor && model != VehicleModel::kFixedWing)
    return make_error(ErrorCode::kInvalidArgument, "limits.model", "has an unknown value");
  if (fixedWing()) return validateFixedWing(*this);
  return Status::success();
}

}  // namespace skyroute
