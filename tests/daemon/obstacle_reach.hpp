// Whether an obstacle update will meet a vehicle's published trajectory, decided at the ground
// station from the samples alone and with its own obstacle motion (not the daemon's code): the
// tests and the load benchmark use it to know which updates must be answered for which vehicle.
// Shapes: cylinders exactly, every other shape by a sphere round it (conservative).
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <optional>

#include "service/mission_types.hpp"

namespace skyroute::testing {

// The obstacle's centre at UTC time t_ns as the update predicts it.
inline Eigen::Vector3d predictedCentre(const ObstacleUpdateData& u, std::int64_t t_ns) {
  const double dt_s = std::max(0.0, static_cast<double>(t_ns - u.valid_from_utc_ns) * 1e-9);
  const Obstacle& o = u.obstacle;
  if (u.constant_velocity_enu_mps) return o.center_m + *u.constant_velocity_enu_mps * dt_s;
  if (!o.motion || !(o.motion->speed_mps > 0.0)) return o.center_m;
  const Eigen::Vector3d track = o.motion->to_m - o.motion->from_m;
  const double length_m = track.norm();
  if (length_m <= 0.0) return o.motion->from_m;
  // Back and forth: the distance covered folded onto [0, 2L), then mirrored on the way back.
  const double folded_m = std::fmod(o.motion->speed_mps * dt_s, 2.0 * length_m);
  const double along_m = folded_m <= length_m ? folded_m : 2.0 * length_m - folded_m;
  return o.motion->from_m + track * (along_m / length_m);
}

inline bool insideGrown(const ObstacleUpdateData& u, const Eigen::Vector3d& p, std::int64_t t_ns, double margin_m) {
  const Eigen::Vector3d d = p - predictedCentre(u, t_ns);
  const Eigen::Vector3d& size = u.obstacle.size_m;
  if (u.obstacle.shape == ObstacleShape::kCylinder) {
    return d.head<2>().norm() <= size.x() + margin_m && std::abs(d.z()) <= size.z() + margin_m;
  }
  return d.norm() <= size.maxCoeff() * std::sqrt(3.0) + margin_m;
}

// True when a sample of `t` between now_ns and now_ns + horizon_s lies within margin_m of the
// obstacle where the update says it will be at that sample's time.
inline bool obstacleMeets(const TrajectoryData& t, const ObstacleUpdateData& u, std::int64_t now_ns, double horizon_s,
                          double margin_m) {
  if (u.remove || t.samples.empty()) return false;
  const std::int64_t until_ns = now_ns + static_cast<std::int64_t>(horizon_s * 1e9);
  for (const TrajectorySampleData& s : t.samples) {
    if (s.utc_ns < now_ns || s.utc_ns > until_ns) continue;
    if (u.valid_until_utc_ns != 0 && s.utc_ns > u.valid_until_utc_ns) break;
    if (insideGrown(u, s.position_enu_m, s.utc_ns, margin_m)) return true;
  }
  return false;
}

// A 40 m box on `current` where the vehicle will be at least 20 s and distance_m (along the
// straight line) after its first sample from now_ns: the update a test sends so that the
// vehicle's owner replans round it. Nothing when the trajectory does not reach that far.
struct BlockAhead {
  ObstacleUpdateData update;
  std::int64_t meets_utc_ns = 0;  // when the vehicle would be at the box's centre
};
inline std::optional<BlockAhead> blockAhead(const TrajectoryData& current, std::uint64_t id, double distance_m,
                                            std::int64_t now_ns) {
  const TrajectorySampleData* here = nullptr;
  for (const TrajectorySampleData& s : current.samples) {
    if (!here && s.utc_ns >= now_ns) here = &s;
    if (here && s.utc_ns >= now_ns + 20'000'000'000LL && (s.position_enu_m - here->position_enu_m).norm() >= distance_m) {
      BlockAhead out;
      out.update.obstacle.id = id;
      out.update.obstacle.size_m = Eigen::Vector3d::Constant(40.0);
      out.update.obstacle.center_m = s.position_enu_m;
      out.update.valid_from_utc_ns = now_ns;
      out.meets_utc_ns = s.utc_ns;
      return out;
    }
  }
  return std::nullopt;
}

}  // namespace skyroute::testing
