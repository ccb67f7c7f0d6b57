// Seeded random waypoint sets for the trajectory tests: a 3D random walk with legs of 50-400 m,
// turns up to 150 degrees and gentle climbs, the kind of path RRT* + LOSPO hands over.
#pragma once

#include <cmath>
#include <numbers>
#include <random>
#include <vector>

#include <Eigen/Core>

namespace skyroute::testing {

inline std::vector<Eigen::Vector3d> randomWalk(unsigned seed, int count, double min_leg_m = 50.0,
                                               double max_leg_m = 400.0, double max_turn_deg = 150.0) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> leg(min_leg_m, max_leg_m);
  std::uniform_real_distribution<double> turn(-max_turn_deg, max_turn_deg);
  std::uniform_real_distribution<double> slope(-0.15, 0.15);
  std::vector<Eigen::Vector3d> points;
  Eigen::Vector3d p(0.0, 0.0, 500.0);
  double heading = 0.0;
  points.push_back(p);
  for (int i = 1; i < count; ++i) {
    heading += turn(rng) * std::numbers::pi / 180.0;
    const double l = leg(rng);
    p += Eigen::Vector3d(l * std::sin(heading), l * std::cos(heading), l * slope(rng));
    points.push_back(p);
  }
  return points;
}

}  // namespace skyroute::testing
