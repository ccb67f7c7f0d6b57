// Field-by-field equality of obstacle updates, for the harnesses' round-trip checks.
#pragma once

#include "service/mission_types.hpp"

namespace skyroute::fuzz {

inline bool sameUpdate(const ObstacleUpdateData& a, const ObstacleUpdateData& b) {
  if (a.remove != b.remove || a.obstacle.id != b.obstacle.id || a.valid_from_utc_ns != b.valid_from_utc_ns ||
      a.valid_until_utc_ns != b.valid_until_utc_ns)
    return false;
  if (a.remove) return true;  // the geometry of a removal means nothing
  const Obstacle& o = a.obstacle;
  const Obstacle& p = b.obstacle;
  if (o.shape != p.shape || o.size_m != p.size_m || o.center_m != p.center_m || o.motion.has_value() != p.motion.has_value() ||
      a.constant_velocity_enu_mps != b.constant_velocity_enu_mps)
    return false;
  if (!o.motion) return true;
  return o.motion->from_m == p.motion->from_m && o.motion->to_m == p.motion->to_m &&
         o.motion->speed_mps == p.motion->speed_mps && o.motion->start_time_s == p.motion->start_time_s;
}

}  // namespace skyroute::fuzz
