// Bad samples over DDS that the other e2e tests do not write, each refused by name with the
// daemon serving afterwards: infinite coordinates, an obstacle update that goes back in time, and
// a new obstacle beyond obstacles.max_active. (NaN points, too many points, a duplicate request
// id, an unknown enum value and cancels for an unknown request or vehicle are in
// skyrouted_e2e_test, request_bounds_e2e_test and refused_input_e2e_test.)
#include <gtest/gtest.h>

#include <limits>
#include <string>

#include "tests/daemon/daemon_fixture.hpp"

namespace skyroute {
namespace {

class BadSamplesE2E : public testing::DaemonFixture {
 protected:
  ObstacleUpdateData sphere(std::uint64_t id, double east_m, std::int64_t valid_from_ns) const {
    ObstacleUpdateData u;
    u.obstacle.id = id;
    u.obstacle.shape = ObstacleShape::kSphere;
    u.obstacle.size_m = Eigen::Vector3d(100.0, 0.0, 0.0);
    u.obstacle.center_m = above(east_m, -4000, 300).enu_m;
    u.valid_from_utc_ns = valid_from_ns;
    return u;
  }
  static ObstacleUpdateData removal(std::uint64_t id) {
    ObstacleUpdateData gone;
    gone.obstacle.id = id;
    gone.remove = true;
    return gone;
  }
  bool heartbeatShowsObstacles(std::uint32_t n) {
    return station_->pumpUntil([&] { return station_->last_heartbeat && station_->last_heartbeat->obstacles == n; },
                               10.0);
  }
  // The service still plans: a request after the bad samples succeeds.
  void expectStillServing(const std::string& id) {
    ASSERT_TRUE(station_->requests->write(simpleMission(id, "uav-after", 2000.0)).ok());
    ASSERT_TRUE(station_->waitTerminal({id}, 60.0)) << daemon_.err();
    EXPECT_EQ(station_->terminal(id)->state, PlanState::kSucceeded) << station_->terminal(id)->message;
    EXPECT_TRUE(daemon_.running());
  }
};

TEST_F(BadSamplesE2E, InfiniteCoordinatesAreRefusedNamingThePoint) {
  startDaemon(72);
  constexpr double kInf = std::numeric_limits<double>::infinity();
  MissionRequestData east = simpleMission("inf-east", "uav-inf", 0.0);
  east.points[0].enu_m.x() = kInf;
  MissionRequestData lat = simpleMission("inf-lat", "uav-inf2", 0.0);
  lat.end = MissionPointData::wgs84(-kInf, 10.0, 1000.0);
  ASSERT_TRUE(station_->requests->write(east).ok());
  ASSERT_TRUE(station_->requests->write(lat).ok());
  ObstacleUpdateData obstacle = sphere(5, 0.0, utcNowNs());
  obstacle.obstacle.center_m.z() = kInf;
  ASSERT_TRUE(station_->obstacles->write(obstacle).ok());
  ASSERT_TRUE(station_->waitTerminal({"inf-east", "inf-lat"}, 10.0)) << daemon_.err();
  for (const auto& [id, field] : {std::pair<std::string, std::string>{"inf-east", "points[0]"}, {"inf-lat", "end"}}) {
    const PlanStatusData s = *station_->terminal(id);
    EXPECT_EQ(s.state, PlanState::kFailed) << id;
    EXPECT_EQ(s.error_code, PlanErrorCode::kInvalidArgument) << id << ": " << s.message;
    EXPECT_EQ(s.field.rfind(field, 0), 0u) << id << ": field '" << s.field << "'";
  }
  EXPECT_TRUE(waitForLog("event=bad_obstacle_update field=position_enu_m.z", 10.0)) << daemon_.err();
  EXPECT_TRUE(heartbeatShowsObstacles(0));
  expectStillServing("after-inf");
}

TEST_F(BadSamplesE2E, AnObstacleUpdateBackInTimeIsRefusedAndTheUpdateInForceStays) {
  startDaemon(73);
  const std::int64_t now_ns = utcNowNs();
  ASSERT_TRUE(station_->obstacles->write(sphere(11, 0.0, now_ns)).ok());
  ASSERT_TRUE(heartbeatShowsObstacles(1));
  // The same obstacle, a minute older and elsewhere: refused, naming the field.
  ASSERT_TRUE(station_->obstacles->write(sphere(11, 3000.0, now_ns - 60'000'000'000LL)).ok());
  EXPECT_TRUE(waitForLog("event=obstacle_rejected id=11 code=invalid_argument field=valid_from_utc_ns", 10.0))
      << daemon_.err();
  EXPECT_TRUE(waitForLog("an update may not go back in time", 1.0)) << daemon_.err();
  // A later update of it is taken, and a removal needs no time.
  ASSERT_TRUE(station_->obstacles->write(sphere(11, 3000.0, now_ns + 1'000'000'000LL)).ok());
  ASSERT_TRUE(station_->obstacles->write(removal(11)).ok());
  EXPECT_TRUE(heartbeatShowsObstacles(0));
  EXPECT_EQ(logCount("event=obstacle_rejected"), 1u) << daemon_.err();
  expectStillServing("after-back-in-time");
}

TEST_F(BadSamplesE2E, ANewObstacleBeyondMaxActiveIsRefusedAndKnownOnesStillMove) {
  startDaemonWithConfig(74, "[obstacles]\nmax_active = 3\n");
  const std::int64_t now_ns = utcNowNs();
  for (std::uint64_t id = 1; id <= 3; ++id) {
    ASSERT_TRUE(station_->obstacles->write(sphere(id, -3000.0 + 1500.0 * static_cast<double>(id), now_ns)).ok());
  }
  ASSERT_TRUE(heartbeatShowsObstacles(3));
  ASSERT_TRUE(station_->obstacles->write(sphere(4, 3000.0, now_ns)).ok());
  EXPECT_TRUE(waitForLog("event=obstacle_rejected id=4 code=limits_out_of_range field=obstacle_id", 10.0))
      << daemon_.err();
  EXPECT_TRUE(waitForLog("3 obstacles are in force (obstacles.max_active)", 1.0)) << daemon_.err();
  EXPECT_TRUE(heartbeatShowsObstacles(3));
  ASSERT_TRUE(station_->obstacles->write(sphere(2, 500.0, now_ns + 1'000'000'000LL)).ok());
  ASSERT_TRUE(station_->obstacles->write(removal(1)).ok());
  ASSERT_TRUE(heartbeatShowsObstacles(2));
  ASSERT_TRUE(station_->obstacles->write(sphere(4, 3000.0, now_ns + 2'000'000'000LL)).ok());
  EXPECT_TRUE(heartbeatShowsObstacles(3));
  expectStillServing("after-max-active");
}

}  // namespace
}  // namespace skyroute
