// The moving-obstacle scenario of seed 003 (Table 1, Fig. 10) placed on a real DEM. The seed used
// a 12.6 x 12.6 km terrain near Seoul with 600 m mountains; the default placement is the square
// whose south-west corner is 44.2 N, 71.9 W on the N44W072 tile (hills up to 591 m). Table 1's
// coordinates are metres east and north of that corner. The obstacles are ellipses in the seed;
// here ellipsoids tall enough (4 km) that the vehicle must go around them, not over.
#pragma once

#include <vector>

#include "terrain/collision_world.hpp"
#include "terrain/heightfield.hpp"
#include "terrain/obstacle.hpp"
#include "trajectory/vehicle_limits.hpp"

namespace skyroute {

struct MovingObstacleScenario {
  std::vector<Obstacle> obstacles;  // A, B, C of Table 1, moving back and forth from world time 0
  Eigen::Vector3d start_m = Eigen::Vector3d::Zero();
  Eigen::Vector3d goal_m = Eigen::Vector3d::Zero();
  Eigen::Vector2d corner_en_m = Eigen::Vector2d::Zero();  // the square's south-west corner in ENU
};

// start and goal are at (1500, 1500) and (11500, 9000) m in the square (the route crosses the tracks
// of A and B and runs beside C's), at altitude_m AMSL or 100 m above the ground there, whichever is higher.
// The scenario's vehicle: V_ref 50 m/s with the speed, acceleration and climb margins the
// replanning tests and benchmark fly it with.
VehicleLimits seed003ScenarioLimits();
// The scenario's world: that vehicle's radius (10 m) and terrain clearance (50 m), a 1500 m AMSL
// ceiling, no octree (the checks run on the heightfield).
CollisionWorldOptions seed003ScenarioWorldOptions();

MovingObstacleScenario seed003Table1Scenario(const Heightfield& terrain, const GeoPoint& south_west_corner = {44.2, -71.9, 0.0},
                                             double altitude_m = 450.0);

}  // namespace skyroute
