#include "service/moving_obstacle_scenario.hpp"

#include <algorithm>

namespace skyroute {

MovingObstacleScenario seed003Table1Scenario(const Heightfield& terrain, const GeoPoint& south_west_corner,
                                             double altitude_m) {
  MovingObstacleScenario s;
  s.corner_en_m = terrain.frame().toEnu(south_west_corner).head<2>();
  auto local = [&](double x, double y, double z) { return Eigen::Vector3d(s.corner_en_m.x() + x, s.corner_en_m.y() + y, z); };
  auto place = [&](double x, double y) {
    const Eigen::Vector3d p = local(x, y, 0.0);
    return Eigen::Vector3d(p.x(), p.y(), std::max(altitude_m, terrain.heightAt(p.x(), p.y()) + 100.0));
  };
  s.start_m = place(1500.0, 1500.0);
  s.goal_m = place(11500.0, 9000.0);
  const double half_height_m = 2000.0;
  const double centre_z = altitude_m;
  struct Row {
    std::uint64_t id;
    double major_m, minor_m, x0, y0, x1, y1, speed_mps;
  };
  // Table 1: major and minor axes (full lengths), initial and final points, velocity.
  const Row rows[] = {{1, 1200.0, 1200.0, 4900.0, 5400.0, 10400.0, 5400.0, 60.0},
                      {2, 1500.0, 1500.0, 9800.0, 6900.0, 2200.0, 6900.0, 70.0},
                      {3, 1500.0, 1050.0, 6000.0, 6600.0, 11600.0, 11600.0, 80.0}};
  for (const Row& r : rows) {
    Obstacle o;
    o.id = r.id;
    o.shape = ObstacleShape::kEllipsoid;
    o.size_m = Eigen::Vector3d(r.major_m / 2.0, r.minor_m / 2.0, half_height_m);
    o.center_m = local(r.x0, r.y0, centre_z);
    o.motion = BackAndForth{local(r.x0, r.y0, centre_z), local(r.x1, r.y1, centre_z), r.speed_mps, 0.0};
    s.obstacles.push_back(o);
  }
  return s;
}

CollisionWorldOptions seed003ScenarioWorldOptions() {
  CollisionWorldOptions options;
  options.vehicle_radius_m = 10.0;
  options.min_clearance_m = 50.0;
  options.ceiling_m = 1500.0;
  options.build_octree = false;
  return options;
}

VehicleLimits seed003ScenarioLimits() {
  VehicleLimits limits;
  limits.v_ref_mps = 50.0;
  limits.max_speed_mps = 65.0;
  limits.max_accel_mps2 = 10.0;
  limits.max_climb_mps = 20.0;
  limits.max_descent_mps = 20.0;
  return limits;
}

}  // namespace skyroute
