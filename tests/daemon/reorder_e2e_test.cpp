// Live re-ordering through skyrouted over DDS: a mission whose order MMD*L chose is flying; a wall
// of obstacles published across the approach to its next point makes the daemon publish a new
// revision that visits the points left in a new order, answered with STATE_REORDERED naming the
// old and the new order, and logged with both.
#include <gtest/gtest.h>

#include <algorithm>
#include <string>
#include <vector>

#include "service/mission_reorder.hpp"
#include "tests/daemon/daemon_fixture.hpp"

namespace skyroute {
namespace {

class ReorderE2E : public testing::DaemonFixture {};

TEST_F(ReorderE2E, AWallAcrossTheApproachToTheNextPointReordersTheFlyingMission) {
  startDaemon(130);
  // Two points near begin that are about as good either way round, then two on the way to end.
  MissionRequestData m;
  m.request_id = "tour-1";
  m.vehicle_id = "uav-r";
  m.begin = above(-4500, -4500, 200);
  m.points = {above(-2500, -4000, 200), above(-4000, -2300, 200), above(1000, 1000, 200), above(2500, 3500, 200)};
  m.end = above(4500, 4500, 200);
  ASSERT_TRUE(station_->requests->write(m).ok());
  ASSERT_TRUE(station_->waitState(m.request_id, PlanState::kSucceeded, 60.0)) << daemon_.err();
  ASSERT_TRUE(station_->pumpUntil([&] { return station_->latest(m.vehicle_id) != nullptr; }, 10.0));
  const TrajectoryData first = *station_->latest(m.vehicle_id);
  ASSERT_EQ(first.visiting_order.size(), 6u);
  const std::uint32_t next = first.visiting_order[1];
  // The vehicle needs well over a minute to the first point: the wall goes up long before.
  ASSERT_GT(first.legs.front().end_s, 60.0);

  // A wall 1.5 km wide across the way from begin to the next point, halfway.
  ASSERT_TRUE(station_->obstacles->waitForReaders(1, 20.0).ok());
  const Eigen::Vector2d from = m.begin.enu_m.head<2>();
  const Eigen::Vector2d to = m.points[next - 1].enu_m.head<2>();
  const Eigen::Vector2d across = Eigen::Vector2d(-(to - from).y(), (to - from).x()).normalized();
  for (int k = -3; k <= 3; ++k) {
    const Eigen::Vector2d at = 0.5 * (from + to) + k * 250.0 * across;
    ObstacleUpdateData u;
    u.obstacle.id = 700 + static_cast<std::uint64_t>(k + 3);
    u.obstacle.shape = ObstacleShape::kCylinder;
    u.obstacle.size_m = Eigen::Vector3d(200.0, 200.0, 1000.0);
    u.obstacle.center_m = Eigen::Vector3d(at.x(), at.y(), terrain_->heightAt(at.x(), at.y()));
    u.valid_from_utc_ns = utcNowNs();
    ASSERT_TRUE(station_->obstacles->write(u).ok());
  }
  ASSERT_TRUE(station_->waitState(m.request_id, PlanState::kReordered, 30.0)) << daemon_.err();
  const auto status = std::find_if(station_->status_log.begin(), station_->status_log.end(), [&](const PlanStatusData& s) {
    return s.request_id == m.request_id && s.state == PlanState::kReordered;
  });
  EXPECT_EQ(status->error_code, PlanErrorCode::kNone);
  // The revision it names arrives with the new order: begin first, end last, the walled-off
  // point no longer next.
  ASSERT_TRUE(station_->pumpUntil(
      [&] {
        const TrajectoryData* t = station_->latest(m.vehicle_id);
        return t && t->revision > 0 && t->visiting_order != first.visiting_order;
      },
      10.0))
      << daemon_.err();
  const TrajectoryData reordered = *station_->latest(m.vehicle_id);
  EXPECT_EQ(reordered.plan_id, first.plan_id);
  ASSERT_EQ(reordered.visiting_order.size(), first.visiting_order.size());
  EXPECT_TRUE(std::is_permutation(reordered.visiting_order.begin(), reordered.visiting_order.end(),
                                  first.visiting_order.begin()));
  EXPECT_EQ(reordered.visiting_order.front(), 0u);
  EXPECT_EQ(reordered.visiting_order.back(), 5u);
  EXPECT_NE(reordered.visiting_order[1], next);
  const std::vector<int> old_order(first.visiting_order.begin(), first.visiting_order.end());
  const std::vector<int> new_order(reordered.visiting_order.begin(), reordered.visiting_order.end());
  EXPECT_NE(status->message.find(orderText(old_order) + " -> " + orderText(new_order)), std::string::npos)
      << status->message;
  ASSERT_TRUE(waitForLog("event=reordered", 5.0)) << daemon_.err();
  EXPECT_EQ(logCount("event=reordered"), 1u) << daemon_.err();
  EXPECT_EQ(logCount("old_order=" + orderText(old_order) + " new_order=" + orderText(new_order)), 1u) << daemon_.err();
  ASSERT_TRUE(daemon_.running()) << daemon_.err();
}

}  // namespace
}  // namespace skyroute
