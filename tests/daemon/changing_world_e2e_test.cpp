// A valid request planned while obstacles arrive: the collision worlds change in place, so a plan
// could find its path in one world and check it in the next, and fail a valid request with
// `invalid_argument`, field `path` (5 of 40 did). The daemon now plans such a request again on
// the world as it is (Engine::plan); every request here is answered on its merits.
#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "tests/daemon/daemon_fixture.hpp"

namespace skyroute {
namespace {

class ChangingWorldE2E : public testing::DaemonFixture {};

TEST_F(ChangingWorldE2E, RequestsPlannedWhileObstaclesArriveOnTheirRoutesAreNotRefusedForTheirPath) {
  startDaemon(22);
  constexpr int kRequests = 40;
  std::vector<std::string> ids;
  for (int k = 0; k < kRequests; ++k) {
    const double lane_m = -4000.0 + 200.0 * k;
    const std::string id = "during-" + std::to_string(k);
    ids.push_back(id);
    ASSERT_TRUE(station_->requests->write(simpleMission(id, "uav-" + std::to_string(k), lane_m)).ok());
    // Right behind the request, while it is planned: a sphere across its last leg.
    ObstacleUpdateData u;
    u.obstacle.id = 1000 + static_cast<std::uint64_t>(k);
    u.obstacle.shape = ObstacleShape::kSphere;
    u.obstacle.size_m = Eigen::Vector3d(120.0, 0.0, 0.0);
    u.obstacle.center_m = above(2500, lane_m + 100, 400).enu_m;
    u.valid_from_utc_ns = utcNowNs();
    ASSERT_TRUE(station_->obstacles->write(u).ok());
    // One request at a time in flight, so each meets its obstacle while it is planned.
    ASSERT_TRUE(station_->waitTerminal({id}, 120.0)) << daemon_.err();
  }
  int succeeded = 0;
  for (const std::string& id : ids) {
    const PlanStatusData s = *station_->terminal(id);
    EXPECT_FALSE(s.state == PlanState::kFailed && s.error_code == PlanErrorCode::kInvalidArgument)
        << id << " was refused: " << s.field << ": " << s.message;
    succeeded += s.state == PlanState::kSucceeded;
  }
  std::printf("%d of %d succeeded; plans retried on a changed world: %zu\n", succeeded, kRequests,
              logCount("event=plan_retried"));
  EXPECT_EQ(succeeded, kRequests) << daemon_.err();
}

}  // namespace
}  // namespace skyroute
