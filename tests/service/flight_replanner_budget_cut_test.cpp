// The seed-003 moving-obstacle scenario (as tests/service/flight_replanner_test.cpp flies it) with
// every replan cut short after its first attempt, the way the wall-clock budget cuts it on a
// loaded machine (ReplanOptions::replan_budget_attempts makes the cut reproducible). The vehicle
// then holds, and cycle after cycle plans from the hold. Where it waits, and the plan it finally
// leaves the hold with, must keep their room from the obstacles, not slip past one by a hair.
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <limits>
#include <string>

#include <gtest/gtest.h>

#include "service/flight_replanner.hpp"
#include "service/moving_obstacle_scenario.hpp"
#include "terrain/terrain_world.hpp"
#include "tests/test_data.hpp"

namespace skyroute {
namespace {

// One flight with the cut; the room it kept from the obstacles (beyond the vehicle's radius).
void flyWithTheCut(std::uint64_t seed) {
  SCOPED_TRACE("seed " + std::to_string(seed));
  SKYROUTE_REQUIRE_SHARED(dem, "dem/N44W072.hgt");
  const CollisionWorldOptions world_options = seed003ScenarioWorldOptions();
  auto world = loadTerrainWorld(dem, world_options);
  ASSERT_TRUE(world.ok()) << world.error().describe();
  const MovingObstacleScenario scenario = seed003Table1Scenario(*world->heightfield);
  for (const Obstacle& o : scenario.obstacles) world->collision->upsertObstacle(o);

  ReplanOptions options;
  options.route.seed = seed;
  options.route.leg_budget_ms = 0.0;
  options.route.leg_max_iterations = 3000;
  options.route.corridor_margin_m = 4000.0;
  options.replan_budget_ms = 0.0;
  options.replan_budget_attempts = 1;  // the cut: one attempt per replan
  options.replan_leg_max_iterations = 500;
  auto replanner = FlightReplanner::start(world->collision, {scenario.start_m, scenario.goal_m},
                                          seed003ScenarioLimits(), options, 0.0);
  ASSERT_TRUE(replanner.ok()) << replanner.error().describe();
  FlightReplanner& r = **replanner;

  int holds = 0, failures = 0, replans_from_hold = 0;
  double min_separation_m = std::numeric_limits<double>::infinity();
  double t = 0.0;
  const double time_limit_s = 1200.0;
  for (; t < time_limit_s && !r.finished(t); t += options.period_s) {
    const bool was_holding = r.holding();
    const ReplanStep step = r.step(t);
    holds += step.holding ? 1 : 0;
    failures += step.failure ? 1 : 0;
    replans_from_hold += (step.replanned && was_holding) ? 1 : 0;
    // Independently, every 10 ms: never inside an obstacle grown by the vehicle radius, and the
    // room beyond that radius.
    for (double s = t; s < t + options.period_s; s += 0.01) {
      const Eigen::Vector3d p = r.stateAt(s).position_m;
      for (const Obstacle& o : scenario.obstacles) {
        ASSERT_FALSE(o.contains(p, s, world_options.vehicle_radius_m)) << "collision with " << o.id << " at t=" << s;
      }
      min_separation_m = std::min(min_separation_m, world->collision->obstacleDistance(p, s));
    }
  }
  ASSERT_TRUE(r.finished(t)) << "did not reach the goal within " << time_limit_s << " s";
  EXPECT_LT((r.stateAt(r.arrivalWorldS()).position_m - scenario.goal_m).norm(), 1e-3);
  // The cut must have mattered: the vehicle held and planned on from its hold.
  EXPECT_GT(holds, 0);
  EXPECT_GT(failures, 0);
  EXPECT_GT(replans_from_hold, 0);
  EXPECT_GE(min_separation_m, 20.0);
  std::printf("seed %llu: arrival %.1f s, %d holds, %d failed replans, %d replans from a hold, min separation %.1f m\n",
              static_cast<unsigned long long>(seed), r.arrivalWorldS(), holds, failures, replans_from_hold, min_separation_m);
}

// Seed 7 (the seed-003 test's): the first plan clear of the obstacles from the hold passed
// 0.4 m from one. Seed 3: the hold came to rest at the edge of an obstacle's track, and the
// obstacle came back along it 0.5 m from the waiting vehicle.
TEST(FlightReplannerBudgetCut, HoldAndThePlanLeavingItKeepTheirRoomFromTheObstacles) {
  for (std::uint64_t seed : {7u, 3u}) flyWithTheCut(seed);
}

}  // namespace
}  // namespace skyroute
