// Whether two trajectories are the same bit for bit: the identity, the order, the legs and every
// number of every sample (no tolerance: a republished trajectory must be the published one).
#pragma once

#include <algorithm>

#include "service/mission_types.hpp"

namespace skyroute::testing {

inline bool sameSample(const TrajectorySampleData& x, const TrajectorySampleData& y) {
  return x.t_rel_s == y.t_rel_s && x.utc_ns == y.utc_ns && x.position_enu_m == y.position_enu_m &&
         x.velocity_enu_mps == y.velocity_enu_mps && x.acceleration_enu_mps2 == y.acceleration_enu_mps2 &&
         x.heading_deg == y.heading_deg && x.geo.lat_deg == y.geo.lat_deg && x.geo.lon_deg == y.geo.lon_deg &&
         x.geo.alt_amsl_m == y.geo.alt_amsl_m;
}

inline bool sameSamples(const TrajectoryData& a, const TrajectoryData& b) {
  return a.samples.size() == b.samples.size() &&
         std::equal(a.samples.begin(), a.samples.end(), b.samples.begin(), sameSample);
}

inline bool sameTrajectory(const TrajectoryData& a, const TrajectoryData& b) {
  const auto same_leg = [](const LegBoundaryData& x, const LegBoundaryData& y) {
    return x.from_point == y.from_point && x.to_point == y.to_point && x.start_s == y.start_s && x.end_s == y.end_s;
  };
  return a.vehicle_id == b.vehicle_id && a.plan_id == b.plan_id && a.revision == b.revision &&
         a.request_id == b.request_id && a.created_utc_ns == b.created_utc_ns && a.visiting_order == b.visiting_order &&
         a.legs.size() == b.legs.size() && std::equal(a.legs.begin(), a.legs.end(), b.legs.begin(), same_leg) &&
         sameSamples(a, b);
}

}  // namespace skyroute::testing
