// Adapter from the terrain CollisionWorld to the planners' MotionValidator: states and motions are
// checked by the world (terrain clearance, ceiling, obstacles; a moving obstacle blocks its whole
// sweep since planning here is timeless), and sampling happens in the flyable box, optionally cut
// down to a region (for example a corridor round one leg, so a 100 km DEM tile does not dilute
// the samples of a 10 km leg).
#pragma once

#include <memory>
#include <optional>

#include "planning/core/motion_validator.hpp"
#include "terrain/collision_world.hpp"

namespace skyroute {

class WorldMotionValidator : public MotionValidator {
 public:
  // region: when given, samples and valid states are kept inside flyableBounds() ∩ region.
  explicit WorldMotionValidator(std::shared_ptr<const CollisionWorld> world,
                                std::optional<Eigen::AlignedBox3d> region = std::nullopt,
                                std::optional<ObstacleSnapshot> snapshot = std::nullopt);

  bool isStateValid(const Eigen::Vector3d& p_m) const override;
  bool isMotionValid(const Eigen::Vector3d& a_m, const Eigen::Vector3d& b_m) const override;
  Eigen::AlignedBox3d samplingBounds() const override { return bounds_; }

  const CollisionWorld& world() const { return *world_; }

  // The box round a and b, grown by margin_m horizontally, spanning the flyable heights.
  static Eigen::AlignedBox3d corridor(const Eigen::Vector3d& a_m, const Eigen::Vector3d& b_m, double margin_m);

 private:
  std::shared_ptr<const CollisionWorld> world_;
  Eigen::AlignedBox3d bounds_;
  std::optional<ObstacleSnapshot> snapshot_;
};

}  // namespace skyroute
