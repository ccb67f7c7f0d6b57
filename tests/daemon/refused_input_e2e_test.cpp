// Inputs the daemon refuses, end to end: absurd obstacles are refused by name and leave planning
// alone; a replayed feed never waits beyond its horizon; an enum value no IDL knows and a cancel
// for nothing are logged and answered; a warning repeated every cycle is logged once per window
// with its count.
#include <gtest/gtest.h>

#include <cstring>
#include <optional>
#include <regex>
#include <filesystem>
#include <fstream>
#include <string>

#include "service/obstacle_feed.hpp"
#include "tests/daemon/daemon_fixture.hpp"

namespace skyroute {
namespace {

using testing::ChildProcess;

class RefusedInputE2E : public testing::DaemonFixture {
 protected:
  ObstacleUpdateData sphere(std::uint64_t id, const Eigen::Vector3d& at, double radius_m) const {
    ObstacleUpdateData u;
    u.obstacle.id = id;
    u.obstacle.shape = ObstacleShape::kSphere;
    u.obstacle.size_m = Eigen::Vector3d(radius_m, 0.0, 0.0);
    u.obstacle.center_m = at;
    u.valid_from_utc_ns = utcNowNs();
    return u;
  }
  bool heartbeatShowsObstacles(std::uint32_t n) {
    return station_->pumpUntil([&] { return station_->last_heartbeat && station_->last_heartbeat->obstacles == n; },
                               10.0);
  }
};

TEST_F(RefusedInputE2E, AbsurdObstaclesAreRefusedByNameAndRequestsStillSucceed) {
  startDaemon(181);
  const Eigen::Vector3d here = above(0, 0, 300).enu_m;
  ObstacleUpdateData huge_sphere = sphere(1, here, 1e300);
  ObstacleUpdateData huge_box = sphere(2, here, 100.0);
  huge_box.obstacle.shape = ObstacleShape::kBox;
  huge_box.obstacle.size_m = Eigen::Vector3d(100.0, 1e308, 100.0);
  ObstacleUpdateData fast = sphere(3, here, 100.0);
  fast.obstacle.motion = BackAndForth{here, here + Eigen::Vector3d(1000, 0, 0), 1e300, 0.0};
  ObstacleUpdateData far = sphere(4, Eigen::Vector3d(1e300, 0.0, 500.0), 100.0);
  for (const ObstacleUpdateData& u : {huge_sphere, huge_box, fast, far}) ASSERT_TRUE(station_->obstacles->write(u).ok());

  for (const char* line : {"event=obstacle_rejected id=1 code=limits_out_of_range field=size_m.x",
                                  "event=obstacle_rejected id=2 code=limits_out_of_range field=size_m.y",
                                  "event=obstacle_rejected id=3 code=limits_out_of_range field=speed_mps",
                                  "event=obstacle_rejected id=4 code=limits_out_of_range field=position_enu_m.x"}) {
    EXPECT_TRUE(waitForLog(line, 10.0)) << line << "\n" << daemon_.err();
  }
  EXPECT_NE(daemon_.err().find("size_m.x is 1e+300 m, more than"), std::string::npos) << daemon_.err();
  ASSERT_TRUE(station_->freshHeartbeat(5.0));
  EXPECT_TRUE(heartbeatShowsObstacles(0));

  // A sane obstacle next to them is taken, and planning is not walled in.
  ASSERT_TRUE(station_->obstacles->write(sphere(5, above(0, -4000, 300).enu_m, 100.0)).ok());
  EXPECT_TRUE(heartbeatShowsObstacles(1));
  const MissionRequestData m = simpleMission("after-absurd", "uav-a", 0.0);
  ASSERT_TRUE(station_->requests->write(m).ok());
  ASSERT_TRUE(station_->waitTerminal({m.request_id}, 120.0)) << daemon_.err();
  EXPECT_EQ(station_->terminal(m.request_id)->state, PlanState::kSucceeded) << station_->terminal(m.request_id)->message;
}

TEST_F(RefusedInputE2E, ReplayRefusesAFeedTimeBeyondTheHorizonNamingItsLine) {
  startDaemon(182);
  FeedEntry entry;
  entry.update = sphere(7, above(0, -4000, 300).enu_m, 100.0);
  entry.valid_for_s = 600.0;
  nlohmann::json far = nlohmann::json::parse(obstacleFeedEntryLine(entry));
  far["t_s"] = 1e12;  // 31,700 years from the start of the feed
  far["obstacle"]["id"] = 8;
  const std::string feed = testing::e2eTempPath("far_future.jsonl");
  std::ofstream(feed) << obstacleFeedHeaderLine() << "\n" << obstacleFeedEntryLine(entry) << "\n" << far.dump() << "\n";

  // Two readers: the daemon's and this ground station's echo (one alone may be the echo, and the
  // update would be published before the daemon matched).
  ChildProcess replay =
      ChildProcess::spawn({SKYROUTE_CLI, "replay", feed, "--domain", "182", "--readers", "2"}, "replay_far");
  EXPECT_EQ(replay.wait(30.0), 0) << replay.err();
  EXPECT_NE(replay.err().find(feed + ":3: t_s 1e+12 is beyond the feed's horizon"), std::string::npos) << replay.err();
  EXPECT_NE(replay.out().find("published 1 obstacle updates"), std::string::npos) << replay.out();
  EXPECT_TRUE(heartbeatShowsObstacles(1));
  std::filesystem::remove(feed);
}

TEST_F(RefusedInputE2E, AnUnknownEnumValueAndACancelForNothingAreLoggedAndAnswered) {
  startDaemon(183);
  // Raw samples as any DDS program may write them: values no enumerator has.
  dds::WireSample<skyroute_msgs_ObstacleUpdate> obstacle(&skyroute_msgs_ObstacleUpdate_desc);
  obstacle.msg().obstacle_id = 9;
  obstacle.msg().shape = 9;
  obstacle.msg().size_m = skyroute_msgs_Vec3{50, 50, 50};
  ASSERT_EQ(dds_write(station_->obstacles->handle(), &obstacle.msg()), DDS_RETCODE_OK);
  EXPECT_TRUE(waitForLog("event=bad_obstacle_update field=shape message=\"shape has an unknown value 9\"", 10.0))
      << daemon_.err();

  MissionRequestData bad_frame = simpleMission("bad-frame", "uav-f", 0.0);
  dds::WireSample<skyroute_msgs_MissionRequest> request(&skyroute_msgs_MissionRequest_desc);
  dds::toWire(bad_frame, request.msg());
  request.msg().begin.frame = 7;
  ASSERT_EQ(dds_write(station_->requests->handle(), &request.msg()), DDS_RETCODE_OK);
  ASSERT_TRUE(station_->waitTerminal({"bad-frame"}, 10.0)) << daemon_.err();
  EXPECT_EQ(station_->terminal("bad-frame")->error_code, PlanErrorCode::kInvalidArgument);
  EXPECT_EQ(station_->terminal("bad-frame")->field, "begin.frame");

  // Cancels for nothing: refused to the canceller, with a log line.
  const std::string canceller = dds::entityGuid(station_->cancels->handle());
  ASSERT_TRUE(station_->cancels->write(CancelRequestData{"ghost", "uav-x"}).ok());
  ASSERT_TRUE(station_->cancels->write(CancelRequestData{"", "uav-y"}).ok());
  auto answered = [&](const std::string& vehicle) -> std::optional<PlanStatusData> {
    for (const auto& s : station_->status_log)
      if (s.vehicle_id == vehicle && s.requester == canceller) return s;
    return std::nullopt;
  };
  ASSERT_TRUE(station_->pumpUntil([&] { return answered("uav-x") && answered("uav-y"); }, 10.0)) << daemon_.err();
  const PlanStatusData ghost = *answered("uav-x");
  EXPECT_EQ(ghost.request_id, "ghost");
  EXPECT_EQ(ghost.state, PlanState::kFailed);
  EXPECT_EQ(ghost.field, "request_id");
  EXPECT_NE(ghost.message.find("cancel refused: no request 'ghost' of vehicle 'uav-x'"), std::string::npos)
      << ghost.message;
  EXPECT_EQ(answered("uav-y")->field, "vehicle_id");
  EXPECT_TRUE(waitForLog("event=cancel_rejected vehicle=uav-x request=ghost", 5.0)) << daemon_.err();
  EXPECT_TRUE(waitForLog("event=cancel_rejected vehicle=uav-y request=", 5.0)) << daemon_.err();
}

TEST_F(RefusedInputE2E, AWarningRepeatedEveryCycleIsLoggedOncePerWindowWithItsCount) {
  startDaemonWithConfig(184, "[log]\nrepeat_window_s = 1\n");
  // A flight whose end point an obstacle then covers, reaching to within 200 m of the begin
  // point: every replanning cycle (10 Hz) finds the conflict ahead and fails to replan (the goal
  // is inside the obstacle).
  MissionRequestData m;
  m.request_id = "blocked";
  m.vehicle_id = "uav-b";
  m.begin = above(-600, 0, 400);
  m.points = {above(0, 50, 400)};
  m.end = above(600, 0, 400);
  ASSERT_TRUE(station_->requests->write(m).ok());
  ASSERT_TRUE(station_->waitTerminal({m.request_id}, 60.0)) << daemon_.err();
  ASSERT_EQ(station_->terminal(m.request_id)->state, PlanState::kSucceeded);
  ASSERT_TRUE(station_->obstacles->write(sphere(11, enuOf(m.end), 1000.0)).ok());
  ASSERT_TRUE(waitForLog("event=replan_failed request=blocked", 10.0)) << daemon_.err();
  station_->pumpUntil([] { return false; }, 3.5);  // 35 replanning cycles
  const std::size_t lines = logCount("event=replan_failed request=blocked");
  std::printf("replan_failed lines in 3.5 s of failures: %zu\n", lines);
  EXPECT_LE(lines, 6u) << daemon_.err();
  EXPECT_TRUE(std::regex_search(daemon_.err(), std::regex(R"(event=replan_failed request=blocked .*\(repeated \d+ times in 1 s\))")))
      << daemon_.err();
}

}  // namespace
}  // namespace skyroute
