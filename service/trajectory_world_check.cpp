#include "service/trajectory_world_check.hpp"

namespace skyroute {

MotionCheck collisionWorldMotionCheck(std::shared_ptr<const CollisionWorld> world,
                                      std::optional<double> world_time_at_start_s) {
  if (world_time_at_start_s) {
    const double start = *world_time_at_start_s;
    return [world, start](const Eigen::Vector3d& a, double t_a, const Eigen::Vector3d& b, double t_b) {
      return world->isSegmentValidDuring(a, start + t_a, b, start + t_b);
    };
  }
  return [world](const Eigen::Vector3d& a, double, const Eigen::Vector3d& b, double) {
    return world->isSegmentValid(a, b);
  };
}

}  // namespace skyroute
