// Time allocation: eq. 3 exactly; the trapezoidal profile against its closed form on a straight
// line; turn and climb limits; the built trajectory within the vehicle's limits before any repair;
// extra waypoints at the spacing; bad input.
#include <cmath>
#include <numeric>

#include <gtest/gtest.h>

#include "tests/trajectory/random_paths.hpp"
#include "trajectory/feasibility.hpp"
#include "trajectory/spline7.hpp"
#include "trajectory/time_allocation.hpp"
#include "trajectory/trajectory_builder.hpp"

namespace skyroute {
namespace {

double sum(const std::vector<double>& v) { return std::accumulate(v.begin(), v.end(), 0.0); }

TEST(TimeAllocation, ConstantSpeedIsEquation3) {
  const auto w = testing::randomWalk(3, 20);
  VehicleLimits limits;
  limits.v_ref_mps = 42.0;
  TimeAllocationOptions options;
  options.method = TimeAllocationMethod::kConstantSpeed;
  auto durations = allocateTimes(w, limits, options);
  ASSERT_TRUE(durations.ok());
  for (std::size_t j = 0; j < durations->size(); ++j) {
    const Eigen::Vector3d d = w[j + 1] - w[j];
    EXPECT_DOUBLE_EQ((*durations)[j], std::sqrt(d.x() * d.x() + d.y() * d.y() + d.z() * d.z()) / 42.0);
  }
}

TEST(TimeAllocation, TrapezoidOnAStraightLineMatchesClosedForm) {
  VehicleLimits limits;
  limits.v_ref_mps = 50.0;
  limits.max_accel_mps2 = 8.0;
  TimeAllocationOptions options;
  options.accel_fraction = 0.5;  // 4 m/s^2
  const double a = 4.0, v = 50.0;
  // Long line: accelerate, cruise, brake. T = L / v + v / a.
  for (double length : {5000.0, 1200.0}) {
    const std::vector<Eigen::Vector3d> line{{0, 0, 100}, {length, 0, 100}};
    const auto dense = densifyWaypoints(line, 100.0).points;
    auto durations = allocateTimes(dense, limits, options);
    ASSERT_TRUE(durations.ok());
    EXPECT_NEAR(sum(*durations), length / v + v / a, 1e-9) << length;
  }
  // Short line: triangle, T = 2 sqrt(L / a).
  const std::vector<Eigen::Vector3d> short_line{{0, 0, 100}, {0, 300, 100}};
  auto durations = allocateTimes(densifyWaypoints(short_line, 50.0).points, limits, options);
  ASSERT_TRUE(durations.ok());
  EXPECT_NEAR(sum(*durations), 2.0 * std::sqrt(300.0 / a), 1e-9);
  // Given end speeds: start at cruise, end at cruise: L / v.
  options.start_speed_mps = 50.0;
  options.end_speed_mps = 50.0;
  durations = allocateTimes(short_line, limits, options);
  ASSERT_TRUE(durations.ok());
  EXPECT_NEAR(sum(*durations), 300.0 / v, 1e-9);
}

TEST(TimeAllocation, SlowsForSharpTurnsAndSteepLegs) {
  VehicleLimits limits;
  limits.max_accel_mps2 = 10.0;
  limits.max_climb_mps = 5.0;
  TimeAllocationOptions options;  // 5 m/s^2 usable
  // 90 degree corner between 400 m legs: fillet radius 200 m / tan(45) = 200 m, v = sqrt(5 * 200).
  const std::vector<Eigen::Vector3d> corner{{0, 0, 100}, {400, 0, 100}, {400, 400, 100}};
  const auto speeds = waypointSpeedLimits(corner, limits, options);
  EXPECT_NEAR(speeds[1], std::sqrt(5.0 * 200.0), 1e-9);
  EXPECT_EQ(speeds.front(), 0.0);
  EXPECT_EQ(speeds.back(), 0.0);
  // A reversal has to stop.
  const std::vector<Eigen::Vector3d> reversal{{0, 0, 100}, {400, 0, 100}, {0, 0, 100.5}};
  EXPECT_NEAR(waypointSpeedLimits(reversal, limits, options)[1], 0.0, 1.0);
  // Climbing 300 m over 1000 m at <= 5 m/s vertical takes at least 60 s.
  const std::vector<Eigen::Vector3d> climb{{0, 0, 100}, {954, 0, 400}};
  auto durations = allocateTimes(climb, limits, options);
  ASSERT_TRUE(durations.ok());
  EXPECT_GE(sum(*durations), 300.0 / 5.0);
}

TEST(TimeAllocation, TrapezoidalTrajectoriesRespectLimitsWithoutRepair) {
  VehicleLimits limits;  // 50 m/s V_ref, 60 max, 10 m/s^2, 15 m/s climb and descent
  TrajectoryOptions options;
  options.repair = false;
  options.waypoint_spacing_m = 100.0;
  // The smooth spline peaks at about 3x a trapezoid's constant acceleration; with 0.3 of the
  // limit the allocation alone keeps the vehicle within it (the default 0.5 leaves the few
  // segments that peak over to the repair pass, for a shorter flight).
  options.time_allocation.accel_fraction = 0.3;
  int constant_speed_violations = 0;
  for (unsigned seed = 1; seed <= 20; ++seed) {
    const auto w = testing::randomWalk(seed, 12);
    auto built = buildTrajectory(w, limits, options);
    ASSERT_TRUE(built.ok()) << built.error().describe();
    const FeasibilityReport& check = built->report.final_check;
    EXPECT_TRUE(check.ok()) << "seed " << seed << ": " << (check.ok() ? "" : built->report.failure_reason);
    EXPECT_LE(check.max_speed_mps, limits.max_speed_mps);
    EXPECT_LE(check.max_accel_mps2, limits.max_accel_mps2);
    EXPECT_LE(check.max_climb_mps, limits.max_climb_mps);
    EXPECT_LE(check.max_descent_mps, limits.max_descent_mps);
    // The paper's constant-speed allocation, rest to rest, on the same path: the start and end
    // (and the turns) ask for more acceleration than the vehicle has, which is why the option exists.
    TrajectoryOptions paper = options;
    paper.time_allocation.method = TimeAllocationMethod::kConstantSpeed;
    auto eq3 = buildTrajectory(w, limits, paper);
    ASSERT_TRUE(eq3.ok());
    if (!eq3->report.final_check.ok()) ++constant_speed_violations;
  }
  EXPECT_EQ(constant_speed_violations, 20);
}

TEST(TimeAllocation, ExtraWaypointsAtTheSpacing) {
  const std::vector<Eigen::Vector3d> w{{0, 0, 0}, {1000, 0, 0}, {1000, 250, 0}, {1000, 250.5, 0}};
  const auto dense = densifyWaypoints(w, 100.0);
  ASSERT_EQ(dense.original_indices.size(), w.size());
  for (std::size_t i = 0; i < w.size(); ++i) EXPECT_EQ(dense.points[dense.original_indices[i]], w[i]);
  EXPECT_EQ(dense.points.size(), 1u + 10u + 3u + 1u);
  for (std::size_t i = 1; i < dense.points.size(); ++i) {
    EXPECT_LE((dense.points[i] - dense.points[i - 1]).norm(), 100.0 + 1e-9);
  }
  EXPECT_EQ(densifyWaypoints(w, 0.0).points.size(), w.size());
}

TEST(TimeAllocation, BadInputNamesTheField) {
  VehicleLimits limits;
  const std::vector<Eigen::Vector3d> ok{{0, 0, 0}, {100, 0, 0}};
  limits.v_ref_mps = 0.0;
  auto r = allocateTimes(ok, limits);
  ASSERT_FALSE(r.ok());
  EXPECT_EQ(r.error().field, "limits.v_ref_mps");
  limits.v_ref_mps = -3.0;
  EXPECT_EQ(allocateTimes(ok, limits).error().field, "limits.v_ref_mps");
  limits = VehicleLimits{};
  limits.v_ref_mps = 70.0;  // above max speed 60
  EXPECT_EQ(allocateTimes(ok, limits).error().field, "limits.v_ref_mps");
  limits = VehicleLimits{};
  limits.max_accel_mps2 = std::nan("");
  EXPECT_EQ(allocateTimes(ok, limits).error().field, "limits.max_accel_mps2");
  limits = VehicleLimits{};
  EXPECT_EQ(allocateTimes({{0, 0, 0}}, limits).error().field, "waypoints");
  EXPECT_EQ(allocateTimes({{0, 0, 0}, {0, 0, 0}}, limits).error().field, "waypoints[1]");
  EXPECT_EQ(allocateTimes({{0, 0, 0}, {5, std::nan(""), 0}}, limits).error().field, "waypoints[1]");
  TimeAllocationOptions options;
  options.accel_fraction = 0.0;
  EXPECT_EQ(allocateTimes(ok, limits, options).error().field, "time_allocation.accel_fraction");
}

}  // namespace
}  // namespace skyroute
