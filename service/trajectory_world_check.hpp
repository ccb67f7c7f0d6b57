// The trajectory's motion check on the terrain world: each piece of the sampled curve is swept
// against the terrain and the obstacles. Without a world time, moving obstacles block their whole
// sweep (CollisionWorld::isSegmentValid); with one, trajectory time t is world time start + t and
// each moving obstacle is where it is then (isSegmentValidDuring).
#pragma once

#include <memory>
#include <optional>

#include "terrain/collision_world.hpp"
#include "trajectory/feasibility.hpp"

namespace skyroute {

MotionCheck collisionWorldMotionCheck(std::shared_ptr<const CollisionWorld> world,
                                      std::optional<double> world_time_at_start_s = std::nullopt);

}  // namespace skyroute
