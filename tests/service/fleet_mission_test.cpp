// Fleet missions in 3D: GMTPA on the flight band, trajectories through the
// trajectory stage, the minimum separation checked over continuous time and repaired by delays.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <random>
#include <set>

#include "service/engine.hpp"
#include "service/fleet_mission.hpp"
#include "terrain/terrain_world.hpp"
#include "tests/service/default_world_fixture.hpp"
#include "tests/service/recording_sink.hpp"

namespace skyroute {
namespace {

constexpr std::int64_t kStartNs = 1'800'000'000'000'000'000LL;

class FleetMissionTest : public testing::DefaultWorldTest {
 protected:
  // Three vehicles at three corners, nine tasks spread over the map (ENU and WGS84 mixed).
  FleetRequestData threeByNine() const {
    FleetRequestData r;
    r.request_id = "fleet-1";
    r.vehicle_ids = {"uav-a", "uav-b", "uav-c"};
    r.begins = {geo(-4000, -4000, 100), enu(4000, -4000, 100), geo(-4000, 4000, 100)};
    r.ends = r.begins;
    r.tasks = {enu(-2500, -1500, 150), enu(-1000, -3000, 150), geo(1500, -2500, 150),
               enu(3000, -1000, 150),  enu(2500, 1500, 150),   geo(-3000, 1000, 150),
               enu(-1500, 3000, 150),  enu(0, 0, 150),         enu(1500, 3500, 150)};
    return r;
  }

