// Every planner respects no-fly zones: a mission whose straight route crosses a zone gets a
// trajectory that avoids it (checked by sampling the trajectory against the prism in closed form,
// not through the zone code), the MMD*L order grid's costs go round the zone, and a mission point
// inside a zone is refused naming the point and the zone.
#include <algorithm>
#include <cmath>
#include <string>

#include <gtest/gtest.h>

#include "service/mission_pipeline.hpp"
#include "service/mission_point_check.hpp"
#include "tests/terrain_data.hpp"

namespace skyroute {
namespace {

constexpr double kHalfEastM = 600.0;   // the zone: a 1200 m x 1600 m rectangle round the centre
constexpr double kHalfNorthM = 800.0;
constexpr double kRouteHalfM = 3000.0; // the route: 6 km west to east through the centre

class NoFlyPipeline : public ::testing::Test {
 protected:
  static void SetUpTestSuite() { terrain_ = testing::defaultTerrainHeightfield(); }

  void SetUp() override {
    ASSERT_TRUE(terrain_) << "data/default_terrain.tif did not load";
    world_ = WorldModel::create(terrain_, WorldModelOptions{}, "default_terrain").value();
    center_ = terrain_->boundsEn().center();
    cruise_m_ = terrain_->maxHeightM() + 150.0;  // clear of every ridge: only the zone is in the way
    zone_.name = "stadium";
    zone_.ring_m = {center_ + Eigen::Vector2d(-kHalfEastM, -kHalfNorthM), center_ + Eigen::Vector2d(kHalfEastM, -kHalfNorthM),
                    center_ + Eigen::Vector2d(kHalfEastM, kHalfNorthM), center_ + Eigen::Vector2d(-kHalfEastM, kHalfNorthM)};
    zone_.floor_m = -1000.0;
    zone_.ceiling_m = 4900.0;  // up to near the vehicles' ceiling: the way is round, not over
  }

  MissionPointData at(double east_m, double north_m) const {
    return MissionPointData::enu(Eigen::Vector3d(center_.x() + east_m, center_.y() + north_m, cruise_m_));
  }

  MissionRequestData request(const std::string& planner) const {
    MissionRequestData r;
    r.request_id = "r-" + planner;
    r.vehicle_id = "uav-1";
    r.begin = at(-kRouteHalfM, 0.0);
    r.end = at(kRouteHalfM, 0.0);
    r.planner = planner;
    r.fixed_order = true;
    return r;
  }

  // Reference: the vehicle's 5 m sphere at p reaches into the rectangle's prism.
  bool inZone(const Eigen::Vector3d& p) const {
    const double r = WorldModelOptions{}.vehicle_radius_m;
    const double dx = std::max(0.0, std::abs(p.x() - center_.x()) - kHalfEastM);
    const double dy = std::max(0.0, std::abs(p.y() - center_.y()) - kHalfNorthM);
    return std::hypot(dx, dy) <= r && p.z() >= zone_.floor_m - r && p.z() <= zone_.ceiling_m + r;
  }

