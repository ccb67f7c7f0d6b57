// The daemon's lifecycle under signals, end to end: a SIGHUP reload that cannot be used changes
// nothing; one that can keeps every active mission, its trajectory and the obstacles, and a
// terrain change waits until no mission flies; SIGTERM stops the daemon within a second whatever
// stage a plan is in, and the client hears `cancelled`, never `succeeded`.
#include <gtest/gtest.h>

#include <chrono>
#include <filesystem>
#include <string>

#include "tests/daemon/daemon_fixture.hpp"

namespace skyroute {
namespace {

using testing::Station;
using Clock = std::chrono::steady_clock;

class DaemonLifecycleE2E : public testing::DaemonFixture {
 protected:
  // Sends SIGHUP and waits for the reload's outcome, the n-th event=reloaded or reload_failed.
  bool reload(const std::string& outcome, std::size_t nth) {
    daemon_.signal(SIGHUP);
    return station_->pumpUntil([&] { return logCount("event=" + outcome) >= nth || !daemon_.running(); }, 20.0) &&
           daemon_.running();
  }
  // Pumps until a heartbeat satisfies `check` (heartbeats describe the daemon as it is now).
  bool heartbeatShows(const std::function<bool(const ServiceStatusData&)>& check, double timeout_s = 10.0) {
    return station_->pumpUntil([&] { return station_->last_heartbeat && check(*station_->last_heartbeat); }, timeout_s);
  }
};

TEST_F(DaemonLifecycleE2E, AReloadNamingAMissingDemIsRefusedAndChangesNothing) {
  startDaemonWithConfig(174, "[planning]\nsample_dt_s = 0.5\n");
  writeConfig("[terrain]\ndem = \"/nonexistent/terrain.tif\"\n[planning]\nsample_dt_s = 1.0\n");
  ASSERT_TRUE(reload("reload_failed", 1)) << daemon_.err();
  EXPECT_NE(daemon_.err().find("field=terrain.dem"), std::string::npos) << daemon_.err();
  EXPECT_NE(daemon_.err().find("/nonexistent/terrain.tif"), std::string::npos) << daemon_.err();

  // Still serving, on the old terrain, with the old tunables (the same file's sample_dt_s too).
  const MissionRequestData m = simpleMission("after-bad-reload", "uav-h", 0.0);
  ASSERT_TRUE(station_->requests->write(m).ok());
  ASSERT_TRUE(station_->waitTerminal({m.request_id}, 120.0)) << daemon_.err();
  EXPECT_EQ(station_->terminal(m.request_id)->state, PlanState::kSucceeded);
  ASSERT_TRUE(station_->pumpUntil([&] { return station_->latest("uav-h") != nullptr; }, 10.0));
  const auto& samples = station_->latest("uav-h")->samples;
  EXPECT_NEAR(samples[1].t_rel_s - samples[0].t_rel_s, 0.5, 1e-9);
  EXPECT_TRUE(heartbeatShows([](const ServiceStatusData& s) { return s.terrain_name == "default_terrain.tif"; }));
}

TEST_F(DaemonLifecycleE2E, ReloadsKeepMissionsTrajectoriesAndObstaclesAndATerrainChangeWaitsForThem) {
  startDaemonWithConfig(175, "[planning]\nthreads = 1\n");
  const MissionRequestData m = simpleMission("keep-1", "uav-k", 0.0);  // 10 km at 20 m/s: flies for minutes
  ASSERT_TRUE(station_->requests->write(m).ok());
  ASSERT_TRUE(station_->waitTerminal({m.request_id}, 120.0)) << daemon_.err();
  ASSERT_EQ(station_->terminal(m.request_id)->state, PlanState::kSucceeded);
  ObstacleUpdateData far_away;  // clear of the route: it changes nothing but the count
  far_away.obstacle.id = 5;
  far_away.obstacle.shape = ObstacleShape::kSphere;
  far_away.obstacle.size_m = Eigen::Vector3d(100.0, 0.0, 0.0);
  far_away.obstacle.center_m = above(0, -4000, 300).enu_m;
  far_away.valid_from_utc_ns = utcNowNs();
  ASSERT_TRUE(station_->obstacles->write(far_away).ok());
  ASSERT_TRUE(heartbeatShows([](const ServiceStatusData& s) { return s.vehicles == 1 && s.obstacles == 1; }));

  // planning.threads 1 -> 2: the engine keeps running with another worker.
  writeConfig("[planning]\nthreads = 2\n");
  ASSERT_TRUE(reload("reloaded", 1)) << daemon_.err();
  EXPECT_NE(daemon_.err().find("planning_threads=2 missions=1 obstacles=1"), std::string::npos) << daemon_.err();
  const int seen = station_->heartbeats;
  ASSERT_TRUE(heartbeatShows([&](const ServiceStatusData&) { return station_->heartbeats > seen + 1; }));
  EXPECT_EQ(station_->last_heartbeat->vehicles, 1u);
  EXPECT_EQ(station_->last_heartbeat->obstacles, 1u);
  auto late = Station::open(175);
  ASSERT_TRUE(late);
  ASSERT_TRUE(late->pumpUntil([&] { return late->latest("uav-k") != nullptr; }, 20.0));
  EXPECT_EQ(late->latest("uav-k")->request_id, "keep-1");

  // Another DEM while the mission flies: refused, the terrain and the mission stay.
  const std::string other_dem = testing::e2eTempPath("other_terrain.tif");
  std::filesystem::copy_file(testing::projectDataPath("default_terrain.tif"), other_dem,
                             std::filesystem::copy_options::overwrite_existing);
  writeConfig("[terrain]\ndem = \"" + other_dem + "\"\n[planning]\nthreads = 2\n");
  ASSERT_TRUE(reload("reload_failed", 1)) << daemon_.err();
  EXPECT_NE(daemon_.err().find("refused while missions are active"), std::string::npos) << daemon_.err();
  EXPECT_TRUE(heartbeatShows([](const ServiceStatusData& s) {
    return s.terrain_name == "default_terrain.tif" && s.vehicles == 1 && s.obstacles == 1;
  }));

  // Once the mission is cancelled, the same reload goes through and the obstacle moves over.
  ASSERT_TRUE(station_->cancels->write(CancelRequestData{"keep-1", "uav-k"}).ok());
  ASSERT_TRUE(heartbeatShows([](const ServiceStatusData& s) { return s.vehicles == 0; }));
  ASSERT_TRUE(reload("reloaded", 2)) << daemon_.err();
  EXPECT_TRUE(heartbeatShows([&](const ServiceStatusData& s) {
    return s.terrain_name == std::filesystem::path(other_dem).filename().string() && s.obstacles == 1;
  })) << daemon_.err();
  std::filesystem::remove(other_dem);
}

TEST_F(DaemonLifecycleE2E, SigtermWhileATrajectoryIsBuiltStopsWithinASecondAndAnswersCancelled) {
  // Building dominates this plan: 41 straight legs well above the terrain (each found at once),
  // flown at the slowest cruise allowed (1 m/s), make a trajectory of about 440,000 s whose
  // check takes seconds. The caps are raised for it (and samples spaced 10 s apart).
  startDaemonWithConfig(176,
                        "[planning]\nsample_dt_s = 10\nleg_max_iterations = 200\n"
                        "[bounds]\nmax_trajectory_duration_s = 1000000\n",
                        {"--log-level", "debug"});
  MissionRequestData m;
  m.request_id = "slow-build";
  m.vehicle_id = "uav-t";
  m.begin = MissionPointData::enu({-5500, -5500, 1350});
  for (int i = 0; i < 40; ++i) {
    m.points.push_back(MissionPointData::enu({i % 2 == 0 ? 5500.0 : -5500.0, -5000.0 + 250 * i, 1300.0 + 20 * (i % 3)}));
  }
  m.end = MissionPointData::enu({-5500, 5500, 1300});
  m.fixed_order = true;
  m.limits.v_ref_mps = 1.0;
  ASSERT_TRUE(station_->requests->write(m).ok());
  ASSERT_TRUE(waitForLog("event=trajectory_build", 60.0)) << daemon_.err();
  ASSERT_FALSE(station_->terminal(m.request_id).has_value()) << "the plan finished before it could be interrupted";
  const auto sent = Clock::now();
  daemon_.signal(SIGTERM);
  const int code = daemon_.wait(5.0);
  const double stop_s = std::chrono::duration<double>(Clock::now() - sent).count();
  std::printf("SIGTERM while building the trajectory: stopped in %.3f s\n", stop_s);
  EXPECT_EQ(code, 0) << daemon_.err();
  EXPECT_LT(stop_s, 1.0) << daemon_.err();
  ASSERT_TRUE(station_->waitTerminal({m.request_id}, 5.0));
  const PlanStatusData status = *station_->terminal(m.request_id);
  EXPECT_EQ(status.state, PlanState::kCancelled) << status.message;
  EXPECT_NE(status.message.find("trajectory"), std::string::npos) << "not stopped in the trajectory stage: " << status.message;
  for (const auto& s : station_->status_log) EXPECT_NE(s.state, PlanState::kSucceeded) << s.request_id;
}

}  // namespace
}  // namespace skyroute