  // The smallest distance between vehicles a and b, sampled every dt_s over the whole mission.
  static double minDistance(const FleetPlanOutput& out, std::size_t a, std::size_t b, double dt_s) {
    double closest = std::numeric_limits<double>::infinity();
    for (double t = 0.0; t <= out.status.makespan_s + dt_s; t += dt_s) {
      closest = std::min(closest, (out.positionAt(a, t) - out.positionAt(b, t)).norm());
    }
    return closest;
  }
};

TEST_F(FleetMissionTest, ThreeVehiclesNineTasksEveryTaskOnceClearOfTerrainAndSeparated) {
  const FleetRequestData r = threeByNine();
  FleetMissionOptions options;
  options.min_separation_m = 150.0;
  const FleetPlanOutput out = planFleetMission(r, *world_, options, kStartNs);
  ASSERT_TRUE(out.ok()) << out.status.message;
  EXPECT_EQ(out.status.state, PlanState::kSucceeded);
  EXPECT_EQ(out.status.request_id, "fleet-1");
  ASSERT_EQ(out.trajectories.size(), 3u);
  ASSERT_EQ(out.status.allocation.size(), 3u);
  EXPECT_GT(out.status.makespan_steps, 0);
  EXPECT_LE(out.cell_size_m * 128, heightfield_->boundsEn().sizes().maxCoeff() * 1.01);

  // Every task exactly once, by one vehicle, and that vehicle's trajectory passes over it.
  std::multiset<std::uint32_t> done;
  for (std::size_t i = 0; i < 3; ++i) {
    const FleetVehicleAllocationData& a = out.status.allocation[i];
    const TrajectoryData& t = out.trajectories[i];
    EXPECT_EQ(a.vehicle_id, r.vehicle_ids[i]);
    EXPECT_EQ(t.vehicle_id, r.vehicle_ids[i]);
    EXPECT_EQ(t.request_id, "fleet-1");
    // Visiting order: 0 = begin, j + 1 = tasks[j], 10 = end.
    ASSERT_EQ(t.visiting_order.size(), a.tasks.size() + 2);
    EXPECT_EQ(t.visiting_order.front(), 0u);
    EXPECT_EQ(t.visiting_order.back(), 10u);
    EXPECT_EQ(t.legs.size(), a.tasks.size() + 1);
    for (std::size_t k = 0; k < a.tasks.size(); ++k) {
      const std::uint32_t j = a.tasks[k];
      done.insert(j);
      EXPECT_EQ(t.visiting_order[k + 1], j + 1);
      double closest_m = std::numeric_limits<double>::infinity();
      for (double s = 0.0; s <= out.flown[i].duration_s(); s += 0.05) {
        const Eigen::Vector3d p = out.flown[i].evaluate(s, Derivative::kPosition);
        closest_m = std::min(closest_m, (p.head<2>() - out.tasks_m[j].head<2>()).norm());
      }
      EXPECT_LT(closest_m, 2.0) << "vehicle " << i << " task " << j;
    }
    // Starts and ends at its begin / end points.
    EXPECT_LT((out.flown[i].evaluate(0.0, Derivative::kPosition) - out.begins_m[i]).norm(), 1e-3);
    EXPECT_LT((out.flown[i].evaluate(out.flown[i].duration_s(), Derivative::kPosition) - out.ends_m[i]).norm(), 1e-3);
    // Published samples are time-stamped from the start plus the delay.
    ASSERT_FALSE(t.samples.empty());
    EXPECT_EQ(t.samples.front().utc_ns, kStartNs + static_cast<std::int64_t>(std::llround(out.delays_s[i] * 1e9)));
  }
  EXPECT_EQ(done, (std::multiset<std::uint32_t>{0, 1, 2, 3, 4, 5, 6, 7, 8}));

  // Terrain: an independent look-up in the heightfield along every trajectory.
  for (std::size_t i = 0; i < 3; ++i) {
    double lowest_agl_m = std::numeric_limits<double>::infinity();
    for (double s = 0.0; s <= out.flown[i].duration_s(); s += 0.05) {
      const Eigen::Vector3d p = out.flown[i].evaluate(s, Derivative::kPosition);
      lowest_agl_m = std::min(lowest_agl_m, p.z() - heightfield_->heightAt(p.x(), p.y()));
    }
    EXPECT_GE(lowest_agl_m, r.limits.min_clearance_agl_m - 0.5) << "vehicle " << i;
  }

  // Separation at every 0.05 s between every pair, with the delays the service chose.
  for (std::size_t a = 0; a < 3; ++a) {
    for (std::size_t b = a + 1; b < 3; ++b) EXPECT_GE(minDistance(out, a, b, 0.05), 150.0) << a << "-" << b;
  }
  EXPECT_GE(out.status.achieved_separation_m, 150.0);
  EXPECT_DOUBLE_EQ(out.status.min_separation_m, 150.0);
  // Flown at about the cruise speed: no trajectory slowed down far beyond the grid plan's length.
  EXPECT_LT(out.status.makespan_s, 2.0 * out.status.makespan_steps * out.cell_size_m / r.limits.v_ref_mps + 600.0);
  std::printf("fleet 3x9: grid cell %.0f m, cruise %.0f m, makespan %d steps / %.1f s, achieved separation %.0f m, "
              "repairs %u, delays %.1f %.1f %.1f s, planning %.3f s\n",
              out.cell_size_m, out.cruise_altitude_m, out.status.makespan_steps, out.status.makespan_s,
              out.status.achieved_separation_m, out.status.separation_repairs, out.delays_s[0], out.delays_s[1],
              out.delays_s[2], out.status.planning_time_s);
}

// Two vehicles from opposite sides fly to tasks 400 m apart and arrive at the same time: the grid
// plan keeps them in different cells, but 400 m is below the 600 m asked for, so the later vehicle
// must be held back.
TEST_F(FleetMissionTest, ConvergingVehiclesAreRepairedByADelay) {
  FleetRequestData r;
  r.request_id = "converge";
  r.vehicle_ids = {"west", "east"};
  r.begins = {enu(-1500, -3500, 100), enu(1500, -3500, 100)};
  r.ends = r.begins;
  r.tasks = {enu(-200, 3000, 150), enu(200, 3000, 150)};
  FleetMissionOptions options;
  options.min_separation_m = 600.0;
  const FleetPlanOutput out = planFleetMission(r, *world_, options, kStartNs);
  ASSERT_TRUE(out.ok()) << out.status.message;
  ASSERT_EQ(out.status.allocation.size(), 2u);
  EXPECT_EQ(out.status.allocation[0].tasks, std::vector<std::uint32_t>{0});
  EXPECT_EQ(out.status.allocation[1].tasks, std::vector<std::uint32_t>{1});

  // Without the delays the two would come closer than asked.
  FleetPlanOutput undelayed = out;
  undelayed.delays_s.assign(2, 0.0);
  EXPECT_LT(minDistance(undelayed, 0, 1, 0.05), 600.0);

  EXPECT_DOUBLE_EQ(out.delays_s[0], 0.0);
  EXPECT_GT(out.delays_s[1], 0.0);
  EXPECT_EQ(out.status.separation_repairs, 1u);
  EXPECT_DOUBLE_EQ(out.status.allocation[1].delay_s, out.delays_s[1]);
  EXPECT_GE(minDistance(out, 0, 1, 0.05), 600.0);
  EXPECT_GE(out.status.achieved_separation_m, 600.0);
  EXPECT_NEAR(out.status.makespan_s, out.delays_s[1] + out.flown[1].duration_s(), 1e-9);
  EXPECT_EQ(out.trajectories[1].samples.front().utc_ns,
            kStartNs + static_cast<std::int64_t>(std::llround(out.delays_s[1] * 1e9)));
  std::printf("converging pair: delay %.1f s, undelayed closest %.0f m, achieved %.0f m, planning %.3f s\n",
              out.delays_s[1], minDistance(undelayed, 0, 1, 0.05), out.status.achieved_separation_m,
              out.status.planning_time_s);
}

TEST_F(FleetMissionTest, BadInputNamesTheField) {
  auto expectError = [&](FleetRequestData r, PlanErrorCode code, const std::string& field) {
    const FleetPlanOutput out = planFleetMission(r, *world_, FleetMissionOptions{}, kStartNs);
    EXPECT_EQ(out.status.state, PlanState::kFailed) << field;
    EXPECT_EQ(out.status.error_code, code) << field << ": " << out.status.message;
    EXPECT_EQ(out.status.field, field) << out.status.message;
    EXPECT_NE(out.status.message.find(field), std::string::npos) << out.status.message;
    EXPECT_TRUE(out.trajectories.empty());
  };
  FleetRequestData r = threeByNine();
  r.tasks[3] = enu(3000, -1000, -50);  // under the ground
  expectError(r, PlanErrorCode::kUnderGround, "tasks[3]");
  r = threeByNine();
  r.tasks[0] = enu(30000, 0, 100);
  r.tasks[0].enu_m.z() = 800.0;
  expectError(r, PlanErrorCode::kOutsideMap, "tasks[0]");
  r = threeByNine();
  r.vehicle_ids[2] = "uav-a";
  expectError(r, PlanErrorCode::kInvalidArgument, "vehicle_ids[2]");
  r = threeByNine();
  r.begins.pop_back();
  expectError(r, PlanErrorCode::kInvalidArgument, "begins");
  r = threeByNine();
  r.begins[1] = enu(-3990, -4000, 100);  // on top of begins[0]
  r.ends = r.begins;
  expectError(r, PlanErrorCode::kInvalidArgument, "begins[1]");
  r = threeByNine();
  r.tasks.clear();
  expectError(r, PlanErrorCode::kEmptyMission, "tasks");
  r = threeByNine();
  r.tasks[5].geo.lat_deg = std::nan("");
  expectError(r, PlanErrorCode::kInvalidArgument, "tasks[5].lat_deg");
  r = threeByNine();
  r.planner = "ga-please";
  expectError(r, PlanErrorCode::kUnknownPlanner, "planner");
  r = threeByNine();
  r.limits.v_ref_mps = -1.0;
  expectError(r, PlanErrorCode::kLimitsOutOfRange, "limits.v_ref_mps");
  r = threeByNine();
  r.limits.model = VehicleModel::kFixedWing;  // a fleet's plans wait in place: no fixed wings
  expectError(r, PlanErrorCode::kInvalidArgument, "limits.model");
}

// More vehicles than the tasks need: the idle one stays at its begin point (no climb to the cruise
// altitude and back) and still gets a trajectory, and nobody comes closer than asked.
TEST_F(FleetMissionTest, AVehicleWithoutTasksHoldsAtItsBegin) {
  FleetRequestData r;
  r.request_id = "idle";
  r.vehicle_ids = {"near", "far"};
  r.begins = {enu(-3000, -3000, 100), enu(4000, 4000, 100)};
  r.ends = r.begins;
  r.tasks = {enu(-2500, -2000, 150)};
  const FleetPlanOutput out = planFleetMission(r, *world_, FleetMissionOptions{}, kStartNs);
  ASSERT_TRUE(out.ok()) << out.status.message;
  EXPECT_EQ(out.status.allocation[0].tasks, std::vector<std::uint32_t>{0});
  EXPECT_TRUE(out.status.allocation[1].tasks.empty());
  ASSERT_EQ(out.trajectories.size(), 2u);
  EXPECT_EQ(out.trajectories[1].visiting_order, (std::vector<std::uint32_t>{0, 2}));
  ASSERT_FALSE(out.trajectories[1].samples.empty());
  for (const TrajectorySampleData& s : out.trajectories[1].samples) {
    EXPECT_LT((s.position_enu_m - out.begins_m[1]).norm(), 1e-6);
  }
  EXPECT_GE(minDistance(out, 0, 1, 0.05), out.status.min_separation_m);
  EXPECT_DOUBLE_EQ(out.status.min_separation_m, out.cell_size_m);  // the default: one grid cell
}

// Ends away from the begins: each vehicle comes back over its depot (GMTPA's eq. 7), flies on to
// over its end at the cruise altitude and descends there.
TEST_F(FleetMissionTest, EndsAwayFromTheBeginsAreReachedAfterTheDepot) {
  FleetRequestData r;
  r.request_id = "ends";
  r.vehicle_ids = {"a", "b"};
  r.begins = {enu(-3000, -3000, 100), enu(3000, -3000, 100)};
  r.ends = {enu(-3000, 0, 120), enu(3000, 0, 120)};
  r.tasks = {enu(-2000, 2000, 150), enu(2000, 2000, 150), enu(0, -1000, 150)};
  const FleetPlanOutput out = planFleetMission(r, *world_, FleetMissionOptions{}, kStartNs);
  ASSERT_TRUE(out.ok()) << out.status.message;
  for (std::size_t i = 0; i < 2; ++i) {
    EXPECT_LT((out.flown[i].evaluate(out.flown[i].duration_s(), Derivative::kPosition) - out.ends_m[i]).norm(), 1e-3);
    EXPECT_EQ(out.trajectories[i].visiting_order.back(), 4u);
    EXPECT_LT((out.trajectories[i].samples.back().position_enu_m - out.ends_m[i]).norm(), 1e-3);
  }
  EXPECT_GE(minDistance(out, 0, 1, 0.05), out.status.min_separation_m);
}

// Seeded random tasks (the instance where a vertical descent's right-angle turn once made the
// trajectory stage stretch a vehicle's trajectory a hundredfold): every vehicle flies at about
// the cruise speed, every task is done once and the separation holds.
TEST_F(FleetMissionTest, RandomTasksAreFlownAtCruiseSpeedAndSeparated) {
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> u(-4200, 4200);
  FleetRequestData r;
  r.request_id = "random";
  for (int i = 0; i < 3; ++i) {
    r.vehicle_ids.push_back("v" + std::to_string(i));
    r.begins.push_back(enu(-4200 + 4200.0 * i, -4300, 100));
  }
  r.ends = r.begins;
  for (int j = 0; j < 9; ++j) {
    const double e = u(rng);
    const double n = u(rng);
    r.tasks.push_back(enu(e, n, 150));
  }
  const FleetPlanOutput out = planFleetMission(r, *world_, FleetMissionOptions{}, kStartNs);
  ASSERT_TRUE(out.ok()) << out.status.message;
  std::multiset<std::uint32_t> done;
  for (const auto& a : out.status.allocation) done.insert(a.tasks.begin(), a.tasks.end());
  EXPECT_EQ(done, (std::multiset<std::uint32_t>{0, 1, 2, 3, 4, 5, 6, 7, 8}));
  for (std::size_t i = 0; i < 3; ++i) {
    const int steps = out.status.makespan_steps;
    EXPECT_LT(out.flown[i].duration_s(), 2.0 * steps * out.cell_size_m / r.limits.v_ref_mps + 600.0) << "vehicle " << i;
  }
  for (std::size_t a = 0; a < 3; ++a) {
    for (std::size_t b = a + 1; b < 3; ++b) EXPECT_GE(minDistance(out, a, b, 0.05), out.status.min_separation_m);
  }
}

// The continuous separation check on hand-made trajectories (no terrain needed): straight runs at
// 100 m/s, sampled every 0.5 s.
Trajectory straightRun(const Eigen::Vector3d& from, const Eigen::Vector3d& to, double duration_s) {
  Segment segment;
  segment.duration_s = duration_s;
  for (int axis = 0; axis < 3; ++axis) {
    Polynomial7::Coefficients c{};
    c[0] = from[axis];
    c[1] = to[axis] - from[axis];  // in tau = t / duration
    segment.axes[static_cast<std::size_t>(axis)] = Polynomial7(c);
  }
  return Trajectory({segment});
}

// Two vehicles crossing the origin at right angles, both there at t = 1.25 s; 10 m asked for,
// sampled every 0.5 s.
std::vector<Trajectory> crossingPair() {
  return {straightRun({-125, 0, 100}, {125, 0, 100}, 2.5), straightRun({0, -125, 100}, {0, 125, 100}, 2.5)};
}
SeparationCheckOptions tenMetresEveryHalfSecond() {
  SeparationCheckOptions o;
  o.separation_m = 10.0;
  o.sample_dt_s = 0.5;
  return o;
}

double closestDense(const std::vector<Trajectory>& flown, const std::vector<double>& delays_s, double until_s) {
  double closest = std::numeric_limits<double>::infinity();
  for (double t = 0.0; t <= until_s; t += 1e-4) {
    const Eigen::Vector3d a = flown[0].evaluate(t - delays_s[0], Derivative::kPosition);
    const Eigen::Vector3d b = flown[1].evaluate(t - delays_s[1], Derivative::kPosition);
    closest = std::min(closest, (a - b).norm());
  }
  return closest;
}

TEST(FleetSeparation, CrossingBetweenSamplesIsCaughtAndRepaired) {
  // They meet between the samples at 1.0 and 1.5 s, where they are 35 m apart.
  const std::vector<Trajectory> flown = crossingPair();
  const SeparationCheckOptions o = tenMetresEveryHalfSecond();
  double sampled = std::numeric_limits<double>::infinity();
  for (int k = 0; k * o.sample_dt_s <= 2.5; ++k) {
    const double t = k * o.sample_dt_s;
    sampled = std::min(sampled, (flown[0].evaluate(t, Derivative::kPosition) - flown[1].evaluate(t, Derivative::kPosition)).norm());
  }
  EXPECT_GT(sampled, o.separation_m);  // a check on samples alone would pass

  EXPECT_NEAR(speedBoundMps(flown[0], 0.0, 2.5), 100.0, 1e-9);
  EXPECT_EQ(speedBoundMps(flown[0], 3.0, 4.0), 0.0);  // holding after its end

  const SeparationVerdict together = checkFleetSeparation(flown, {0.0, 0.0}, o);
  EXPECT_FALSE(together.clear);
  EXPECT_EQ(together.vehicle_a, 0u);
  EXPECT_EQ(together.vehicle_b, 1u);
  EXPECT_NEAR(together.time_s, 1.25, 0.25);
  EXPECT_LT(together.closest_m, o.separation_m);

  const SeparationRepair repair = repairFleetSeparation(flown, o, 0.5, 60.0);
  ASSERT_FALSE(repair.failed_vehicle.has_value());
  ASSERT_FALSE(repair.stopped);
  ASSERT_EQ(repair.delays_s.size(), 2u);
  EXPECT_EQ(repair.delays_s[0], 0.0);
  EXPECT_GT(repair.delays_s[1], 0.0);
  EXPECT_EQ(repair.repaired, 1u);
  EXPECT_TRUE(checkFleetSeparation(flown, repair.delays_s, o).clear);
  EXPECT_GE(closestDense(flown, repair.delays_s, 2.5 + repair.delays_s[1] + 0.5), o.separation_m);
  EXPECT_GE(repair.closest_m, o.separation_m);
}

TEST(FleetSeparation, ANearMissBetweenSamplesIsProvenClear) {
  // The second vehicle starts 0.17 s later (not a whole sample): the closest approach,
  // 100 * 0.17 / sqrt(2) = 12.0 m, falls between samples and exceeds the 10 m asked for. The
  // Lipschitz bound alone cannot tell (it allows 200 m/s of closing), so the check refines.
  const std::vector<Trajectory> flown = crossingPair();
  SeparationCheckOptions o = tenMetresEveryHalfSecond();
  const std::vector<double> delays{0.0, 0.17};
  const double truth = closestDense(flown, delays, 3.5);
  ASSERT_NEAR(truth, 100.0 * 0.17 / std::sqrt(2.0), 0.05);
  const SeparationVerdict verdict = checkFleetSeparation(flown, delays, o);
  EXPECT_TRUE(verdict.clear);
  EXPECT_GT(verdict.refinements, 0u);
  EXPECT_GE(verdict.closest_m, truth - 1e-9);
  EXPECT_LT(verdict.closest_m, truth + 1.0);  // the refinement got near the true minimum

  // Asking for 13 m, just above the true minimum, fails.
  o.separation_m = 13.0;
  EXPECT_FALSE(checkFleetSeparation(flown, delays, o).clear);
}

TEST(FleetSeparation, SpeedBoundCoversACurvedSegment) {
  // A degree-7 segment with turning velocity: the bound is at least every sampled speed and not
  // wildly above the largest.
  Segment segment;
  segment.duration_s = 4.0;
  segment.axes[0] = Polynomial7({0.0, 10.0, 40.0, -30.0, 5.0, 2.0, -1.0, 0.5});
  segment.axes[1] = Polynomial7({5.0, -20.0, 15.0, 10.0, -8.0, 0.0, 3.0, -1.0});
  segment.axes[2] = Polynomial7({100.0, 0.0, 6.0, -4.0, 0.0, 0.0, 0.0, 0.0});
  const Trajectory t({segment});
  double fastest = 0.0;
  for (double s = 0.0; s <= 4.0; s += 1e-3) fastest = std::max(fastest, t.evaluate(s, Derivative::kVelocity).norm());
  const double bound = speedBoundMps(t, 0.0, 4.0);
  EXPECT_GE(bound, fastest);
  EXPECT_LT(bound, 3.0 * fastest);
}

// The engine plans a fleet on its planning path: accepted, planning, one trajectory per vehicle,
// then the fleet status with the allocation; a bad request is refused at once naming the field.
using testing::RecordingSink;

TEST_F(FleetMissionTest, EngineAnswersAFleetWithTrajectoriesAndAFleetStatus) {
  RecordingSink sink;
  auto engine = Engine::create(world_, EngineOptions{}, sink, [] { return kStartNs; });
  ASSERT_TRUE(engine.ok()) << engine.error().describe();
  FleetRequestData bad = threeByNine();
  bad.vehicle_ids[1] = "uav-a";
  const auto refused = (*engine)->submitFleet(bad);
  ASSERT_TRUE(refused.has_value());
  EXPECT_EQ(refused->field, "vehicle_ids[1]");
  ASSERT_EQ(sink.fleet.size(), 1u);
  EXPECT_EQ(sink.fleet[0].state, PlanState::kFailed);
  EXPECT_EQ(sink.fleet[0].field, "vehicle_ids[1]");
  EXPECT_EQ((*engine)->queueLength(), 0u);

  ASSERT_FALSE((*engine)->submitFleet(threeByNine()).has_value());
  EXPECT_EQ(sink.fleet.back().state, PlanState::kAccepted);
  EXPECT_EQ((*engine)->queueLength(), 1u);
  ASSERT_TRUE((*engine)->planNext());
  ASSERT_EQ(sink.fleet.size(), 4u);
  EXPECT_EQ(sink.fleet[2].state, PlanState::kPlanning);
  const FleetStatusData& done = sink.fleet[3];
  ASSERT_EQ(done.state, PlanState::kSucceeded) << done.message;
  EXPECT_EQ(done.allocation.size(), 3u);
  EXPECT_GT(done.planning_time_s, 0.0);
  ASSERT_EQ(sink.trajectories.size(), 3u);
  for (std::size_t i = 0; i < 3; ++i) {
    EXPECT_EQ(sink.trajectories[i].vehicle_id, threeByNine().vehicle_ids[i]);
    EXPECT_EQ(sink.trajectories[i].samples.front().utc_ns,
              kStartNs + static_cast<std::int64_t>(std::llround(done.allocation[i].delay_s * 1e9)));
  }
  EXPECT_TRUE(sink.statuses.empty());  // fleets answer on their own status topic only
  EXPECT_EQ((*engine)->activeMissions(), 0u);  // fleet vehicles are not replanned
}

}  // namespace
}  // namespace skyroute
