#include "planning/sampling/world_motion_validator.hpp"

#include <cmath>
#include <limits>
#include <numbers>

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
  const double rise = b_m.z() - a_m.z();
  const double run = (b_m - a_m).head<2>().norm();
  if (rise > max_climb_slope_ * run || -rise > max_descent_slope_ * run) return false;
  if (snapshot_) return world_->isSegmentValid(a_m, b_m, *snapshot_);
  return world_->isSegmentValid(a_m, b_m);
}

void WorldMotionValidator::limitPathAngles(double max_climb_deg, double max_descent_deg) {
  constexpr double kRad = std::numbers::pi / 180.0;
  max_climb_slope_ = std::tan(max_climb_deg * kRad);
  max_descent_slope_ = std::tan(max_descent_deg * kRad);
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
