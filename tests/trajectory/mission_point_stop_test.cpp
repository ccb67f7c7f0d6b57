// Stops at fixed waypoints (mission points): in the pass mode a fixed corner that no pass-through
// fits, or whose every pass-through collides, becomes a stop instead of a failure; in the stop mode
// every interior fixed waypoint is one. Checked independently: the point is flown exactly, the
// vehicle is at rest there (velocity, acceleration and jerk), speeds, accelerations and turn radii
// measured from positions alone stay within the limits, and the curve keeps clear of the obstacle.
// A trajectory that cannot fly even with stops names the fixed waypoint nearest its violation; the
// last resort, asked for, rests at every corner and flies the checked polyline itself.
#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>

#include <gtest/gtest.h>

#include "tests/trajectory/finite_differences.hpp"
#include "trajectory/knot_stops.hpp"
#include "trajectory/trajectory_builder.hpp"

namespace skyroute {
namespace {

constexpr double kDegToRad = std::numbers::pi / 180.0;

VehicleLimits fixedWing() {
  VehicleLimits limits;
  limits.min_turn_radius_m = 50.0;
  return limits;
}

// A 160 degree turn on 120 m legs: a 50 m pass-through needs far more of each leg than it has.
std::vector<Eigen::Vector3d> hairpin() {
  return {{0, 0, 500},
          {120, 0, 500},
          {120 - 120 * std::cos(20 * kDegToRad), 120 * std::sin(20 * kDegToRad), 500},
          {-200, 200, 520}};
}

// Five corners of 106 degrees each, climbing then descending.
std::vector<Eigen::Vector3d> zigZag() {
  return {{0, 0, 500}, {300, 400, 520}, {600, 0, 540}, {900, 400, 560}, {1200, 0, 560}, {1500, 400, 540}};
}

// Limits measured from positions alone: the largest speed and acceleration, and the smallest turn
// radius where the speed is at least min_turn_speed_mps.
struct Measured {
  double max_speed_mps = 0.0;
  double max_accel_mps2 = 0.0;
  double min_turn_radius_m = std::numeric_limits<double>::infinity();
};

Measured measure(const Trajectory& t, double min_turn_speed_mps) {
  Measured m;
  testing::forEachFiniteDifference(t, [&](double, const Eigen::Vector3d& v, const Eigen::Vector3d& a) {
    m.max_speed_mps = std::max(m.max_speed_mps, v.norm());
    m.max_accel_mps2 = std::max(m.max_accel_mps2, a.norm());
    if (v.norm() < min_turn_speed_mps) return;
    const double cross = v.cross(a).norm();
    if (cross > 0.0) m.min_turn_radius_m = std::min(m.min_turn_radius_m, std::pow(v.norm(), 3) / cross);
  });
  return m;
}

void expectWithinLimits(const Trajectory& t, const VehicleLimits& limits) {
  // Finite differences of 1 ms steps: a little slack on the derivatives, none on the radius
  // (measured from 2 m/s: leaving rest, the curvature changes within one step of the check).
  const Measured m = measure(t, 2.0);
  EXPECT_LE(m.max_speed_mps, limits.max_speed_mps * 1.001);
  EXPECT_LE(m.max_accel_mps2, limits.max_accel_mps2 * 1.01);
  if (limits.min_turn_radius_m > 0.0) {
    EXPECT_GE(m.min_turn_radius_m, limits.min_turn_radius_m);
  }
}

// Knot time of input waypoint w (it is a knot, bit-exact).
double knotTime(const BuiltTrajectory& built, const Eigen::Vector3d& w) {
  for (std::size_t k = 0; k < built.knots.size(); ++k)
    if (built.knots[k] == w) return built.trajectory.knotTimes()[k];
  ADD_FAILURE() << "no knot at " << w.transpose();
  return 0.0;
}

void expectAtRest(const BuiltTrajectory& built, const Eigen::Vector3d& w) {
  const double t = knotTime(built, w);
  EXPECT_LT((built.trajectory.evaluate(t, Derivative::kPosition) - w).norm(), 1e-6);
  // Measured from positions around the knot: the vehicle has not moved 1 mm within 0.1 s of it.
  for (double dt : {-0.1, -0.01, 0.01, 0.1}) {
    EXPECT_LT((built.trajectory.evaluate(t + dt, Derivative::kPosition) - w).norm(), 1e-3) << dt;
  }
  EXPECT_LT(built.trajectory.evaluate(t, Derivative::kVelocity).norm(), 1e-6);
  EXPECT_LT(built.trajectory.evaluate(t, Derivative::kAcceleration).norm(), 1e-6);
  EXPECT_LT(built.trajectory.evaluate(t, Derivative::kJerk).norm(), 1e-6);
}

TEST(MissionPointStop, PassStopsWhereNoPassThroughFits) {
  const auto w = hairpin();
  const VehicleLimits limits = fixedWing();
  TrajectoryOptions options;
  options.fixed_waypoints = {1, 2};
  auto built = buildTrajectory(w, limits, options);
  ASSERT_TRUE(built.ok());
  ASSERT_NE(built->report.status, TrajectoryStatus::kInfeasible) << built->report.failure_reason;
  // The hairpin stops; the gentle corner after it (18 degrees, room for a pass-through) does not.
  ASSERT_EQ(built->report.stops.size(), 1u) << ::testing::PrintToString(built->report.repairs);
  EXPECT_EQ(built->report.stops[0].waypoint, 1u);
  EXPECT_NE(built->report.stops[0].reason.find("cannot be rounded"), std::string::npos) << built->report.stops[0].reason;
  expectAtRest(*built, w[1]);
  EXPECT_GT(built->trajectory.evaluate(knotTime(*built, w[2]), Derivative::kVelocity).norm(), 5.0);
  expectWithinLimits(built->trajectory, limits);
}

TEST(MissionPointStop, PassKeepsFlyingThroughWhereItCan) {
  // The zig-zag's fixed corners have room for a pass-through: no stop, the vehicle flies through.
  const auto w = zigZag();
  TrajectoryOptions options;
  options.fixed_waypoints = {1, 3};
  auto built = buildTrajectory(w, fixedWing(), options);
  ASSERT_TRUE(built.ok());
  ASSERT_NE(built->report.status, TrajectoryStatus::kInfeasible) << built->report.failure_reason;
  EXPECT_TRUE(built->report.stops.empty());
  for (std::size_t i : {1u, 3u}) EXPECT_GT(built->trajectory.evaluate(knotTime(*built, w[i]), Derivative::kVelocity).norm(), 5.0);
}

TEST(MissionPointStop, StopModeRestsAtEveryInteriorFixedWaypoint) {
  const auto w = zigZag();
  for (const VehicleLimits& limits : {fixedWing(), VehicleLimits{}}) {
    TrajectoryOptions options;
    options.fixed_waypoints = {4, 1, 3, 0, 5};
    options.fixed_waypoint_mode = FixedWaypointMode::kStop;
    auto built = buildTrajectory(w, limits, options);
    ASSERT_TRUE(built.ok());
    ASSERT_NE(built->report.status, TrajectoryStatus::kInfeasible) << built->report.failure_reason;
    ASSERT_EQ(built->report.stops.size(), 3u);
    for (std::size_t k = 0; k < 3; ++k) EXPECT_EQ(built->report.stops[k].waypoint, std::size_t{1} + k + (k > 0 ? 1 : 0));
    for (std::size_t i : {1u, 3u, 4u}) expectAtRest(*built, w[i]);
    expectWithinLimits(built->trajectory, limits);
    // Between the stops it moves: waypoint 2 (not fixed) is not a stop.
    const double middle = 0.5 * (knotTime(*built, w[1]) + knotTime(*built, w[3]));
    EXPECT_GT(built->trajectory.evaluate(middle, Derivative::kVelocity).norm(), 1.0);
  }
}

// A sphere of radius r at c, as a motion check that rejects every motion touching it.
MotionCheck sphereCheck(const Eigen::Vector3d& c, double r) {
  return [c, r](const Eigen::Vector3d& a, double, const Eigen::Vector3d& b, double) {
    const Eigen::Vector3d d = b - a;
    const double u = std::clamp((c - a).dot(d) / std::max(d.squaredNorm(), 1e-12), 0.0, 1.0);
    return (a + u * d - c).norm() > r;
  };
}

TEST(MissionPointStop, PassStopsWhereEveryPassThroughCollides) {
  // The pass-through at zig-zag corner 2 crosses the point along the turn's bisector h for at
  // least 30 m each way; a sphere on that line 20 m past the point (clear of both legs, 16 m and
  // 20 m away) blocks every one, while a stop keeps to the legs.
  const auto w = zigZag();
  const VehicleLimits limits = fixedWing();
  const Eigen::Vector3d h = ((w[3] - w[2]).normalized() + (w[2] - w[1]).normalized()).normalized();
  const Eigen::Vector3d centre = w[2] + 20.0 * h;
  const double r = 12.0;
  MotionCheck check = sphereCheck(centre, r);
  ASSERT_TRUE(check(w[1], 0, w[2], 1));
  ASSERT_TRUE(check(w[2], 0, w[3], 1));
  TrajectoryOptions options;
  options.fixed_waypoints = {2};
  auto built = buildTrajectory(w, limits, options, &check);
  ASSERT_TRUE(built.ok());
  ASSERT_NE(built->report.status, TrajectoryStatus::kInfeasible) << built->report.failure_reason;
  ASSERT_EQ(built->report.stops.size(), 1u) << ::testing::PrintToString(built->report.repairs);
  EXPECT_EQ(built->report.stops[0].waypoint, 2u);
  EXPECT_NE(built->report.stops[0].reason.find("collides"), std::string::npos) << built->report.stops[0].reason;
  expectAtRest(*built, w[2]);
  expectWithinLimits(built->trajectory, limits);
  for (double t = 0.0; t <= built->trajectory.duration_s(); t += 0.01)
    ASSERT_GT((built->trajectory.evaluate(t, Derivative::kPosition) - centre).norm(), r) << t;
}

TEST(MissionPointStop, AFailureNamesTheFixedWaypointNearestItsViolation) {
  // The straight path into waypoint 3 is blocked: no repair and no stop helps, and the report
  // names waypoint 3 (fixed) as the place, after trying a stop there.
  const auto w = zigZag();
  MotionCheck blocked = sphereCheck(0.5 * (w[2] + w[3]), 5.0);
  TrajectoryOptions options;
  options.fixed_waypoints = {1, 3};
  auto built = buildTrajectory(w, VehicleLimits{}, options, &blocked);
  ASSERT_TRUE(built.ok());
  EXPECT_EQ(built->report.status, TrajectoryStatus::kInfeasible);
  ASSERT_TRUE(built->report.failure_waypoint.has_value());
  ASSERT_TRUE(built->report.failure_violation.has_value());
  EXPECT_EQ(built->report.failure_violation->kind, ViolationKind::kCollision);
  EXPECT_NE(built->report.failure_reason.find("blocked"), std::string::npos) << built->report.failure_reason;
  EXPECT_EQ(*built->report.failure_waypoint, 3u);
  ASSERT_FALSE(built->report.stops.empty());
}

double distanceToPolyline(const Eigen::Vector3d& p, const std::vector<Eigen::Vector3d>& w) {
  double best = std::numeric_limits<double>::infinity();
  for (std::size_t k = 1; k < w.size(); ++k) {
    const Eigen::Vector3d d = w[k] - w[k - 1];
    const double u = std::clamp((p - w[k - 1]).dot(d) / d.squaredNorm(), 0.0, 1.0);
    best = std::min(best, (w[k - 1] + u * d - p).norm());
  }
  return best;
}

TEST(MissionPointStop, LastResortRestsAtEveryCornerOnTheCheckedPath) {
  // Corners too sharp for the turn radius and no rounding allowed: nothing flies through them.
  // Asked for, the last resort rests at every corner and flies the polyline itself, straight.
  const auto w = zigZag();
  const VehicleLimits limits = fixedWing();
  TrajectoryOptions options;
  options.round_corners = false;
  options.fixed_waypoints = {2};
  auto failed = buildTrajectory(w, limits, options);
  ASSERT_TRUE(failed.ok());
  EXPECT_EQ(failed->report.status, TrajectoryStatus::kInfeasible);
  options.stop_at_corners_as_last_resort = true;
  auto built = buildTrajectory(w, limits, options);
  ASSERT_TRUE(built.ok());
  ASSERT_NE(built->report.status, TrajectoryStatus::kInfeasible) << built->report.failure_reason;
  ASSERT_EQ(built->report.stops.size(), w.size() - 2);
  for (std::size_t i = 1; i + 1 < w.size(); ++i) expectAtRest(*built, w[i]);
  for (double t = 0.0; t <= built->trajectory.duration_s(); t += 0.05) {
    ASSERT_LT(distanceToPolyline(built->trajectory.evaluate(t, Derivative::kPosition), w), 1e-6) << t;
  }
  expectWithinLimits(built->trajectory, limits);
}

TEST(MissionPointStop, PiecewiseSolveRestsAtTheStopsAndIsSmoothElsewhere) {
  const auto w = zigZag();
  const VehicleLimits limits;
  const std::vector<std::size_t> stops{2, 4, 2};
  auto durations = allocateTimesWithStops(w, limits, {}, stops);
  ASSERT_TRUE(durations.ok());
  auto segments = solveMinimumSnapSplineWithStops(w, *durations, {}, stops);
  ASSERT_TRUE(segments.ok());
  ASSERT_EQ(segments->size(), w.size() - 1);
  const Trajectory t(std::move(*segments));
  const auto& times = t.knotTimes();
  for (std::size_t k = 0; k < w.size(); ++k) {
    EXPECT_LT((t.evaluate(times[k], Derivative::kPosition) - w[k]).norm(), 1e-6) << k;
    const bool rest = k == 0 || k == 2 || k == 4 || k + 1 == w.size();
    const double speed = t.evaluate(times[k], Derivative::kVelocity).norm();
    if (rest) {
      EXPECT_LT(speed, 1e-6) << k;
    } else {
      EXPECT_GT(speed, 1.0) << k;
    }
  }
  // Continuous to the jerk at every joint, the stops included (both sides are zero there).
  for (std::size_t s = 0; s + 1 < t.segments().size(); ++s) {
    const Segment& a = t.segments()[s];
    const Segment& b = t.segments()[s + 1];
    for (Derivative d : {Derivative::kPosition, Derivative::kVelocity, Derivative::kAcceleration, Derivative::kJerk}) {
      EXPECT_LT((a.evaluate(a.duration_s, d) - b.evaluate(0.0, d)).norm(), 1e-6) << s;
    }
  }
  EXPECT_EQ(parseFixedWaypointMode("stop"), FixedWaypointMode::kStop);
  EXPECT_EQ(parseFixedWaypointMode("pass"), FixedWaypointMode::kPass);
  EXPECT_FALSE(parseFixedWaypointMode("Stop").has_value());
}

}  // namespace
}  // namespace skyroute
