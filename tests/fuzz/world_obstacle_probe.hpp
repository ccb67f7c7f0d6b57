// What the world model and the collision checks compute from an accepted obstacle update, over a
// minute ahead (more than the replanning horizon): run for the sanitizers, the values unused.
#pragma once

#include <cstdint>

#include <Eigen/Core>

#include "service/mission_types.hpp"
#include "service/world_model.hpp"

namespace skyroute::fuzz {

inline void probeWorldObstacle(const ObstacleUpdateData& update, std::int64_t now_utc_ns) {
  const Obstacle o = worldObstacle(update, WorldModelOptions{}.constant_velocity_horizon_s);
  const double now_s = static_cast<double>(now_utc_ns) * 1e-9;
  (void)o.centerAt(now_s);
  (void)o.trackDuring(now_s, now_s + 60.0);
  (void)o.boundingRadius();
  (void)o.contains(Eigen::Vector3d::Zero(), now_s, 1.0);
}

}  // namespace skyroute::fuzz
