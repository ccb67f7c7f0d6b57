// Cutting a trajectory keeps the curve (every derivative, at every time), and a stop from a state
// in the middle of a turn starts in that state to the jerk, ends at rest and is within the limits.
#include <cmath>

#include <gtest/gtest.h>

#include "tests/trajectory/random_paths.hpp"
#include "trajectory/trajectory_builder.hpp"
#include "trajectory/trajectory_splice.hpp"

namespace skyroute {
namespace {

constexpr Derivative kToJerk[] = {Derivative::kPosition, Derivative::kVelocity, Derivative::kAcceleration,
                                  Derivative::kJerk, Derivative::kSnap};

TEST(TrajectorySplice, SubSegmentIsTheSameCurve) {
  auto built = buildTrajectory(testing::randomWalk(3, 6), VehicleLimits{});
  ASSERT_TRUE(built.ok());
  for (const Segment& s : built->trajectory.segments()) {
    const double a = 0.23 * s.duration_s, b = 0.81 * s.duration_s;
    const Segment piece = subSegment(s, a, b);
    EXPECT_DOUBLE_EQ(piece.duration_s, b - a);
    for (double u : {0.0, 0.1, 0.5, 0.77, 1.0}) {
      for (Derivative d : kToJerk) {
        const Eigen::Vector3d want = s.evaluate(a + u * (b - a), d);
        EXPECT_LT((piece.evaluate(u * (b - a), d) - want).norm(), 1e-8 * std::max(1.0, want.norm()))
            << "u " << u << " derivative " << order(d);
      }
    }
  }
}

TEST(TrajectorySplice, SegmentsBetweenCoverTheRangeWithTheSameCurve) {
  auto built = buildTrajectory(testing::randomWalk(5, 9), VehicleLimits{});
  ASSERT_TRUE(built.ok());
  const Trajectory& t = built->trajectory;
  const auto& knots = t.knotTimes();
  ASSERT_GE(knots.size(), 5u);
  // Cuts inside segments, and exactly at knots (no zero-length piece then).
  const std::pair<double, double> ranges[] = {{0.4 * knots[1], 0.5 * (knots[3] + knots[4])},
                                              {knots[1], knots[3]},
                                              {0.5 * knots[2] + 0.5 * knots[1], 0.6 * knots[2] + 0.4 * knots[1]}};
  for (const auto& [from, to] : ranges) {
    const Trajectory piece(segmentsBetween(t, from, to));
    EXPECT_NEAR(piece.duration_s(), to - from, 1e-9);
    for (const Segment& s : piece.segments()) EXPECT_GT(s.duration_s, 1e-6);
    for (double u = 0.0; u <= 1.0; u += 0.05) {
      for (Derivative d : kToJerk) {
        const Eigen::Vector3d want = t.evaluate(from + u * (to - from), d);
        EXPECT_LT((piece.evaluate(u * (to - from), d) - want).norm(), 1e-7 * std::max(1.0, want.norm()))
            << from << ".." << to << " u " << u << " derivative " << order(d);
      }
    }
  }
  EXPECT_TRUE(segmentsBetween(t, 3.0, 3.0).empty());
  EXPECT_TRUE(segmentsBetween(Trajectory(), 0.0, 1.0).empty());
}

TEST(TrajectorySplice, StopFromTheMiddleOfATurnStartsInItsStateAndEndsAtRest) {
  // A sharp corner flown at speed: find where the acceleration is largest (mid-turn).
  VehicleLimits limits;
  TrajectoryOptions options;
  options.waypoint_spacing_m = 0.0;
  auto built = buildTrajectory({{0, 0, 500}, {2000, 0, 500}, {2000, 2000, 500}}, limits, options);
  ASSERT_TRUE(built.ok());
  ASSERT_NE(built->report.status, TrajectoryStatus::kInfeasible) << built->report.failure_reason;
  const Trajectory& t = built->trajectory;
  TrajectoryState start;
  for (double s = 0.0; s < t.duration_s(); s += 0.05) {
    const TrajectoryState at = t.stateAt(s);
    if (at.acceleration_mps2.norm() > start.acceleration_mps2.norm() && at.velocity_mps.norm() > 10.0) start = at;
  }
  ASSERT_GT(start.acceleration_mps2.norm(), 0.3 * limits.max_accel_mps2);
  const auto stop = stopSegment(start, limits);
  ASSERT_TRUE(stop.has_value());
  const Trajectory stopping({*stop});
  EXPECT_LT((stopping.evaluate(0.0, Derivative::kPosition) - start.position_m).norm(), 1e-9);
  EXPECT_LT((stopping.evaluate(0.0, Derivative::kVelocity) - start.velocity_mps).norm(), 1e-9);
  EXPECT_LT((stopping.evaluate(0.0, Derivative::kAcceleration) - start.acceleration_mps2).norm(), 1e-9);
  EXPECT_LT((stopping.evaluate(0.0, Derivative::kJerk) - start.jerk_mps3).norm(), 1e-8);
  for (Derivative d : {Derivative::kVelocity, Derivative::kAcceleration, Derivative::kJerk})
    EXPECT_LT(stopping.evaluate(stopping.duration_s(), d).norm(), 1e-9) << order(d);
  EXPECT_TRUE(checkFeasibility(stopping, limits).ok());
  // At rest already: nothing to stop.
  TrajectoryState rest;
  rest.position_m = start.position_m;
  EXPECT_FALSE(stopSegment(rest, limits).has_value());
}

}  // namespace
}  // namespace skyroute
