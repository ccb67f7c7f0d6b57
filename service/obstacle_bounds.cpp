#include "service/obstacle_bounds.hpp"

#include "service/number_text.hpp"

namespace skyroute {
namespace {

PlanError outOfRange(const std::string& field, const std::string& what) {
  return PlanError{PlanErrorCode::kLimitsOutOfRange, field, field + " " + what};
}

std::optional<PlanError> checkPosition(const Eigen::Vector3d& p, const std::string& field, const Heightfield& terrain,
                                       double reach_m) {
  const Eigen::AlignedBox2d& box = terrain.boundsEn();
  const double lo[3] = {box.min().x() - reach_m, box.min().y() - reach_m, terrain.minHeightM() - reach_m};
  const double hi[3] = {box.max().x() + reach_m, box.max().y() + reach_m, terrain.maxHeightM() + reach_m};
  static const char* const kAxes[3] = {".x", ".y", ".z"};
  for (int i = 0; i < 3; ++i) {
    if (!(p[i] >= lo[i] && p[i] <= hi[i])) {
      return outOfRange(field + kAxes[i], "is " + numberText(p[i]) + " m, outside [" + numberText(lo[i]) + ", " +
                                              numberText(hi[i]) + "] m (the terrain's extent, grown by " +
                                              numberText(reach_m) + " m)");
    }
  }
  return std::nullopt;
}

}  // namespace

std::optional<PlanError> checkObstacleBounds(const ObstacleUpdateData& update, const Heightfield& terrain,
                                             const ObstacleBounds& bounds) {
  if (update.remove) return std::nullopt;
  const Obstacle& o = update.obstacle;
  const double reach_m = bounds.extent_factor * terrain.boundsEn().sizes().maxCoeff();
  static const char* const kSizes[3] = {"size_m.x", "size_m.y", "size_m.z"};
  const bool used[3] = {true, o.shape == ObstacleShape::kEllipsoid || o.shape == ObstacleShape::kBox,
                        o.shape != ObstacleShape::kSphere};
  for (int i = 0; i < 3; ++i) {
    if (used[i] && o.size_m[i] > reach_m) {
      return outOfRange(kSizes[i], "is " + numberText(o.size_m[i]) + " m, more than " + numberText(reach_m) +
                                       " m (the terrain's longer side times " + numberText(bounds.extent_factor) + ")");
    }
  }
  if (auto e = checkPosition(o.center_m, "position_enu_m", terrain, reach_m)) return e;
  if (o.motion) {
    if (auto e = checkPosition(o.motion->from_m, "from_enu_m", terrain, reach_m)) return e;
    if (auto e = checkPosition(o.motion->to_m, "to_enu_m", terrain, reach_m)) return e;
    if (o.motion->speed_mps > bounds.max_speed_mps) {
      return outOfRange("speed_mps", "is " + numberText(o.motion->speed_mps) + " m/s, more than " +
                                         numberText(bounds.max_speed_mps) + " m/s");
    }
  }
  if (update.constant_velocity_enu_mps && update.constant_velocity_enu_mps->norm() > bounds.max_speed_mps) {
    return outOfRange("velocity_enu_mps", "is " + numberText(update.constant_velocity_enu_mps->norm()) +
                                              " m/s, more than " + numberText(bounds.max_speed_mps) + " m/s");
  }
  return std::nullopt;
}

}  // namespace skyroute
