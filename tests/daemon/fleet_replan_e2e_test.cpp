// A flying fleet replanned over DDS, end to end: skyrouted as a separate process, the test the
// ground station. A 5-vehicle, 15-task fleet flies; three obstacle updates then cross the paths of
// three vehicles. The station must receive new revisions for the vehicles the obstacles meet, and
// only for them, and the trajectories in force must serve every task once, keep clear of the
// obstacles' actual motion and keep the separation: all judged from the published samples.
// Then the same over a climb: a column crossing a vehicle's climb over its begin right after the
// launch, which the vehicle must step aside from below the band.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <memory>
#include <set>

#include "service/dds/loopback.hpp"
#include "service/dds/wait_loop.hpp"
#include "service/world_model.hpp"
#include "tests/daemon/fleet_daemon_fixture.hpp"
#include "tests/service/fleet_flown.hpp"
#include "tests/terrain_data.hpp"

namespace skyroute {
namespace {

using testing::ChildProcess;
using testing::FleetFlown;
using testing::sampledAt;
using testing::Station;

constexpr int kDomain = 185;
constexpr int kClimbDomain = 186;
constexpr double kVehicleRadiusM = 5.0;  // the daemon's default
constexpr double kMarginM = 30.0;        // fleet.replan_margin_m's default

class FleetReplanE2E : public testing::FleetDaemonTest {
 protected:
  void SetUp() override { startDaemon(kDomain, {"--log-level", "debug"}, "skyrouted_fleet_replan", 20.0); }

