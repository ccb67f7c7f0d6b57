// Cutting and joining trajectories without changing the curve: a piece of a segment re-expanded
// in its own dimensionless time (the same polynomial, so the same positions and derivatives),
// the part of a trajectory between two times, and a stop from any flown state. The replanner
// keeps the trajectory in force up to a takeover time (a commit horizon) and joins the new plan
// there: the kept part is the flown curve itself, so the joint is continuous to the jerk and the
// kept part is as feasible as the trajectory it comes from.
#pragma once

#include <optional>
#include <vector>

#include <Eigen/Core>

#include "trajectory/feasibility.hpp"
#include "trajectory/segment.hpp"
#include "trajectory/trajectory.hpp"
#include "trajectory/vehicle_limits.hpp"

namespace skyroute {

// The piece of `segment` from local time from_s to to_s (0 <= from_s < to_s <= duration), as a
// segment of its own: evaluate(t) equals segment.evaluate(from_s + t) for every derivative.
Segment subSegment(const Segment& segment, double from_s, double to_s);

// The segments of `trajectory` covering [from_s, to_s] (trajectory times, clamped to the
// trajectory), the first and last cut at those times; a cut within 1 ns of a knot is the knot.
// Empty when the range is empty.
std::vector<Segment> segmentsBetween(const Trajectory& trajectory, double from_s, double to_s);

// A stop from `start` (position to jerk): one degree-7 segment ending at rest (velocity,
// acceleration and jerk zero) along the start velocity, with the shortest duration among the
// tried ones (from the time to brake at brake_accel_share * max_accel, then longer) that passes
// the limits check. nullopt when none passes, or when the start is at rest already.
struct StopOptions {
  double brake_accel_share = 0.5;  // of limits.max_accel_mps2, for the first duration tried
  int durations_tried = 8;         // each 1.3 x the one before
};
std::optional<Segment> stopSegment(const TrajectoryState& start, const VehicleLimits& limits,
                                   const StopOptions& options = {});

}  // namespace skyroute
