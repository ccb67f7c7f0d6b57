// A segment is a duration plus one degree-7 polynomial per ENU axis (as in mav_trajectory_generation).
#pragma once

#include <array>

#include <Eigen/Core>

#include "trajectory/polynomial.hpp"

namespace skyroute {

struct Segment {
  double duration_s = 0.0;
  std::array<Polynomial7, 3> axes;  // east, north, up; each in tau = t_local / duration_s

  // Derivative d in ENU at local time t_local_s in [0, duration_s] (clamped).
  Eigen::Vector3d evaluate(double t_local_s, Derivative d) const {
    double tau = duration_s > 0.0 ? t_local_s / duration_s : 0.0;
    tau = tau < 0.0 ? 0.0 : (tau > 1.0 ? 1.0 : tau);
    return {axes[0].evaluateTime(tau, d, duration_s), axes[1].evaluateTime(tau, d, duration_s),
            axes[2].evaluateTime(tau, d, duration_s)};
  }
};

}  // namespace skyroute
