// Live re-ordering in the engine's replanning cycle: obstacles that wall off the approach to a
// flying mission's next point make the cycle publish a new revision that visits the points left
// in a new order, with a reordered status and a log line giving the old and the new order; the new
// trajectory continues the flown one, keeps clear of the obstacles and still passes every point
// not reached. A change far from the mission publishes nothing.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <memory>

#include <spdlog/sinks/ringbuffer_sink.h>
#include <spdlog/spdlog.h>

#include "service/engine.hpp"
#include "service/no_fly_zone_data.hpp"
#include "tests/service/default_world_fixture.hpp"
#include "tests/service/recording_sink.hpp"

namespace skyroute {
namespace {

constexpr double kCylinderRadiusM = 200.0;

class EngineReorderTest : public testing::DefaultWorldTest {
 protected:
  void SetUp() override {
    DefaultWorldTest::SetUp();
    if (HasFatalFailure()) return;
    EngineOptions options;
    options.pipeline.sample_dt_s = 0.1;
    options.pipeline.replan.replan_budget_ms = 0.0;  // iteration budgets: the same plans on any machine
    auto engine = Engine::create(world_, options, sink_, [this] { return now_ns_; });
    ASSERT_TRUE(engine.ok()) << engine.error().describe();
    engine_ = std::move(*engine);
    log_ = std::make_shared<spdlog::sinks::ringbuffer_sink_mt>(256);
    log_->set_pattern("%v");
    previous_logger_ = spdlog::default_logger();
    spdlog::set_default_logger(std::make_shared<spdlog::logger>("engine_reorder_test", log_));
  }
  void TearDown() override {
    if (previous_logger_) spdlog::set_default_logger(previous_logger_);
  }

  // Two points near begin that are about as good either way round, then two on the way to end.
  MissionRequestData request() const {
    MissionRequestData r;
    r.request_id = "tour";
    r.vehicle_id = "uav-7";
    r.begin = enu(-4500, -4500, 200);
    r.points = {enu(-2500, -4000, 200), enu(-4000, -2300, 200), enu(1000, 1000, 200), enu(2500, 3500, 200)};
    r.end = enu(4500, 4500, 200);
    return r;
  }
  Eigen::Vector3d pointOf(const MissionRequestData& r, std::uint32_t index) const {
    if (index == 0) return r.begin.enu_m;
    if (index == r.points.size() + 1) return r.end.enu_m;
    return r.points[index - 1].enu_m;
  }
  ObstacleUpdateData cylinderAt(std::uint64_t id, const Eigen::Vector2d& at) const {
    ObstacleUpdateData u;
    u.obstacle.id = id;
    u.obstacle.shape = ObstacleShape::kCylinder;
    u.obstacle.size_m = Eigen::Vector3d(kCylinderRadiusM, kCylinderRadiusM, 1000.0);
    u.obstacle.center_m = Eigen::Vector3d(at.x(), at.y(), heightfield_->heightAt(at.x(), at.y()));
    u.valid_from_utc_ns = now_ns_;
    return u;
  }
  // The way from begin to point `next` (east, north): its midpoint and the unit vectors along and
  // across it.
  struct Approach {
    Eigen::Vector2d mid, along, across;
  };
  Approach approachTo(const MissionRequestData& r, std::uint32_t next) const {
    const Eigen::Vector2d from = r.begin.enu_m.head<2>();
    const Eigen::Vector2d to = pointOf(r, next).head<2>();
    const Eigen::Vector2d along = (to - from).normalized();
    return {0.5 * (from + to), along, Eigen::Vector2d(-along.y(), along.x())};
  }
  std::size_t logLines(const std::string& what) const {
    const std::vector<std::string> lines = log_->last_formatted();
    return static_cast<std::size_t>(
        std::count_if(lines.begin(), lines.end(), [&](const std::string& l) { return l.find(what) != std::string::npos; }));
  }
  std::string logLine(const std::string& what) const {
    for (const std::string& l : log_->last_formatted())
      if (l.find(what) != std::string::npos) return l;
    return {};
  }