  static inline std::shared_ptr<const Heightfield> terrain_;
  std::shared_ptr<WorldModel> world_;
  Eigen::Vector2d center_;
  double cruise_m_ = 0.0;
  NoFlyZone zone_;
};

class NoFlyEveryPlanner : public NoFlyPipeline, public ::testing::WithParamInterface<std::string> {};

TEST_P(NoFlyEveryPlanner, TrajectoryGoesRoundTheZone) {
  world_->setNoFlyZones({zone_});
  const MissionRequestData r = request(GetParam());
  // The straight route crosses the zone, so the zone is what the planner must answer.
  const Eigen::Vector3d a = r.begin.toEnu(terrain_->frame()), b = r.end.toEnu(terrain_->frame());
  ASSERT_TRUE(inZone(0.5 * (a + b)));
  PipelineOptions options;
  options.seed = 3;
  const MissionPipeline pipeline(world_, options);
  auto plan = pipeline.plan(PipelineRequest{r, std::nullopt, std::nullopt}, 0.0);
  ASSERT_TRUE(plan.ok()) << plan.error().message;
  const Trajectory& trajectory = plan->flight->route().built.trajectory;
  ASSERT_GT(trajectory.duration_s(), 0.0);
  // Every 0.01 s: at 30 m/s at most, 0.3 m between samples.
  double closest_m = 1e9;
  for (double t = 0.0; t <= trajectory.duration_s(); t += 0.01) {
    const Eigen::Vector3d p = trajectory.evaluate(t, Derivative::kPosition);
    ASSERT_FALSE(inZone(p)) << GetParam() << " enters the zone at t = " << t << " s: " << p.transpose();
    const double dx = std::max(0.0, std::abs(p.x() - center_.x()) - kHalfEastM);
    const double dy = std::max(0.0, std::abs(p.y() - center_.y()) - kHalfNorthM);
    closest_m = std::min(closest_m, std::hypot(dx, dy));
  }
  EXPECT_LT(closest_m, 500.0) << "the detour should pass the zone, not wander off";
  // The end is reached.
  EXPECT_LT((trajectory.evaluate(trajectory.duration_s(), Derivative::kPosition) - b).norm(), 1.0);
}

INSTANTIATE_TEST_SUITE_P(Planners, NoFlyEveryPlanner,
                         ::testing::Values(std::string(kDefaultRoutePlanner), std::string("hab-pp"),
                                           std::string("hab-pp-rrt")),
                         [](const auto& info) {
                           std::string name = info.param;
                           std::replace(name.begin(), name.end(), '-', '_');
                           return name;
                         });

TEST_F(NoFlyPipeline, OrderGridCostsGoRoundTheZone) {
  MissionRequestData r = request(std::string(kDefaultRoutePlanner));
  r.fixed_order = false;
  // points[0] west and points[1] east of the zone; begin and end north of it.
  r.points = {at(-kRouteHalfM, 0.0), at(kRouteHalfM, 0.0)};
  r.begin = at(-kRouteHalfM, 2500.0);
  r.end = at(kRouteHalfM, 2500.0);
  const MissionPipeline pipeline(world_, PipelineOptions{});
  auto free = pipeline.order(r, 0.0);
  ASSERT_TRUE(free.ok()) << free.error().message;
  world_->setNoFlyZones({zone_});
  auto zoned = pipeline.order(r, 0.0);
  ASSERT_TRUE(zoned.ok()) << zoned.error().message;
  ASSERT_EQ(free->ordering.method, "mmdstar");
  ASSERT_EQ(zoned->ordering.method, "mmdstar");
  // points[0] (1) to points[1] (2): straight without the zone; round the grown rectangle's
  // corners with it (an 8-connected grid path is no shorter than the shortest path in the plane).
  const double cell_m = zoned->ordering.cell_size_m;
  const double straight_m = 2.0 * kRouteHalfM;
  const double r_m = WorldModelOptions{}.vehicle_radius_m;
  const double round_m = 2.0 * std::hypot(kRouteHalfM - kHalfEastM - r_m, kHalfNorthM + r_m) + 2.0 * (kHalfEastM + r_m);
  EXPECT_LE(free->ordering.cost_matrix_m[1][2], straight_m + 2.0 * cell_m);
  EXPECT_GE(zoned->ordering.cost_matrix_m[1][2], round_m - 2.0 * cell_m);
  // begin (0) to points[0] (1), west of the zone, is untouched.
  EXPECT_NEAR(zoned->ordering.cost_matrix_m[0][1], free->ordering.cost_matrix_m[0][1], 1e-6);
}

TEST_F(NoFlyPipeline, PointInsideAZoneNamesThePointAndTheZone) {
  world_->setNoFlyZones({zone_});
  MissionRequestData r = request(std::string(kDefaultRoutePlanner));
  r.points = {at(100.0, 100.0)};
  const MissionPipeline pipeline(world_, PipelineOptions{});
  auto ordered = pipeline.order(r, 0.0);
  ASSERT_FALSE(ordered.ok());
  EXPECT_EQ(ordered.error().field, "points[0]");
  EXPECT_EQ(ordered.error().stage, PlanStage::kValidate);
  EXPECT_NE(ordered.error().message.find("is inside no-fly zone 'stadium'"), std::string::npos)
      << ordered.error().message;
  // A zone out of force when the vehicle starts does not refuse the point.
  zone_.valid_until_s = 100.0;
  world_->setNoFlyZones({zone_});
  EXPECT_TRUE(pipeline.order(r, 200.0).ok());
}

TEST_F(NoFlyPipeline, FleetFliesRoundTheZoneAndRefusesATaskInside) {
  world_->setNoFlyZones({zone_});
  FleetRequestData r;
  r.request_id = "fleet";
  r.vehicle_ids = {"a", "b"};
  r.begins = {at(-kRouteHalfM, -300.0), at(-kRouteHalfM, 300.0)};
  r.tasks = {at(kRouteHalfM, -300.0), at(kRouteHalfM, 300.0)};  // straight east: through the zone
  r.ends = r.begins;
  const MissionPipeline pipeline(world_, PipelineOptions{});
  const FleetPlanOutput plan = pipeline.planFleet(r, 0);
  ASSERT_TRUE(plan.ok()) << plan.status.field << ": " << plan.status.message;
  ASSERT_EQ(plan.flown.size(), 2u);
  for (std::size_t i = 0; i < plan.flown.size(); ++i) {
    for (double t = 0.0; t <= plan.flown[i].duration_s(); t += 0.01) {
      const Eigen::Vector3d p = plan.flown[i].evaluate(t, Derivative::kPosition);
      ASSERT_FALSE(inZone(p)) << "vehicle " << i << " enters the zone at t = " << t << " s: " << p.transpose();
    }
  }
  r.tasks[1] = at(0.0, 0.0);
  const FleetPlanOutput refused = pipeline.planFleet(r, 0);
  ASSERT_FALSE(refused.ok());
  EXPECT_EQ(refused.status.field, "tasks[1]");
  EXPECT_NE(refused.status.message.find("is inside no-fly zone 'stadium'"), std::string::npos)
      << refused.status.message;
}

TEST_F(NoFlyPipeline, ExpireDropsZonesWhoseWindowEnded) {
  NoFlyZone until = zone_;
  until.valid_until_s = 100.0;
  world_->setNoFlyZones({zone_, until});
  const std::uint64_t version = world_->version();
  EXPECT_EQ(world_->expire(99.0), 0u);
  EXPECT_EQ(world_->expire(100.0), 1u);
  EXPECT_EQ(world_->noFlyZones().size(), 1u);
  EXPECT_GT(world_->version(), version);
  auto world = world_->worldFor(30.0, 5000.0);
  ASSERT_TRUE(world.ok());
  EXPECT_EQ((*world)->noFlyZones().size(), 1u);
}

}  // namespace
}  // namespace skyroute
