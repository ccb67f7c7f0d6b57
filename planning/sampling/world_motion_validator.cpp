#include "planning/sampling/world_motion_validator.hpp"

#include <limits>

namespace skyroute {

WorldMotionValidator::WorldMotionValidator(std::shared_ptr<const CollisionWorld> world,
                                           std::optional<Eigen::AlignedBox3d> region,
                                           std::optional<ObstacleSnapshot> snapshot)
    : world_(std::move(world)), bounds_(world_->flyableBounds()), snapshot_(snapshot) {
  if (region) bounds_ = bounds_.intersection(*region);
}

bool WorldMotionValidator::isStateValid(const Eigen::Vector3d& p_m) const {
  if (snapshot_) return bounds_.contains(p_m) && world_->isPointValid(p_m, *snapshot_);
  return bounds_.contains(p_m) && world_->isPointValid(p_m);
}

bool WorldMotionValidator::isMotionValid(const Eigen::Vector3d& a_m, const Eigen::Vector3d& b_m) const {
  // The box is convex: a motion between two points inside it stays inside.
  if (!bounds_.contains(a_m) || !bounds_.contains(b_m)) return false;
  if (snapshot_) return world_->isSegmentValid(a_m, b_m, *snapshot_);
  return world_->isSegmentValid(a_m, b_m);
}

Eigen::AlignedBox3d WorldMotionValidator::corridor(const Eigen::Vector3d& a_m, const Eigen::Vector3d& b_m,
                                                   double margin_m) {
  const double inf = std::numeric_limits<double>::infinity();
  Eigen::Vector3d lo = a_m.cwiseMin(b_m), hi = a_m.cwiseMax(b_m);
  lo.head<2>().array() -= margin_m;
  hi.head<2>().array() += margin_m;
  lo.z() = -inf;
  hi.z() = inf;
  return Eigen::AlignedBox3d(lo, hi);
}

}  // namespace skyroute
