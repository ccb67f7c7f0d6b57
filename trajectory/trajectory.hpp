// A trajectory: consecutive segments from t = 0 (seed 003 eq. 2) evaluated at any time, and
// sampled at a fixed step with the heading of eq. 8.
#pragma once

#include <cstddef>
#include <vector>

#include <Eigen/Core>

#include "trajectory/derivative.hpp"
#include "trajectory/segment.hpp"

namespace skyroute {

struct TrajectoryState {
  double time_s = 0.0;
  Eigen::Vector3d position_m = Eigen::Vector3d::Zero();        // ENU
  Eigen::Vector3d velocity_mps = Eigen::Vector3d::Zero();
  Eigen::Vector3d acceleration_mps2 = Eigen::Vector3d::Zero();
  Eigen::Vector3d jerk_mps3 = Eigen::Vector3d::Zero();
  // Compass heading: degrees clockwise from north in [0, 360), psi = atan2(d_east, d_north) (eq. 8).
  double heading_deg = 0.0;
};

class Trajectory {
 public:
  Trajectory() = default;
  explicit Trajectory(std::vector<Segment> segments);

  bool empty() const { return segments_.empty(); }
  double duration_s() const { return knot_times_s_.empty() ? 0.0 : knot_times_s_.back(); }
  const std::vector<Segment>& segments() const { return segments_; }
  // Time of each joint, t_0 = 0 .. t_M = duration (eqs. 2-4, 7).
  const std::vector<double>& knotTimes() const { return knot_times_s_; }
  std::size_t segmentIndexAt(double t_s) const;

  // Derivative d at time t_s (clamped to [0, duration]); zero for an empty trajectory.
  Eigen::Vector3d evaluate(double t_s, Derivative d) const;
  // Position to jerk at t_s. Heading: the limit of eq. 8 as the step goes to zero, i.e. the
  // direction of the horizontal velocity; at rest, the first non-zero higher derivative's
  // direction (where the vehicle is about to go); 0 when there is no horizontal motion at all.
  TrajectoryState stateAt(double t_s) const;

  // Samples at t = 0, dt, 2 dt, ... and always the end time. Heading by eq. 8 on consecutive
  // samples, psi_j = atan2(x_{j+1} - x_j, y_{j+1} - y_j), the last one repeating the one before;
  // a sample with no horizontal displacement keeps its neighbour's heading. dt_s must be > 0.
  std::vector<TrajectoryState> sample(double dt_s) const;

  // Seed 003 eq. 9: the state at every joint time t_j, with psi_j from eq. 8 on the joint
  // positions (psi_M = psi_{M-1}).
  std::vector<TrajectoryState> knotStates() const;

 private:
  std::vector<Segment> segments_;
  std::vector<double> knot_times_s_;
};

// Compass heading in [0, 360) of a horizontal direction (east, north).
double compassHeadingDeg(double east, double north);

}  // namespace skyroute
