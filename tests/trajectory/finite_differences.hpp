// Velocity and acceleration of a trajectory measured from its positions alone (central differences
// with a 1 ms step, every 0.01 s): the trajectory tests' independent check of what the polynomials'
// derivatives claim.
#pragma once

#include <Eigen/Core>

#include "trajectory/derivative.hpp"
#include "trajectory/trajectory.hpp"

namespace skyroute::testing {

// Calls visit(time_s, velocity_mps, acceleration_mps2) at each sample time.
template <class Visit>
void forEachFiniteDifference(const Trajectory& t, Visit&& visit) {
  const double h = 1e-3;
  for (double time = h; time < t.duration_s() - h; time += 0.01) {
    const Eigen::Vector3d p0 = t.evaluate(time - h, Derivative::kPosition);
    const Eigen::Vector3d p1 = t.evaluate(time, Derivative::kPosition);
    const Eigen::Vector3d p2 = t.evaluate(time + h, Derivative::kPosition);
    const Eigen::Vector3d v = (p2 - p0) / (2 * h);
    const Eigen::Vector3d a = (p2 - 2 * p1 + p0) / (h * h);
    visit(time, v, a);
  }
}

}  // namespace skyroute::testing
