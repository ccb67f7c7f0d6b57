// Field-by-field equality of missions, for the harnesses' round-trip checks (a mission read back
// from its own JSON or wire form must be the mission that was written).
#pragma once

#include "service/mission_types.hpp"

namespace skyroute::fuzz {

inline bool samePoint(const MissionPointData& a, const MissionPointData& b) {
  if (a.frame != b.frame) return false;
  if (a.frame == MissionPointData::Frame::kWgs84)
    return a.geo.lat_deg == b.geo.lat_deg && a.geo.lon_deg == b.geo.lon_deg && a.geo.alt_amsl_m == b.geo.alt_amsl_m;
  return a.enu_m == b.enu_m;
}

inline bool sameMission(const MissionRequestData& a, const MissionRequestData& b) {
  if (a.request_id != b.request_id || a.vehicle_id != b.vehicle_id || a.planner != b.planner ||
      a.fixed_order != b.fixed_order || a.points.size() != b.points.size())
    return false;
  if (!samePoint(a.begin, b.begin) || !samePoint(a.end, b.end)) return false;
  for (std::size_t i = 0; i < a.points.size(); ++i)
    if (!samePoint(a.points[i], b.points[i])) return false;
  const VehicleLimitsData& l = a.limits;
  const VehicleLimitsData& m = b.limits;
  return l.v_ref_mps == m.v_ref_mps && l.max_speed_mps == m.max_speed_mps && l.max_accel_mps2 == m.max_accel_mps2 &&
         l.max_climb_rate_mps == m.max_climb_rate_mps && l.max_descent_rate_mps == m.max_descent_rate_mps &&
         l.min_turn_radius_m == m.min_turn_radius_m && l.min_clearance_agl_m == m.min_clearance_agl_m &&
         l.ceiling_amsl_m == m.ceiling_amsl_m && l.model == m.model && l.stall_speed_mps == m.stall_speed_mps &&
         l.stall_margin == m.stall_margin && l.max_bank_deg == m.max_bank_deg &&
         l.max_climb_angle_deg == m.max_climb_angle_deg && l.max_descent_angle_deg == m.max_descent_angle_deg;
}

}  // namespace skyroute::fuzz