  testing::RecordingSink sink_;
  std::int64_t now_ns_ = 1'800'000'000'000'000'000LL;
  std::unique_ptr<Engine> engine_;
  std::shared_ptr<spdlog::sinks::ringbuffer_sink_mt> log_;
  std::shared_ptr<spdlog::logger> previous_logger_;
};

TEST_F(EngineReorderTest, AWallOnTheApproachToTheNextPointGivesAReorderedRevision) {
  const MissionRequestData r = request();
  ASSERT_FALSE(engine_->submit(r).has_value());
  ASSERT_TRUE(engine_->planNext());
  ASSERT_EQ(sink_.trajectories.size(), 1u);
  const TrajectoryData first = sink_.trajectories.front();
  ASSERT_EQ(first.visiting_order.size(), 6u);
  const std::uint32_t next = first.visiting_order[1];
  EXPECT_EQ(engine_->replanCycle(), 0u);  // nothing in the way

  // 10 s into the flight (the first point is further), a wall 1.5 km wide across the way from
  // begin to the next point, halfway.
  now_ns_ += 10'000'000'000LL;
  ASSERT_LT(first.legs.front().end_s, first.samples.back().t_rel_s);
  ASSERT_GT(first.legs.front().end_s, 20.0);
  const Approach way = approachTo(r, next);
  std::vector<ObstacleUpdateData> wall;
  for (int k = -3; k <= 3; ++k) wall.push_back(cylinderAt(50 + static_cast<std::uint64_t>(k + 3), way.mid + k * 250.0 * way.across));
  for (const ObstacleUpdateData& u : wall) ASSERT_FALSE(engine_->updateObstacle(u).has_value());
  ASSERT_EQ(engine_->replanCycle(), 1u);
  ASSERT_EQ(sink_.trajectories.size(), 2u);
  const TrajectoryData& second = sink_.trajectories.back();
  EXPECT_EQ(second.plan_id, first.plan_id);
  EXPECT_EQ(second.revision, 1u);

  // The status says so, with both orders; the log line too.
  const PlanStatusData& status = sink_.statuses.back();
  EXPECT_EQ(status.state, PlanState::kReordered);
  EXPECT_EQ(status.error_code, PlanErrorCode::kNone);
  EXPECT_FALSE(isTerminal(status.state));
  std::vector<int> old_order(first.visiting_order.begin(), first.visiting_order.end());
  std::vector<int> new_order(second.visiting_order.begin(), second.visiting_order.end());
  EXPECT_NE(status.message.find(orderText(old_order) + " -> " + orderText(new_order)), std::string::npos)
      << status.message;
  EXPECT_EQ(logLines("event=reordered"), 1u);
  const std::string line = logLine("event=reordered");
  EXPECT_NE(line.find("old_order=" + orderText(old_order)), std::string::npos) << line;
  EXPECT_NE(line.find("new_order=" + orderText(new_order)), std::string::npos) << line;

  // A new order of the same points, begin first and end last, the walled-off point no longer next.
  ASSERT_EQ(second.visiting_order.size(), first.visiting_order.size());
  EXPECT_EQ(second.visiting_order.front(), 0u);
  EXPECT_EQ(second.visiting_order.back(), 5u);
  EXPECT_TRUE(std::is_permutation(second.visiting_order.begin(), second.visiting_order.end(), first.visiting_order.begin()));
  EXPECT_NE(second.visiting_order, first.visiting_order);
  EXPECT_NE(second.visiting_order[1], next);

  // It continues the flown curve where it starts, passes every point in the new order and keeps
  // clear of the cylinders.
  const auto flown = std::find_if(first.samples.begin(), first.samples.end(),
                                  [&](const TrajectorySampleData& s) { return s.utc_ns >= second.samples.front().utc_ns; });
  ASSERT_NE(flown, first.samples.end());
  EXPECT_LT((flown->position_enu_m - second.samples.front().position_enu_m).norm(), 0.5);
  EXPECT_LT((flown->velocity_enu_mps - second.samples.front().velocity_enu_mps).norm(), 0.1);
  std::size_t at = 0;
  for (std::size_t k = 1; k < second.visiting_order.size(); ++k) {
    const Eigen::Vector3d p = pointOf(r, second.visiting_order[k]);
    while (at < second.samples.size() && (second.samples[at].position_enu_m - p).norm() > 30.0) ++at;
    ASSERT_LT(at, second.samples.size()) << "point " << second.visiting_order[k] << " is not passed in order";
  }
  for (const TrajectorySampleData& s : second.samples) {
    for (const ObstacleUpdateData& u : wall) {
      const Eigen::Vector3d& c = u.obstacle.center_m;
      if (s.position_enu_m.z() > c.z() + u.obstacle.size_m.z()) continue;  // above it
      ASSERT_GT((s.position_enu_m - c).head<2>().norm(), kCylinderRadiusM + WorldModelOptions{}.vehicle_radius_m)
          << "at t_rel " << s.t_rel_s;
    }
  }
  // Clear ahead now, and the same obstacles: the next cycle publishes nothing.
  now_ns_ += 100'000'000LL;
  EXPECT_EQ(engine_->replanCycle(), 0u);
}

TEST_F(EngineReorderTest, ANoFlyZoneOnTheApproachToTheNextPointGivesAReorderedRevisionThatAvoidsIt) {
  const MissionRequestData r = request();
  ASSERT_FALSE(engine_->submit(r).has_value());
  ASSERT_TRUE(engine_->planNext());
  ASSERT_EQ(sink_.trajectories.size(), 1u);
  const TrajectoryData first = sink_.trajectories.front();
  const std::uint32_t next = first.visiting_order[1];

  // 10 s into the flight a zone 1.9 km wide and 400 m deep is published across the way from
  // begin to the next point, halfway (WGS84 ring, heights AMSL, as the DDS edge receives it).
  now_ns_ += 10'000'000'000LL;
  const auto [mid, along, across] = approachTo(r, next);
  NoFlyZoneData zone;
  zone.zone_id = "tfr";
  for (const Eigen::Vector2d& v : {Eigen::Vector2d(mid - 950.0 * across - 200.0 * along), Eigen::Vector2d(mid + 950.0 * across - 200.0 * along),
                                   Eigen::Vector2d(mid + 950.0 * across + 200.0 * along), Eigen::Vector2d(mid - 950.0 * across + 200.0 * along)})
    zone.ring.push_back(heightfield_->frame().toGeo(Eigen::Vector3d(v.x(), v.y(), 0.0)));
  zone.floor_amsl_m = -1000.0;
  zone.ceiling_amsl_m = 9000.0;
  ASSERT_FALSE(engine_->updateNoFlyZone(zone).has_value());
  ASSERT_EQ(engine_->replanCycle(), 1u);
  ASSERT_EQ(sink_.trajectories.size(), 2u);
  const TrajectoryData& second = sink_.trajectories.back();
  EXPECT_EQ(sink_.statuses.back().state, PlanState::kReordered) << sink_.statuses.back().message;
  EXPECT_EQ(logLines("event=reordered"), 1u);
  EXPECT_NE(second.visiting_order[1], next);
  EXPECT_TRUE(std::is_permutation(second.visiting_order.begin(), second.visiting_order.end(), first.visiting_order.begin()));
  // Every sample outside the zone (grown by the vehicle's radius).
  const NoFlyZone in_frame = toNoFlyZone(zone, heightfield_->frame()).value();
  for (const TrajectorySampleData& s : second.samples)
    ASSERT_FALSE(in_frame.touchesPoint(s.position_enu_m, WorldModelOptions{}.vehicle_radius_m)) << "at t_rel " << s.t_rel_s;
}

TEST_F(EngineReorderTest, AnObstacleFarFromTheMissionPublishesNothing) {
  ASSERT_FALSE(engine_->submit(request()).has_value());
  ASSERT_TRUE(engine_->planNext());
  now_ns_ += 10'000'000'000LL;
  ASSERT_FALSE(engine_->updateObstacle(cylinderAt(9, Eigen::Vector2d(-5800, 5800))).has_value());
  EXPECT_EQ(engine_->replanCycle(), 0u);
  EXPECT_EQ(sink_.trajectories.size(), 1u);
  EXPECT_EQ(logLines("event=reordered"), 0u);
}

}  // namespace
}  // namespace skyroute
