#include "trajectory/trajectory.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>

namespace skyroute {

double compassHeadingDeg(double east, double north) {
  double deg = std::atan2(east, north) * 180.0 / std::numbers::pi;
  if (deg < 0.0) deg += 360.0;
  if (deg >= 360.0) deg -= 360.0;
  return deg;
}

Trajectory::Trajectory(std::vector<Segment> segments) : segments_(std::move(segments)) {
  knot_times_s_.reserve(segments_.size() + 1);
  double t = 0.0;
  knot_times_s_.push_back(t);
  for (const Segment& s : segments_) {
    t += s.duration_s;
    knot_times_s_.push_back(t);
  }
}

std::size_t Trajectory::segmentIndexAt(double t_s) const {
  if (segments_.empty()) return 0;
  // First knot strictly after t, minus one, clamped to a real segment.
  const auto it = std::upper_bound(knot_times_s_.begin(), knot_times_s_.end(), t_s);
  std::size_t index = it == knot_times_s_.begin() ? 0 : static_cast<std::size_t>(it - knot_times_s_.begin()) - 1;
  return std::min(index, segments_.size() - 1);
}

Eigen::Vector3d Trajectory::evaluate(double t_s, Derivative d) const {
  if (segments_.empty()) return Eigen::Vector3d::Zero();
  t_s = std::clamp(t_s, 0.0, duration_s());
  const std::size_t i = segmentIndexAt(t_s);
  return segments_[i].evaluate(t_s - knot_times_s_[i], d);
}

TrajectoryState Trajectory::stateAt(double t_s) const {
  TrajectoryState state;
  state.time_s = t_s;
  if (segments_.empty()) return state;
  const double t = std::clamp(t_s, 0.0, duration_s());
  const std::size_t i = segmentIndexAt(t);
  const Segment& segment = segments_[i];
  const double local = t - knot_times_s_[i];
  const double tau = segment.duration_s > 0.0 ? std::clamp(local / segment.duration_s, 0.0, 1.0) : 0.0;
  Eigen::Vector3d derivative[5];
  for (int axis = 0; axis < 3; ++axis) {
    double d[5];
    segment.axes[static_cast<std::size_t>(axis)].evaluateTimeUpTo(tau, 4, segment.duration_s, d);
    for (int n = 0; n < 5; ++n) derivative[n](axis) = d[n];
  }
  state.position_m = derivative[0];
  state.velocity_mps = derivative[1];
  state.acceleration_mps2 = derivative[2];
  state.jerk_mps3 = derivative[3];
  // Heading: first derivative with a horizontal part that is not negligible. The thresholds are
  // relative to the trajectory's scale so that round-off at a rest point does not set the heading.
  const Eigen::Vector3d candidates[] = {derivative[1], derivative[2], derivative[3], derivative[4]};
  for (const Eigen::Vector3d& c : candidates) {
    if (std::hypot(c.x(), c.y()) > 1e-9 * (1.0 + c.norm()) && std::hypot(c.x(), c.y()) > 1e-12) {
      state.heading_deg = compassHeadingDeg(c.x(), c.y());
      break;
    }
  }
  return state;
}

std::vector<TrajectoryState> Trajectory::knotStates() const {
  std::vector<TrajectoryState> knots;
  for (double t : knot_times_s_) knots.push_back(stateAt(t));
  for (std::size_t j = 0; j + 1 < knots.size(); ++j) {
    const Eigen::Vector3d step = knots[j + 1].position_m - knots[j].position_m;
    if (std::hypot(step.x(), step.y()) > 1e-9) knots[j].heading_deg = compassHeadingDeg(step.x(), step.y());
  }
  if (knots.size() >= 2) knots.back().heading_deg = knots[knots.size() - 2].heading_deg;
  return knots;
}

std::vector<TrajectoryState> Trajectory::sample(double dt_s) const {
  std::vector<TrajectoryState> samples;
  if (segments_.empty() || !(dt_s > 0.0) || !std::isfinite(dt_s)) return samples;
  const double end = duration_s();
  const auto steps = static_cast<std::size_t>(std::floor(end / dt_s + 1e-9));
  samples.reserve(steps + 2);
  for (std::size_t k = 0; k <= steps; ++k) samples.push_back(stateAt(std::min(end, static_cast<double>(k) * dt_s)));
  if (end - samples.back().time_s > 1e-9 * std::max(1.0, end)) samples.push_back(stateAt(end));
  // Eq. 8 on consecutive samples.
  const std::size_t n = samples.size();
  std::vector<bool> defined(n, false);
  for (std::size_t j = 0; j + 1 < n; ++j) {
    const Eigen::Vector3d step = samples[j + 1].position_m - samples[j].position_m;
    if (std::hypot(step.x(), step.y()) > 1e-9) {
      samples[j].heading_deg = compassHeadingDeg(step.x(), step.y());
      defined[j] = true;
    }
  }
  // psi_M = psi_{M-1}; undefined ones (no horizontal displacement) copy the previous defined one,
  // or the next one at the start; with no horizontal motion at all they keep stateAt's heading.
  if (n >= 2) {
    samples[n - 1].heading_deg = samples[n - 2].heading_deg;
    defined[n - 1] = defined[n - 2];
  }
  std::size_t first_defined = n;
  for (std::size_t j = 0; j < n; ++j)
    if (defined[j]) { first_defined = j; break; }
  if (first_defined < n) {
    for (std::size_t j = 0; j < first_defined; ++j) samples[j].heading_deg = samples[first_defined].heading_deg;
    for (std::size_t j = first_defined + 1; j < n; ++j)
      if (!defined[j]) samples[j].heading_deg = samples[j - 1].heading_deg;
  }
  return samples;
}

}  // namespace skyroute
