// Feasibility: planted violations of each limit are found (against an independent finite-difference
// measurement of the sampled positions), repair fixes what time stretching and extra waypoints
// can fix, and reports why not otherwise. Collision re-check through synthetic motion checks.
#include <cmath>
#include <limits>

#include <gtest/gtest.h>

#include "tests/trajectory/finite_differences.hpp"
#include "tests/trajectory/random_paths.hpp"
#include "trajectory/feasibility.hpp"
#include "trajectory/spline7.hpp"
#include "trajectory/trajectory_builder.hpp"

namespace skyroute {
namespace {

struct Measured {
  double speed = 0, accel = 0, climb = 0, descent = 0;
};

// Speeds and accelerations from positions only (central differences), every 0.01 s.
Measured measureByFiniteDifferences(const Trajectory& t) {
  Measured m;
  testing::forEachFiniteDifference(t, [&m](double, const Eigen::Vector3d& v, const Eigen::Vector3d& a) {
    m.speed = std::max(m.speed, v.norm());
    m.accel = std::max(m.accel, a.norm());
    m.climb = std::max(m.climb, v.z());
    m.descent = std::max(m.descent, -v.z());
  });
  return m;
}

double distanceToPolyline(const Eigen::Vector3d& p, const std::vector<Eigen::Vector3d>& poly) {
  double best = std::numeric_limits<double>::infinity();
  for (std::size_t i = 0; i + 1 < poly.size(); ++i) {
    const Eigen::Vector3d d = poly[i + 1] - poly[i];
    const double u = std::clamp((p - poly[i]).dot(d) / d.squaredNorm(), 0.0, 1.0);
    best = std::min(best, (poly[i] + u * d - p).norm());
  }
  return best;
}

Trajectory fromDurations(const std::vector<Eigen::Vector3d>& w, double speed_mps) {
  std::vector<double> d;
  for (std::size_t i = 1; i < w.size(); ++i) d.push_back((w[i] - w[i - 1]).norm() / speed_mps);
  return Trajectory(solveMinimumSnapSpline(w, d).value());
}

TEST(Feasibility, FindsPlantedViolationsOfEachLimit) {
  VehicleLimits limits;
  // Straight and level at an average of 58 m/s rest to rest: peak speed far above 60 m/s.
  const std::vector<Eigen::Vector3d> line{{0, 0, 500}, {3000, 0, 500}};
  Trajectory fast = fromDurations(line, 58.0);
  FeasibilityReport r = checkFeasibility(fast, limits);
  const Measured m = measureByFiniteDifferences(fast);
  EXPECT_TRUE(r.has(ViolationKind::kSpeed));
  EXPECT_NEAR(r.max_speed_mps, m.speed, 0.02 * m.speed);
  EXPECT_NEAR(r.max_accel_mps2, m.accel, 0.02 * m.accel);
  EXPECT_GT(m.speed, limits.max_speed_mps);
  EXPECT_FALSE(r.has(ViolationKind::kClimbRate));
  // Short and quick: acceleration.
  Trajectory jumpy = fromDurations({{0, 0, 500}, {200, 0, 500}}, 40.0);
  r = checkFeasibility(jumpy, limits);
  EXPECT_TRUE(r.has(ViolationKind::kAcceleration));
  EXPECT_GT(measureByFiniteDifferences(jumpy).accel, limits.max_accel_mps2);
  // Steep climb and steep descent.
  Trajectory climb = fromDurations({{0, 0, 500}, {600, 0, 1100}}, 20.0);
  r = checkFeasibility(climb, limits);
  EXPECT_TRUE(r.has(ViolationKind::kClimbRate));
  EXPECT_NEAR(r.max_climb_mps, measureByFiniteDifferences(climb).climb, 0.02 * r.max_climb_mps);
  Trajectory dive = fromDurations({{0, 0, 1100}, {600, 0, 500}}, 20.0);
  EXPECT_TRUE(checkFeasibility(dive, limits).has(ViolationKind::kDescentRate));
  // A sharp corner against a large minimum turn radius.
  limits.min_turn_radius_m = 800.0;
  Trajectory corner = fromDurations({{0, 0, 500}, {1000, 0, 500}, {1000, 1000, 500}}, 30.0);
  r = checkFeasibility(corner, limits);
  EXPECT_TRUE(r.has(ViolationKind::kTurnRadius));
  EXPECT_LT(r.min_turn_radius_m, 800.0);
  // A gentle version of the same flight passes.
  limits = VehicleLimits{};
  Trajectory gentle = fromDurations(line, 20.0);
  EXPECT_TRUE(checkFeasibility(gentle, limits).ok());
}

TEST(Feasibility, RepairStretchesTimeUntilTheLimitsHold) {
  VehicleLimits limits;
  TrajectoryOptions options;
  options.time_allocation.method = TimeAllocationMethod::kConstantSpeed;  // eq. 3: infeasible ends
  for (unsigned seed = 1; seed <= 10; ++seed) {
    const auto w = testing::randomWalk(seed, 10);
    auto built = buildTrajectory(w, limits, options);
    ASSERT_TRUE(built.ok()) << built.error().describe();
    const TrajectoryBuildReport& report = built->report;
    EXPECT_EQ(report.status, TrajectoryStatus::kRepaired) << "seed " << seed << ": " << report.failure_reason;
    EXPECT_FALSE(report.repairs.empty());
    const Measured m = measureByFiniteDifferences(built->trajectory);
    EXPECT_LE(m.speed, limits.max_speed_mps * 1.01) << "seed " << seed;
    EXPECT_LE(m.accel, limits.max_accel_mps2 * 1.01) << "seed " << seed;
    EXPECT_LE(m.climb, limits.max_climb_mps * 1.01);
    EXPECT_LE(m.descent, limits.max_descent_mps * 1.01);
  }
}

TEST(Feasibility, RepairAddsWaypointsWhereTheCurveLeavesTheCheckedCorridor) {
  // Motion check: valid only within 3 m of the input polyline (a tube around the checked path).
  const auto w = testing::randomWalk(42, 8, 200.0, 600.0, 120.0);
  const double tube_m = 3.0;
  MotionCheck tube = [&](const Eigen::Vector3d& a, double, const Eigen::Vector3d& b, double) {
    return distanceToPolyline(a, w) <= tube_m && distanceToPolyline(b, w) <= tube_m;
  };
  VehicleLimits limits;
  TrajectoryOptions options;
  options.waypoint_spacing_m = 0.0;  // no extra waypoints: the curve rounds corners wide
  options.max_repair_rounds = 40;
  auto built = buildTrajectory(w, limits, options, &tube);
  ASSERT_TRUE(built.ok());
  EXPECT_EQ(built->report.status, TrajectoryStatus::kRepaired) << built->report.failure_reason;
  EXPECT_GT(built->report.knots, w.size());
  // Independent dense check of the final curve.
  for (double t = 0.0; t <= built->trajectory.duration_s(); t += 0.01)
    ASSERT_LE(distanceToPolyline(built->trajectory.evaluate(t, Derivative::kPosition), w), tube_m + 1e-6) << t;
}

TEST(Feasibility, ReportsWhyItCannotRepair) {
  VehicleLimits limits;
  const std::vector<Eigen::Vector3d> w{{0, 0, 500}, {2000, 0, 500}, {4000, 0, 500}};
  // A sphere of 50 m radius sits on the straight path itself.
  const Eigen::Vector3d centre(3000, 0, 500);
  MotionCheck sphere = [&](const Eigen::Vector3d& a, double, const Eigen::Vector3d& b, double) {
    const Eigen::Vector3d d = b - a;
    const double u = std::clamp((centre - a).dot(d) / std::max(d.squaredNorm(), 1e-12), 0.0, 1.0);
    return (a + u * d - centre).norm() > 50.0;
  };
  auto built = buildTrajectory(w, limits, {}, &sphere);
  ASSERT_TRUE(built.ok());
  EXPECT_EQ(built->report.status, TrajectoryStatus::kInfeasible);
  EXPECT_NE(built->report.failure_reason.find("itself blocked"), std::string::npos) << built->report.failure_reason;
  EXPECT_TRUE(built->report.final_check.has(ViolationKind::kCollision));

  // A turn tighter than the vehicle can fly.
  limits.min_turn_radius_m = 2000.0;
  auto corner = buildTrajectory({{0, 0, 500}, {1000, 0, 500}, {1000, 1000, 500}}, limits);
  ASSERT_TRUE(corner.ok());
  EXPECT_EQ(corner->report.status, TrajectoryStatus::kInfeasible);
  EXPECT_NE(corner->report.failure_reason.find("turn_radius"), std::string::npos) << corner->report.failure_reason;
}

TEST(Feasibility, StopsWhenStretchingAGivenStartVelocityOnlyMakesItWorse) {
  // A takeover state from a replan (45 m/s, 25 degrees off the path, accelerating sideways with
  // 12 m/s^3 of jerk): the first 100 m knot asks for more than the vehicle has, and a longer
  // first segment only lets the curve run further off before it must come back. The build must
  // say so after a few rounds instead of stretching that segment to hundreds of seconds.
  const VehicleLimits limits;  // the defaults: seed 003's vehicle, 50 m/s cruise, 60 max, 10 m/s^2, 15 m/s up and down
  TrajectoryOptions options;
  options.boundary.start.velocity_mps = Eigen::Vector3d(40.7, 19.4, -0.2);
  options.boundary.start.acceleration_mps2 = Eigen::Vector3d(2.3, 3.8, 0.2);
  options.boundary.start.jerk_mps3 = Eigen::Vector3d(-3.5, 11.2, 1.1);
  const Eigen::Vector3d p0(0, 0, 500), d(62.7, 77.4, -3.3);
  const std::vector<Eigen::Vector3d> path{p0, p0 + d, p0 + 10.0 * d};
  auto built = buildTrajectory(path, limits, options);
  ASSERT_TRUE(built.ok());
  EXPECT_EQ(built->report.status, TrajectoryStatus::kInfeasible);
  EXPECT_LT(built->report.repair_rounds, options.max_repair_rounds) << built->report.failure_reason;
  EXPECT_LT(built->trajectory.duration_s(), 200.0);
  EXPECT_NE(built->report.failure_reason.find("worse"), std::string::npos) << built->report.failure_reason;
  // The same path from rest is feasible: the stop is about the start state, not the path.
  auto from_rest = buildTrajectory(path, limits);
  ASSERT_TRUE(from_rest.ok());
  EXPECT_NE(from_rest->report.status, TrajectoryStatus::kInfeasible) << from_rest->report.failure_reason;
}

TEST(Feasibility, TimedMotionCheckSeesMovingObstacles) {
  // A 40 m sphere crosses the straight line x = 0..3000 at x = 1500, moving along +y at 30 m/s,
  // at y = 0 at world time 50 s. The check gets trajectory times; an independent dense sweep
  // confirms the built trajectory never comes within 40 m of the sphere's centre.
  const std::vector<Eigen::Vector3d> w{{0, 0, 500}, {1500, 0, 500}, {3000, 0, 500}};
  auto centre_at = [](double t) { return Eigen::Vector3d(1500, 30.0 * (t - 50.0), 500); };
  MotionCheck moving = [&](const Eigen::Vector3d& a, double ta, const Eigen::Vector3d& b, double tb) {
    for (int k = 0; k <= 20; ++k) {
      const double u = k / 20.0;
      if ((a + u * (b - a) - centre_at(ta + u * (tb - ta))).norm() <= 40.0) return false;
    }
    return true;
  };
  VehicleLimits limits;
  auto built = buildTrajectory(w, limits, {}, &moving);
  ASSERT_TRUE(built.ok());
  if (built->report.status == TrajectoryStatus::kInfeasible) {
    // It meets the sphere on the path itself: the report must say so (replanning is the answer).
    EXPECT_NE(built->report.failure_reason.find("itself blocked"), std::string::npos);
  } else {
    for (double t = 0; t <= built->trajectory.duration_s(); t += 0.005)
      ASSERT_GT((built->trajectory.evaluate(t, Derivative::kPosition) - centre_at(t)).norm(), 40.0 - 1.0) << t;
  }
  // The same check is blind to the sphere when it passes long before the vehicle arrives.
  auto early = [&](const Eigen::Vector3d& a, double ta, const Eigen::Vector3d& b, double tb) {
    return moving(a, ta + 1000.0, b, tb + 1000.0);
  };
  MotionCheck early_check = early;
  auto clear = buildTrajectory(w, limits, {}, &early_check);
  ASSERT_TRUE(clear.ok());
  EXPECT_EQ(clear->report.status, TrajectoryStatus::kFeasible);
}

TEST(Feasibility, BuilderBadInputNamesTheField) {
  VehicleLimits limits;
  EXPECT_EQ(buildTrajectory({{0, 0, 0}}, limits).error().field, "waypoints");
  EXPECT_EQ(buildTrajectory({}, limits).error().field, "waypoints");
  EXPECT_EQ(buildTrajectory({{0, 0, 0}, {1, 1, std::nan("")}}, limits).error().field, "waypoints[1]");
  EXPECT_EQ(buildTrajectory({{0, 0, 0}, {100, 0, 0}, {100, 0, 0}}, limits).error().field, "waypoints[2]");
  limits.v_ref_mps = 0.0;
  auto r = buildTrajectory({{0, 0, 0}, {100, 0, 0}}, limits);
  ASSERT_FALSE(r.ok());
  EXPECT_EQ(r.error().field, "limits.v_ref_mps");
  EXPECT_EQ(r.error().code, ErrorCode::kInvalidArgument);
  EXPECT_NE(r.error().describe().find("v_ref"), std::string::npos);
  limits = VehicleLimits{};
  TrajectoryOptions options;
  options.waypoint_spacing_m = -1.0;
  EXPECT_EQ(buildTrajectory({{0, 0, 0}, {100, 0, 0}}, limits, options).error().field, "options.waypoint_spacing_m");
  options = TrajectoryOptions{};
  options.boundary.start.velocity_mps.x() = std::nan("");
  EXPECT_EQ(buildTrajectory({{0, 0, 0}, {100, 0, 0}}, limits, options).error().field, "boundary.start.velocity_mps");
}

}  // namespace
}  // namespace skyroute
