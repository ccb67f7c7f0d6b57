// A fixed wing's trajectory never dips under its minimum airspeed. Where it used to: the repair
// stretched a turn in time to ease its load factor (1.3 against 1.22) by 23-38%, slower than
// 25 m/s / 19.5 m/s allows. Now the stretch goes no further than the minimum airspeed allows,
// the turn is widened beyond that, and what still cannot fly says where and why. Checked on
// seeded random paths (the kind RRT* + LOSPO hands over, with legs a fixed wing can turn
// between) from the positions alone.
#include <cmath>
#include <cstdio>
#include <limits>
#include <string>

#include <gtest/gtest.h>

#include "tests/trajectory/finite_differences.hpp"
#include "tests/trajectory/fixed_wing_vehicle.hpp"
#include "tests/trajectory/random_paths.hpp"
#include "trajectory/trajectory_builder.hpp"

namespace skyroute {
namespace {

VehicleLimits fixedWing() { return testing::fixedWingVehicle(); }

// The slowest speed measured from the positions alone.
double slowestMps(const Trajectory& t) {
  double slowest = std::numeric_limits<double>::infinity();
  testing::forEachFiniteDifference(t, [&](double, const Eigen::Vector3d& v, const Eigen::Vector3d&) {
    slowest = std::min(slowest, v.norm());
  });
  return slowest;
}

TEST(FixedWingAirspeed, RandomPathsNeverFlyUnderTheMinimumAirspeedOrSayWhereAndWhy) {
  const VehicleLimits limits = fixedWing();
  int flown = 0, load_factor_repaired = 0, refused = 0;
  for (unsigned seed = 1; seed <= 200; ++seed) {
    const std::vector<Eigen::Vector3d> path = testing::randomWalk(seed, 8, 150.0, 800.0, 120.0);
    auto built = buildTrajectory(path, limits);
    ASSERT_TRUE(built.ok()) << seed << ": " << built.error().describe();
    const TrajectoryBuildReport& report = built->report;
    if (report.status == TrajectoryStatus::kInfeasible) {
      ++refused;
      ASSERT_TRUE(report.failure_violation.has_value()) << seed;
      // Never traded for a stall: the violation named is the one the repairs could not fix.
      EXPECT_NE(report.failure_violation->kind, ViolationKind::kBelowMinAirspeed) << seed << ": " << report.failure_reason;
      if (report.failure_violation->kind == ViolationKind::kLoadFactor) {
        EXPECT_TRUE(report.failure_reason.find("minimum airspeed") != std::string::npos ||
                    report.failure_reason.find("rounded corner") != std::string::npos)
            << seed << ": " << report.failure_reason;
      }
      continue;
    }
    ++flown;
    for (const std::string& line : report.repairs)
      if (line.find("load_factor") != std::string::npos) {
        ++load_factor_repaired;
        break;
      }
    EXPECT_GE(slowestMps(built->trajectory), limits.minAirspeedMps() * (1.0 - 1e-3)) << seed;
  }
  std::printf("%d of 200 flown (%d with a load factor repaired), %d refused naming another violation\n", flown,
              load_factor_repaired, refused);
  EXPECT_GT(load_factor_repaired, 5);  // the repair this is about does happen
  EXPECT_GT(flown, 120);
}

// The paths whose trajectories used to fly under the minimum airspeed (17.7-19.3 m/s, after a
// 23-38% stretch for the load factor in a turn) now fly, at or above it throughout.
TEST(FixedWingAirspeed, SeedsThatDippedUnderTheMinimumAirspeedNowFly) {
  const VehicleLimits limits = fixedWing();
  for (unsigned seed : {18u, 81u, 126u, 160u, 184u}) {
    auto built = buildTrajectory(testing::randomWalk(seed, 8, 150.0, 800.0, 120.0), limits);
    ASSERT_TRUE(built.ok());
    ASSERT_NE(built->report.status, TrajectoryStatus::kInfeasible) << seed << ": " << built->report.failure_reason;
    EXPECT_GE(slowestMps(built->trajectory), limits.minAirspeedMps() * (1.0 - 1e-3)) << seed;
    EXPECT_GE(built->report.final_check.min_speed_mps, limits.minAirspeedMps()) << seed;
  }
}

}  // namespace
}  // namespace skyroute
