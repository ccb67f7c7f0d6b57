// Adapter from the terrain CollisionWorld to the planners' MotionValidator: states and motions are
// checked by the world (terrain clearance, ceiling, obstacles; a moving obstacle blocks its whole
// sweep since planning here is timeless), and sampling happens in the flyable box, optionally cut
// down to a region (for example a corridor round one leg, so a 100 km DEM tile does not dilute
// the samples of a 10 km leg).
#pragma once

#include <limits>
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

  // A fixed wing climbs and descends at most at these angles above and below the horizontal
  // (degrees, in (0, 90)); a steeper motion is invalid. Unset (the default): any slope.
  void limitPathAngles(double max_climb_deg, double max_descent_deg);

  const CollisionWorld& world() const { return *world_; }

  // The box round a and b, grown by margin_m horizontally, spanning the flyable heights.
  static Eigen::AlignedBox3d corridor(const Eigen::Vector3d& a_m, const Eigen::Vector3d& b_m, double margin_m);

 private:
  std::shared_ptr<const CollisionWorld> world_;
  Eigen::AlignedBox3d bounds_;
  std::optional<ObstacleSnapshot> snapshot_;
  // tan of the path angle limits; infinite = none.
  double max_climb_slope_ = std::numeric_limits<double>::infinity();
  double max_descent_slope_ = std::numeric_limits<double>::infinity();
};

}  // namespace skyroute
