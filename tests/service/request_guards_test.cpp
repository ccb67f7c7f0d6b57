// The engine's guards against costly or repeated input, one by one: the footprint lower bound and
// caps, the request registry, obstacle bounds relative to the terrain, and the log throttle.
#include <gtest/gtest.h>

#include <memory>

#include <spdlog/sinks/ringbuffer_sink.h>
#include <spdlog/spdlog.h>

#include "service/log_throttle.hpp"
#include "service/obstacle_bounds.hpp"
#include "service/request_footprint.hpp"
#include "service/request_registry.hpp"
#include "terrain/heightfield.hpp"
#include "tests/terrain_data.hpp"
#include "tests/test_data.hpp"

namespace skyroute {
namespace {

TEST(RequestFootprint, TheDurationBoundIsTheShortestRouteThroughThePointsOverVRef) {
  const std::vector<Eigen::Vector3d> points{{0, 0, 0}, {3000, 4000, 0}, {0, 8000, 0}, {0, 1000, 0}};
  FootprintOptions o;
  o.sample_dt_s = 0.5;
  // Given order: 5000 + 5000 + 7000 m.
  const RequestFootprint fixed = estimateFootprint(points, true, 10.0, o);
  EXPECT_DOUBLE_EQ(fixed.min_route_m, 17000.0);
  EXPECT_DOUBLE_EQ(fixed.min_duration_s, 1700.0);
  EXPECT_EQ(fixed.min_samples, 3402u);
  // Any order: at least the detour through the farthest point, 8000 + 7000 m.
  const RequestFootprint free = estimateFootprint(points, false, 10.0, o);
  EXPECT_DOUBLE_EQ(free.min_route_m, 15000.0);
  EXPECT_GT(free.memory_bytes, fixed.memory_bytes) << "the ordering grid costs memory";
}

TEST(RequestFootprint, EachCapRefusesTooLargeNamingWhatToChange) {
  const std::vector<Eigen::Vector3d> points{{0, 0, 0}, {5000, 0, 0}, {10000, 0, 0}};
  FootprintOptions o;
  o.trajectory.max_duration_s = 1000.0;
  auto refusal = checkFootprint(estimateFootprint(points, true, 5.0, o), 5.0, o);  // 2000 s
  ASSERT_TRUE(refusal);
  EXPECT_EQ(refusal->code, PlanErrorCode::kTooLarge);
  EXPECT_EQ(refusal->field, "limits.v_ref_mps");
  EXPECT_FALSE(checkFootprint(estimateFootprint(points, true, 20.0, o), 20.0, o));  // 500 s

  o.trajectory.max_samples = 1000;  // 500 s at 0.2 s: 2502 samples
  refusal = checkFootprint(estimateFootprint(points, true, 20.0, o), 20.0, o);
  ASSERT_TRUE(refusal);
  EXPECT_NE(refusal->message.find("2502 samples"), std::string::npos) << refusal->message;

  o.trajectory.max_samples = 100000;
  o.memory_share_bytes = 1024.0;
  refusal = checkFootprint(estimateFootprint(points, true, 20.0, o), 20.0, o);
  ASSERT_TRUE(refusal);
  EXPECT_EQ(refusal->field, "points");

  EXPECT_TRUE(checkTrajectorySize(1001.0, 0.2, TrajectorySizeBounds{1000.0, 100000}));
  EXPECT_FALSE(checkTrajectorySize(999.0, 0.2, TrajectorySizeBounds{1000.0, 100000}));
}

TEST(RequestRegistry, OneIdIsInFlightOnceAndRemembersItsLastResultWithinCapacity) {
  RequestRegistry registry(2);
  registry.begin("uav-1", "a");
  EXPECT_TRUE(registry.inFlight("uav-1", "a"));
  EXPECT_FALSE(registry.inFlight("uav-2", "a")) << "ids are per vehicle";
  PlanStatusData done{"a", "uav-1", PlanState::kSucceeded, PlanErrorCode::kNone, "", "", 1.0};
  registry.finish(done);
  EXPECT_FALSE(registry.inFlight("uav-1", "a"));
  ASSERT_TRUE(registry.finished("uav-1", "a"));
  done.state = PlanState::kCancelled;  // the mission is cancelled later: that is its final word
  registry.finish(done);
  EXPECT_EQ(registry.finished("uav-1", "a")->state, PlanState::kCancelled);
  registry.finish(PlanStatusData{"b", "uav-1", PlanState::kFailed, PlanErrorCode::kUnreachable, "", "", 0.0});
  registry.finish(PlanStatusData{"c", "uav-1", PlanState::kFailed, PlanErrorCode::kUnreachable, "", "", 0.0});
  EXPECT_FALSE(registry.finished("uav-1", "a")) << "the oldest is forgotten first";
  EXPECT_EQ(registry.finishedCount(), 2u);
}

TEST(ObstacleBounds, SizesPositionsAndSpeedsAreBoundedByTheTerrainsExtent) {
  const auto terrain = testing::defaultTerrainHeightfield();
  ASSERT_TRUE(terrain);
  const double side_m = terrain->boundsEn().sizes().maxCoeff();
  ObstacleUpdateData u;
  u.obstacle.shape = ObstacleShape::kCylinder;
  u.obstacle.size_m = {100.0, 0.0, 200.0};
  u.obstacle.center_m = {0.0, 0.0, 500.0};
  EXPECT_FALSE(checkObstacleBounds(u, *terrain, {}));
  u.obstacle.size_m.z() = 1.5 * side_m;
  EXPECT_EQ(checkObstacleBounds(u, *terrain, {})->field, "size_m.z");
  EXPECT_FALSE(checkObstacleBounds(u, *terrain, ObstacleBounds{400.0, 2.0})) << "extent_factor 2";
  u.obstacle.size_m.z() = 200.0;
  u.obstacle.center_m.x() = terrain->boundsEn().max().x() + 1.5 * side_m;
  EXPECT_EQ(checkObstacleBounds(u, *terrain, {})->field, "position_enu_m.x");
  u.obstacle.center_m.x() = 0.0;
  u.constant_velocity_enu_mps = Eigen::Vector3d(500.0, 0.0, 0.0);
  EXPECT_EQ(checkObstacleBounds(u, *terrain, {})->field, "velocity_enu_mps");
  u.remove = true;
  EXPECT_FALSE(checkObstacleBounds(u, *terrain, {})) << "a removal carries no geometry";
}

TEST(LogThrottle, ARepeatedWarningIsLoggedOnceThenOncePerWindowWithItsCount) {
  auto sink = std::make_shared<spdlog::sinks::ringbuffer_sink_mt>(64);
  sink->set_pattern("%v");
  auto previous = spdlog::default_logger();
  spdlog::set_default_logger(std::make_shared<spdlog::logger>("throttle_test", sink));
  LogThrottle throttle(10.0);
  const auto t0 = LogThrottle::Clock::now();
  throttle.warn("uav-1:goal", "blocked", t0);
  for (int i = 1; i <= 211; ++i) throttle.warn("uav-1:goal", "blocked", t0 + std::chrono::milliseconds(40 * i));
  throttle.warn("uav-2:goal", "other vehicle", t0 + std::chrono::seconds(1));
  throttle.flush(t0 + std::chrono::seconds(11));
  throttle.flush(t0 + std::chrono::seconds(22));  // a window without repeats: forgotten
  throttle.warn("uav-1:goal", "blocked again", t0 + std::chrono::seconds(23));
  spdlog::set_default_logger(previous);
  EXPECT_EQ(sink->last_formatted(), (std::vector<std::string>{"blocked\n", "other vehicle\n",
                                                              "blocked (repeated 211 times in 10 s)\n",
                                                              "blocked again\n"}));
}

}  // namespace
}  // namespace skyroute
