// End to end over DDS: skyrouted runs as a separate process on loopback with a domain id of each
// test's own; the test is the ground station (requests in, statuses and trajectories out).
#include <gtest/gtest.h>

#include <chrono>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <functional>
#include <map>
#include <memory>
#include <set>
#include <thread>

#include "service/obstacle_feed.hpp"
#include "service/world_model.hpp"
#include "terrain/terrain_world.hpp"
#include "tests/daemon/daemon_fixture.hpp"
#include "tests/spoiled_request.hpp"
#include "tests/terrain_data.hpp"

namespace skyroute {
namespace {

using testing::ChildProcess;
using testing::Station;

std::string tempPath(const std::string& name) { return testing::e2eTempPath(name); }

class SkyroutedE2E : public testing::DaemonFixture {
 protected:
  // One simple mission for each of `count` vehicles uav-<v> (request <prefix><v>), spaced
  // spacing_m apart from first_m: the ids written (fewer when a write failed, which is reported).
  std::vector<std::string> sendSimpleMissions(const std::string& prefix, int count, double first_m, double spacing_m) {
    std::vector<std::string> ids;
    for (int v = 0; v < count; ++v) {
      const MissionRequestData m =
          simpleMission(prefix + std::to_string(v), "uav-" + std::to_string(v), first_m + spacing_m * v);
      const Status written = station_->requests->write(m);
      EXPECT_TRUE(written.ok()) << written.error().describe();
      if (!written.ok()) break;
      ids.push_back(m.request_id);
    }
    return ids;
  }

  // Replays a cylinder crossing uav-r's route on `domain` and checks the daemon's new revisions:
  // each avoids it, and the last reaches the end. Returns the revisions that came after it.
  std::vector<TrajectoryData> replayCrossingObstacle(int domain) {
    std::vector<TrajectoryData> after;
    replayCrossingObstacleInto(domain, after);
    return after;
  }
  void replayCrossingObstacleInto(int domain, std::vector<TrajectoryData>& after) {
    MissionRequestData m = simpleMission("replay-1", "uav-r", 0.0);
    m.limits.v_ref_mps = 50.0;  // seed 003's vehicle: at cruise within seconds
    m.limits.max_speed_mps = 60.0;
    m.limits.max_accel_mps2 = 10.0;
    m.limits.max_climb_rate_mps = 15.0;
    m.limits.max_descent_rate_mps = 15.0;
    ASSERT_TRUE(station_->requests->write(m).ok());
    ASSERT_TRUE(station_->waitTerminal({m.request_id}, 120.0)) << daemon_.err();
    ASSERT_EQ(station_->terminal(m.request_id)->state, PlanState::kSucceeded);
    ASSERT_TRUE(station_->pumpUntil([&] { return station_->latest("uav-r") != nullptr; }, 10.0));
    const TrajectoryData first = *station_->latest("uav-r");

    // A recorded feed: a cylinder that sweeps across the route and reaches the point 1.5 km ahead
    // of the vehicle just when the vehicle does (it starts 1 km to the side).
    const double now_rel_s = static_cast<double>(utcNowNs() - first.samples.front().utc_ns) * 1e-9;
    const double dt_s = first.samples[1].t_rel_s - first.samples[0].t_rel_s;
    const std::size_t now_k = static_cast<std::size_t>(now_rel_s / dt_s);
    std::size_t k = now_k;
    while (k + 1 < first.samples.size() &&
           (first.samples[k].position_enu_m - first.samples[now_k].position_enu_m).norm() < 1500.0)
      ++k;
    const double meet_in_s = first.samples[k].t_rel_s - now_rel_s;
    ASSERT_GT(meet_in_s, 10.0);
    ASSERT_LT(meet_in_s, 40.0);  // inside the 45 s replanning horizon
    const Eigen::Vector3d on_route = first.samples[k].position_enu_m;
    const Eigen::Vector3d heading = first.samples[k].velocity_enu_mps.normalized();
    const Eigen::Vector3d across(-heading.y(), heading.x(), 0.0);
    FeedEntry entry;
    entry.update.obstacle.id = 77;
    entry.update.obstacle.shape = ObstacleShape::kCylinder;
    entry.update.obstacle.size_m = Eigen::Vector3d(200.0, 0.0, 300.0);
    entry.update.obstacle.center_m = on_route - 1000.0 * across;
    entry.update.obstacle.motion =
        BackAndForth{on_route - 1000.0 * across, on_route + 1000.0 * across, 1000.0 / meet_in_s, 0.0};
    const std::string feed = tempPath("crossing.jsonl");
    ASSERT_TRUE(writeObstacleFeed(feed, {entry}).ok());

    ChildProcess replay = ChildProcess::spawn({SKYROUTE_CLI, "replay", feed, "--domain", std::to_string(domain), "--readers", "2"}, "replay");
    ASSERT_EQ(replay.wait(30.0), 0) << replay.err();
    ASSERT_TRUE(station_->pumpUntil([&] { return !station_->obstacle_log.empty(); }, 10.0));
    const auto heard = std::chrono::steady_clock::now();
    ASSERT_TRUE(station_->pumpUntil([&] { return station_->latest("uav-r")->revision >= 1; }, 20.0)) << daemon_.err();
    const double reaction_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - heard).count();
    std::printf("obstacle heard -> new revision received: %.3f s\n", reaction_s);
    EXPECT_LT(reaction_s, 5.0) << daemon_.err();

