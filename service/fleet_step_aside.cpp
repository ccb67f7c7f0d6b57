#include "service/fleet_step_aside.hpp"

#include <algorithm>
#include <cmath>

namespace skyroute {

double horizontalReachM(const Obstacle& o) {
  return o.shape == ObstacleShape::kBox ? o.size_m.head<2>().norm()
         : o.shape == ObstacleShape::kEllipsoid ? o.size_m.head<2>().maxCoeff()
                                                : o.size_m.x();
}

double verticalReachM(const Obstacle& o) { return o.shape == ObstacleShape::kSphere ? o.size_m.x() : o.size_m.z(); }

std::vector<StepAside> stepAsidesFrom(const std::vector<Obstacle>& obstacles, const Eigen::Vector3d& p_m,
                                      double band_m, double room_m, double at_s) {
  std::vector<StepAside> out;
  const double low_m = std::min(p_m.z(), band_m), high_m = std::max(p_m.z(), band_m);
  for (const Obstacle& o : obstacles) {
    const Eigen::Vector3d c = o.centerAt(at_s);
    const double up_m = verticalReachM(o) + room_m;
    double obstacle_low_m = c.z(), obstacle_high_m = c.z();
    if (o.moving()) {
      obstacle_low_m = std::min(o.motion->from_m.z(), o.motion->to_m.z());
      obstacle_high_m = std::max(o.motion->from_m.z(), o.motion->to_m.z());
    }
    if (obstacle_high_m + up_m < low_m || obstacle_low_m - up_m > high_m) continue;  // above or below the climb
    const double reach_m = horizontalReachM(o) + room_m;
    const Eigen::Vector2d to_p = p_m.head<2>() - c.head<2>();
    Eigen::Vector2d track = o.moving() ? Eigen::Vector2d((o.motion->to_m - o.motion->from_m).head<2>())
                                       : Eigen::Vector2d::Zero();
    if (track.norm() < 1e-6) {
      // Fixed (or moving up and down): straight away from its axis.
      if (to_p.norm() >= reach_m) continue;
      const Eigen::Vector2d away = to_p.norm() > 1e-6 ? Eigen::Vector2d(to_p.normalized()) : Eigen::Vector2d::UnitX();
      out.push_back({c.head<2>() + away * reach_m, 0.0});
      continue;
    }
    track.normalize();
    const Eigen::Vector2d across(-track.y(), track.x());
    const double off_m = to_p.dot(across);
    if (std::abs(off_m) >= reach_m) continue;  // its track passes by
    // How far it still has to come to be over p (negative once past).
    const Eigen::Vector2d heading = (o.centerAt(at_s + 1.0) - c).head<2>();
    const double ahead_m = heading.dot(to_p) >= 0.0 ? std::abs(to_p.dot(track)) : -std::abs(to_p.dot(track));
    if (ahead_m + reach_m <= 0.0) continue;  // gone by already
    const double gone_by_s = at_s + (ahead_m + reach_m) / o.motion->speed_mps;
    const double side = off_m >= 0.0 ? 1.0 : -1.0;
    for (double s : {side, -side}) {
      const Eigen::Vector2d xy = p_m.head<2>() + across * (s * reach_m - off_m);
      out.push_back({xy, 0.0});
      out.push_back({xy, gone_by_s});
    }
  }
  return out;
}

}  // namespace skyroute