  bool reached(const std::string& id, PlanState state) const {
    return std::any_of(fleet_log_.begin(), fleet_log_.end(),
                       [&](const FleetStatusData& s) { return s.request_id == id && s.state == state; });
  }
  // Sends the fleet request and waits (20 s) for its success and every vehicle's first plan.
  bool planFleet(const FleetRequestData& r) {
    if (!fleet_requests_->write(r).ok()) return false;
    auto firstPlans = [&] {
      std::size_t n = 0;
      for (const TrajectoryData& t : station_->trajectory_log) n += t.request_id == r.request_id ? 1 : 0;
      return n;
    };
    return station_->pumpUntil(
        [&] { return reached(r.request_id, PlanState::kSucceeded) && firstPlans() == r.vehicle_ids.size(); }, 20.0);
  }
  // Vehicles with a revision after the first plan, of request id.
  std::set<std::string> revised(const std::string& id) const {
    std::set<std::string> out;
    for (const TrajectoryData& t : station_->trajectory_log)
      if (t.request_id == id && t.revision > 0) out.insert(t.vehicle_id);
    return out;
  }
};

// The least distance between two of `vehicles` on the trajectories in force, every 0.1 s from
// from_s to to_s (m).
double closestPairM(const FleetFlown& flown, const std::vector<std::string>& vehicles, double from_s, double to_s) {
  double closest_m = std::numeric_limits<double>::infinity();
  for (double t = from_s; t <= to_s; t += 0.1) {
    for (std::size_t a = 0; a < vehicles.size(); ++a)
      for (std::size_t b = a + 1; b < vehicles.size(); ++b)
        closest_m = std::min(closest_m, (flown.positionAt(vehicles[a], t) - flown.positionAt(vehicles[b], t)).norm());
  }
  return closest_m;
}

TEST_F(FleetReplanE2E, CrossingObstaclesGetOnlyTheVehiclesTheyMeetNewRevisions) {
  FleetRequestData r;
  r.request_id = "fleet-replan-e2e";
  r.vehicle_ids = {"fr-a", "fr-b", "fr-c", "fr-d", "fr-e"};
  r.begins = {above(-4000, -4000, 100), above(4000, -4000, 100), above(-4000, 4000, 100), above(4000, 4000, 100),
              above(0, -4500, 100)};
  r.ends = r.begins;
  const double spots[15][2] = {{-2500, -1500}, {-1000, -3000}, {1500, -2500}, {3000, -1000}, {2500, 1500},
                               {-3000, 1000},  {-1500, 3000},  {0, 0},        {1500, 3500},  {-3500, -2500},
                               {2000, -500},   {-500, 1800},   {3500, 2800},  {-2000, 500},  {500, -1500}};
  for (const auto& s : spots) r.tasks.push_back(above(s[0], s[1], 150));
  ASSERT_TRUE(planFleet(r)) << daemon_.err();
  const FleetFlown planned(station_->trajectory_log, r.request_id);

  // Three columns (every altitude of the band), each aimed at where one vehicle will be 300, 450
  // and 600 s from now (cruising on the band), crossing its path from the side.
  const std::int64_t now_ns = utcNowNs();
  const double now_s = static_cast<double>(now_ns) * 1e-9;
  auto aimedAt = [&](std::uint64_t id, const std::string& vehicle, double in_s, const Eigen::Vector2d& velocity) {
    const Eigen::Vector3d meet = planned.positionAt(vehicle, now_s + in_s);
    const Eigen::Vector2d from = meet.head<2>() - velocity * in_s;
    ObstacleUpdateData u;
    u.obstacle.id = id;
    u.obstacle.shape = ObstacleShape::kCylinder;
    u.obstacle.size_m = Eigen::Vector3d(120.0, 120.0, 2500.0);
    u.obstacle.center_m = Eigen::Vector3d(from.x(), from.y(), 1000.0);
    u.constant_velocity_enu_mps = Eigen::Vector3d(velocity.x(), velocity.y(), 0.0);
    u.valid_from_utc_ns = now_ns;
    return u;
  };
  const std::vector<ObstacleUpdateData> updates = {aimedAt(101, "fr-a", 300.0, Eigen::Vector2d(0.0, 12.0)),
                                                   aimedAt(102, "fr-c", 450.0, Eigen::Vector2d(10.0, -6.0)),
                                                   aimedAt(103, "fr-d", 600.0, Eigen::Vector2d(-8.0, 0.0))};
  std::vector<Obstacle> obstacles;
  for (const ObstacleUpdateData& u : updates) obstacles.push_back(worldObstacle(u, 3600.0));
  // Which vehicles the obstacles meet (the daemon's margin round the vehicle's sphere), by the
  // test's own sampling of the first plans: surely within a slightly smaller room, surely not
  // beyond a slightly larger one.
  auto meeting = [&](double room_m) {
    std::set<std::string> out;
    for (const std::string& v : r.vehicle_ids) {
      for (double t = now_s; t <= planned.endOf(v); t += 0.25) {
        for (const Obstacle& o : obstacles)
          if (o.contains(planned.positionAt(v, t), t, room_m)) out.insert(v);
      }
    }
    return out;
  };
  const std::set<std::string> surely = meeting(kVehicleRadiusM + kMarginM - 5.0);
  const std::set<std::string> maybe = meeting(kVehicleRadiusM + kMarginM + 5.0);
  ASSERT_GE(surely.size(), 3u);
  ASSERT_LT(maybe.size(), r.vehicle_ids.size()) << "the scenario must leave a vehicle alone";
  for (const ObstacleUpdateData& u : updates) ASSERT_TRUE(station_->obstacles->write(u).ok());

  // New revisions for every vehicle met, and a replanned fleet status.
  ASSERT_TRUE(station_->pumpUntil(
      [&] {
        const std::set<std::string> got = revised(r.request_id);
        return reached(r.request_id, PlanState::kReplanned) &&
               std::includes(got.begin(), got.end(), surely.begin(), surely.end());
      },
      20.0))
      << daemon_.err();
  station_->pumpUntil([] { return false; }, 1.5);  // anything else that would come
  const std::set<std::string> got = revised(r.request_id);
  for (const std::string& v : got) EXPECT_TRUE(maybe.count(v) > 0) << v << " got a revision without meeting an obstacle";
  for (const TrajectoryData& t : station_->trajectory_log) {
    if (t.request_id == r.request_id && t.revision > 0) {
      EXPECT_EQ(t.plan_id, r.request_id + "-" + t.vehicle_id);
    }
  }
  const FleetStatusData& last = *std::find_if(fleet_log_.rbegin(), fleet_log_.rend(), [&](const FleetStatusData& s) {
    return s.request_id == r.request_id && s.state == PlanState::kReplanned;
  });
  EXPECT_TRUE(last.field.empty()) << last.message;
  ASSERT_EQ(last.allocation.size(), 5u);

  // The trajectories in force: every task once, clear of the obstacles, separated.
  const FleetFlown flown(station_->trajectory_log, r.request_id);
  for (std::uint32_t j = 0; j < r.tasks.size(); ++j) {
    const auto served = flown.servings(j);
    ASSERT_EQ(served.size(), 1u) << "task " << j;
    EXPECT_LT((flown.positionAt(served[0].first, served[0].second).head<2>() - r.tasks[j].enu_m.head<2>()).norm(), 3.0);
  }
  double last_end_s = now_s;
  for (const std::string& v : r.vehicle_ids) {
    last_end_s = std::max(last_end_s, flown.endOf(v));
    for (double t = std::max(now_s, flown.beginOf(v)); t <= flown.endOf(v); t += 0.05) {
      for (std::size_t k = 0; k < obstacles.size(); ++k)
        ASSERT_FALSE(obstacles[k].contains(flown.positionAt(v, t), t, kVehicleRadiusM)) << v << " in obstacle " << k;
    }
  }
  const double closest_m = closestPairM(flown, r.vehicle_ids, now_s, last_end_s);
  EXPECT_GE(closest_m, last.min_separation_m - 1.0);
  std::printf("fleet replan over DDS: met %zu (maybe %zu), revised %zu, replan %.3f s, closest pair %.0f m (min %.0f)\n",
              surely.size(), maybe.size(), got.size(), last.planning_time_s, closest_m, last.min_separation_m);
}

class FleetClimbE2E : public FleetReplanE2E {
 protected:
  void SetUp() override { startDaemon(kClimbDomain, {"--log-level", "debug"}, "skyrouted_fleet_climb", 20.0); }
};

TEST_F(FleetClimbE2E, AColumnCrossingAClimbIsSteppedAround) {
  FleetRequestData r;
  r.request_id = "fleet-climb-e2e";
  r.vehicle_ids = {"fc-a", "fc-b", "fc-c"};
  r.begins = {above(-4000, -4000, 100), above(4000, -4000, 100), above(0, 4000, 100)};
  r.ends = r.begins;
  const double spots[6][2] = {{-2500, -1500}, {-1000, -3000}, {1500, -2500}, {3000, -1000}, {-1500, 3000}, {1500, 3500}};
  for (const auto& s : spots) r.tasks.push_back(above(s[0], s[1], 150));
  ASSERT_TRUE(planFleet(r)) << daemon_.err();
  const FleetFlown planned(station_->trajectory_log, r.request_id);
  double cruise_m = 0.0;
  for (double t = planned.beginOf("fc-a"); t <= planned.endOf("fc-a"); t += 1.0)
    cruise_m = std::max(cruise_m, planned.positionAt("fc-a", t).z());

  // A column (every altitude of the band) across where fc-a is 70 s after its launch: still
  // climbing over its begin.
  const std::int64_t now_ns = utcNowNs();
  const double now_s = static_cast<double>(now_ns) * 1e-9;
  const double meet_s = planned.beginOf("fc-a") + 70.0;
  ASSERT_GT(meet_s - now_s, 30.0) << "the plan came too late for the scenario";
  const Eigen::Vector3d meet = planned.positionAt("fc-a", meet_s);
  ASSERT_LT(meet.z(), cruise_m - 200.0) << "the column must meet fc-a in its climb";
  const Eigen::Vector2d velocity(0.0, 10.0);
  const Eigen::Vector2d from = meet.head<2>() - velocity * (meet_s - now_s);
  ObstacleUpdateData u;
  u.obstacle.id = 201;
  u.obstacle.shape = ObstacleShape::kCylinder;
  u.obstacle.size_m = Eigen::Vector3d(120.0, 120.0, 2500.0);
  u.obstacle.center_m = Eigen::Vector3d(from.x(), from.y(), 1000.0);
  u.constant_velocity_enu_mps = Eigen::Vector3d(velocity.x(), velocity.y(), 0.0);
  u.valid_from_utc_ns = now_ns;
  const Obstacle column = worldObstacle(u, 3600.0);
  ASSERT_TRUE(station_->obstacles->write(u).ok());

  ASSERT_TRUE(station_->pumpUntil(
      [&] { return reached(r.request_id, PlanState::kReplanned) && revised(r.request_id).count("fc-a") > 0; }, 20.0))
      << daemon_.err();
  station_->pumpUntil([] { return false; }, 1.0);  // anything else that would come
  const FleetStatusData& last = *std::find_if(fleet_log_.rbegin(), fleet_log_.rend(), [&](const FleetStatusData& s) {
    return s.request_id == r.request_id && s.state == PlanState::kReplanned;
  });
  EXPECT_TRUE(last.field.empty()) << last.message;

  const FleetFlown flown(station_->trajectory_log, r.request_id);
  for (std::uint32_t j = 0; j < r.tasks.size(); ++j) ASSERT_EQ(flown.servings(j).size(), 1u) << "task " << j;
  double last_end_s = now_s;
  for (const std::string& v : r.vehicle_ids) {
    last_end_s = std::max(last_end_s, flown.endOf(v));
    for (double t = std::max(now_s, flown.beginOf(v)); t <= flown.endOf(v); t += 0.05)
      ASSERT_FALSE(column.contains(flown.positionAt(v, t), t, kVehicleRadiusM)) << v << " in the column at " << t;
  }
  const double closest_m = closestPairM(flown, r.vehicle_ids, now_s, last_end_s);
  EXPECT_GE(closest_m, last.min_separation_m - 1.0);
  std::printf("climb over DDS: revised %zu, replan %.3f s, closest pair %.0f m (min %.0f)\n", revised(r.request_id).size(),
              last.planning_time_s, closest_m, last.min_separation_m);
}

}  // namespace
}  // namespace skyroute