    // The first answer may be a hold: when a loaded machine cuts the replan at the cycle's
    // deadline, the vehicle stops clear of the obstacle and the next cycles plan on from there. So
    // every new revision must avoid the obstacle, and one of them must reach the end.
    const Obstacle obstacle = worldObstacle(station_->obstacle_log.back(), 3600.0);
    const auto reachesEnd = [&](const TrajectoryData& t) {
      return (t.samples.back().position_enu_m - enuOf(m.end)).norm() < 0.01;
    };
    ASSERT_TRUE(station_->pumpUntil([&] { return reachesEnd(*station_->latest("uav-r")); }, 30.0))
        << "no revision after the obstacle reaches the end; the last is revision "
        << station_->latest("uav-r")->revision << "\n" << daemon_.err();
    for (const TrajectoryData& t : station_->trajectory_log) {
      if (t.vehicle_id != "uav-r" || t.revision < 1) continue;
      EXPECT_EQ(t.plan_id, first.plan_id);
      after.push_back(t);
      for (const auto& s : t.samples) {
        const double t_s = static_cast<double>(s.utc_ns) * 1e-9;
        ASSERT_FALSE(obstacle.contains(s.position_enu_m, t_s, WorldModelOptions{}.vehicle_radius_m))
            << "revision " << t.revision << " meets the obstacle at t_rel=" << s.t_rel_s;
      }
    }
    std::filesystem::remove(feed);
  }
};

TEST_F(SkyroutedE2E, MissionGivesACollisionFreeTrajectoryThroughEveryPointBeginFirstEndLast) {
  startDaemon(140);
  const MissionRequestData mission = demoMission();
  ASSERT_TRUE(station_->requests->write(mission).ok());
  ASSERT_TRUE(station_->waitTerminal({mission.request_id}, 120.0)) << daemon_.err();
  const auto status = *station_->terminal(mission.request_id);
  ASSERT_EQ(status.state, PlanState::kSucceeded) << status.message;
  EXPECT_GT(status.planning_time_s, 0.0);
  ASSERT_TRUE(station_->pumpUntil([&] { return station_->latest(mission.vehicle_id) != nullptr; }, 10.0));
  const TrajectoryData& t = *station_->latest(mission.vehicle_id);
  EXPECT_EQ(t.request_id, mission.request_id);
  const std::size_t count = mission.points.size() + 2;
  ASSERT_EQ(t.visiting_order.size(), count);
  EXPECT_EQ(t.visiting_order.front(), 0u);
  EXPECT_EQ(t.visiting_order.back(), count - 1);
  EXPECT_EQ(std::set<std::uint32_t>(t.visiting_order.begin(), t.visiting_order.end()).size(), count);

  std::vector<Eigen::Vector3d> points{enuOf(mission.begin)};
  for (const auto& p : mission.points) points.push_back(enuOf(p));
  points.push_back(enuOf(mission.end));
  ASSERT_FALSE(t.samples.empty());
  EXPECT_LT((t.samples.front().position_enu_m - points.front()).norm(), 0.01);
  EXPECT_LT((t.samples.back().position_enu_m - points.back()).norm(), 0.01);
  const double step_m = mission.limits.max_speed_mps * 0.2;  // the daemon's default sample spacing
  for (const auto& p : points) {
    double nearest = 1e300;
    for (const auto& s : t.samples) nearest = std::min(nearest, (s.position_enu_m - p).norm());
    EXPECT_LT(nearest, step_m) << "a mission point is not on the trajectory";
  }
  // Independent terrain check at every sample and half-way between samples.
  const double clearance = mission.limits.min_clearance_agl_m;
  for (std::size_t i = 0; i < t.samples.size(); ++i) {
    const Eigen::Vector3d p = t.samples[i].position_enu_m;
    ASSERT_GE(p.z() - terrain_->heightAt(p.x(), p.y()), clearance - 1.0) << "sample " << i;
    if (i > 0) {
      const Eigen::Vector3d mid = 0.5 * (p + t.samples[i - 1].position_enu_m);
      ASSERT_GE(mid.z() - terrain_->heightAt(mid.x(), mid.y()), clearance - 1.0) << "between samples " << i - 1 << ", " << i;
    }
    EXPECT_LE(t.samples[i].velocity_enu_mps.norm(), mission.limits.max_speed_mps * 1.01);
  }
}

TEST_F(SkyroutedE2E, LateJoiningGroundStationGetsEveryVehiclesCurrentTrajectory) {
  startDaemon(141);
  const std::vector<std::string> ids = sendSimpleMissions("late-", 3, -3000.0, 2500.0);
  ASSERT_EQ(ids.size(), 3u);
  ASSERT_TRUE(station_->waitTerminal(ids, 120.0)) << daemon_.err();
  for (const auto& id : ids) ASSERT_EQ(station_->terminal(id)->state, PlanState::kSucceeded);

  auto late = Station::open(141);
  ASSERT_TRUE(late);
  std::set<std::string> vehicles;
  ASSERT_TRUE(late->pumpUntil(
      [&] {
        for (const auto& t : late->trajectory_log) vehicles.insert(t.vehicle_id);
        return vehicles.size() == 3;
      },
      20.0));
  EXPECT_EQ(vehicles, (std::set<std::string>{"uav-0", "uav-1", "uav-2"}));
  for (const auto& t : late->trajectory_log) EXPECT_FALSE(t.samples.empty());
}

TEST_F(SkyroutedE2E, ReplayedObstacleFeedCrossingTheRouteGivesANewRevisionThatAvoidsIt) {
  startDaemon(142);
  const std::vector<TrajectoryData> after = replayCrossingObstacle(142);
  EXPECT_FALSE(after.empty());
}

// A replan cut at its deadline (a 1 ms budget stands for a loaded machine) answers with a hold
// that stops clear of the obstacle, and the cycles after it plan on to the end.
TEST_F(SkyroutedE2E, ReplanCutAtItsDeadlineHoldsClearOfTheObstacleAndThenReachesTheEnd) {
  startDaemonWithConfig(128, "[replanning]\nbudget_s = 0.001\n");
  const std::vector<TrajectoryData> after = replayCrossingObstacle(128);
  ASSERT_GE(after.size(), 2u);
  EXPECT_GT((after.front().samples.back().position_enu_m - after.back().samples.back().position_enu_m).norm(), 100.0)
      << "the first answer should be a hold short of the end";
  EXPECT_LT(after.front().samples.back().velocity_enu_mps.norm(), 0.01) << "a hold ends at rest";
}

TEST_F(SkyroutedE2E, BadRequestsGetTheirErrorAndTheServiceGoesOnServing) {
  startDaemon(143);
  using Case = testing::SpoiledRequest;
  const std::vector<Case> cases = {
      {"planner", [](auto& m) { m.planner = "astar-9000"; }, PlanErrorCode::kUnknownPlanner, "planner"},
      {"nan", [](auto& m) { m.points[0].enu_m.y() = std::nan(""); }, PlanErrorCode::kInvalidArgument, "points[0]"},
      {"oversize", [](auto& m) { m.points.assign(200, m.points.front()); }, PlanErrorCode::kMissionTooLarge, "points"},
      {"limits", [](auto& m) { m.limits.max_speed_mps = 5000.0; }, PlanErrorCode::kLimitsOutOfRange, "limits.max_speed_mps"},
      {"outside", [](auto& m) { m.end = MissionPointData::wgs84(10.0, 10.0, 1000.0); }, PlanErrorCode::kOutsideMap, "end"},
      {"underground", [this](auto& m) { m.points[0] = above(100, 100, -50); }, PlanErrorCode::kUnderGround, "points[0]"},
  };
  std::vector<std::string> ids;
  for (const Case& c : cases) {
    MissionRequestData m = simpleMission("bad-" + c.name, "uav-bad", 0.0);
    c.spoil(m);
    ids.push_back(m.request_id);
    ASSERT_TRUE(station_->requests->write(m).ok());
  }
  const MissionRequestData good = simpleMission("good-after-bad", "uav-good", 1000.0);
  ASSERT_TRUE(station_->requests->write(good).ok());
  ids.push_back(good.request_id);
  MissionRequestData plain = simpleMission("good-begin-to-end", "uav-plain", 2000.0);
  plain.points.clear();  // a plain A -> B mission is a mission too
  ASSERT_TRUE(station_->requests->write(plain).ok());
  ids.push_back(plain.request_id);
  ASSERT_TRUE(station_->waitTerminal(ids, 120.0)) << daemon_.err();
  for (const Case& c : cases) {
    const auto s = *station_->terminal("bad-" + c.name);
    EXPECT_EQ(s.state, PlanState::kFailed) << c.name;
    EXPECT_EQ(s.error_code, c.code) << c.name << ": " << s.message;
    EXPECT_EQ(s.field.rfind(c.field, 0), 0u) << c.name << ": field '" << s.field << "'";
    EXPECT_NE(s.message.find(s.field), std::string::npos) << c.name << ": " << s.message;
  }
  EXPECT_EQ(station_->terminal(good.request_id)->state, PlanState::kSucceeded);
  EXPECT_EQ(station_->terminal(plain.request_id)->state, PlanState::kSucceeded) << station_->terminal(plain.request_id)->message;
  EXPECT_TRUE(daemon_.running());
}

TEST_F(SkyroutedE2E, SigtermDuringPlanningStopsCleanlyWithinASecond) {
  // A plan that takes many seconds: a huge RRT* budget per leg.
  const std::string config = tempPath("slow.toml");
  std::ofstream(config) << "[planning]\nleg_max_iterations = 2000000\n";
  startDaemon(144, {"--config", config});
  std::filesystem::remove(config);
  const MissionRequestData big = slowMission("big", "uav-big");
  ASSERT_TRUE(station_->requests->write(big).ok());
  ASSERT_TRUE(station_->waitState("big", PlanState::kPlanning, 30.0));
  std::this_thread::sleep_for(std::chrono::milliseconds(200));
  ASSERT_FALSE(station_->terminal("big").has_value()) << "planning finished too fast to interrupt";
  const auto sent = std::chrono::steady_clock::now();
  daemon_.signal(SIGTERM);
  const int code = daemon_.wait(5.0);
  const double stop_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - sent).count();
  EXPECT_EQ(code, 0) << daemon_.err();
  EXPECT_LT(stop_s, 1.0) << daemon_.err();
  // The cancelled status was flushed before the writers went away.
  ASSERT_TRUE(station_->waitTerminal({"big"}, 5.0));
  EXPECT_EQ(station_->terminal("big")->state, PlanState::kCancelled);
  EXPECT_NE(daemon_.err().find("event=stopped"), std::string::npos);
}

