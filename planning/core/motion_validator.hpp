// What a 3D planner may ask of the world (as OMPL's StateValidityChecker + MotionValidator):
// is a point valid, is a straight motion valid, and where may it sample. Planners see only this,
// so they are tested on synthetic worlds and run on the terrain CollisionWorld alike.
// Implementations must be safe for concurrent calls from several planner threads.
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>

namespace skyroute {

class MotionValidator {
 public:
  virtual ~MotionValidator() = default;
  // Point in ENU metres: clear of terrain (with the minimum clearance), obstacles, under the ceiling.
  virtual bool isStateValid(const Eigen::Vector3d& p_m) const = 0;
  // The vehicle's sphere swept along the straight segment a -> b stays valid (no tunnelling).
  virtual bool isMotionValid(const Eigen::Vector3d& a_m, const Eigen::Vector3d& b_m) const = 0;
  // Box that contains every valid state; planners sample inside it.
  virtual Eigen::AlignedBox3d samplingBounds() const = 0;
};

}  // namespace skyroute