TEST_F(SkyroutedE2E, SighupReloadsTheConfiguration) {
  const std::string config = tempPath("skyrouted.toml");
  std::ofstream(config) << "[planning]\nsample_dt_s = 0.2\n";
  startDaemon(145, {"--config", config});
  MissionRequestData m = simpleMission("hup-1", "uav-h", 0.0);
  ASSERT_TRUE(station_->requests->write(m).ok());
  ASSERT_TRUE(station_->waitTerminal({m.request_id}, 120.0));
  ASSERT_TRUE(station_->pumpUntil([&] { return station_->latest("uav-h") != nullptr; }, 10.0));
  const auto& s1 = station_->latest("uav-h")->samples;
  EXPECT_NEAR(s1[1].t_rel_s - s1[0].t_rel_s, 0.2, 1e-9);

  std::ofstream(config) << "[planning]\nsample_dt_s = 1.0\n";
  daemon_.signal(SIGHUP);
  ASSERT_TRUE(station_->pumpUntil([&] { return daemon_.err().find("event=reloaded") != std::string::npos; }, 10.0))
      << daemon_.err();
  m.request_id = "hup-2";
  ASSERT_TRUE(station_->requests->write(m).ok());
  ASSERT_TRUE(station_->waitTerminal({m.request_id}, 120.0));
  ASSERT_TRUE(station_->pumpUntil([&] { return station_->latest("uav-h")->request_id == "hup-2"; }, 10.0));
  const auto& s2 = station_->latest("uav-h")->samples;
  EXPECT_NEAR(s2[1].t_rel_s - s2[0].t_rel_s, 1.0, 1e-9);

  // A broken file is refused and the service keeps its configuration and serves on.
  std::ofstream(config) << "[planning]\nsample_dt_s = -3\n";
  daemon_.signal(SIGHUP);
  ASSERT_TRUE(station_->pumpUntil([&] { return daemon_.err().find("event=reload_failed") != std::string::npos; }, 10.0));
  EXPECT_NE(daemon_.err().find("planning.sample_dt_s"), std::string::npos);
  EXPECT_TRUE(daemon_.running());
  std::filesystem::remove(config);
}

TEST_F(SkyroutedE2E, TwentyVehiclesWithConcurrentMissionsAreAllServed) {
  startDaemon(146);
  const std::vector<std::string> ids = sendSimpleMissions("fleet-", 20, -5000.0, 500.0);
  ASSERT_EQ(ids.size(), 20u);
  ASSERT_TRUE(station_->waitTerminal(ids, 300.0)) << daemon_.err();
  std::set<std::string> vehicles;
  for (const auto& id : ids) EXPECT_EQ(station_->terminal(id)->state, PlanState::kSucceeded) << id;
  ASSERT_TRUE(station_->pumpUntil(
      [&] {
        for (const auto& t : station_->trajectory_log) vehicles.insert(t.vehicle_id);
        return vehicles.size() == 20;
      },
      20.0));
  EXPECT_EQ(vehicles.size(), 20u);
}

}  // namespace
}  // namespace skyroute
