// What the vehicle does at a mission point, through the pipeline and the engine on the embedded
// terrain: a point whose corner no pass-through rounds (the flight-band lift dives into a valley
// point and climbs straight out, 30 m turn radius) is flown with a stop there, and the engine's
// PlanStatus says so; planning.mission_point_mode = stop rests at every point; a trajectory that
// cannot be flown even so is refused in the trajectory stage naming the point and the limit; RRT*
// routes whose time repairs once fought each other fly; and the configuration key parses, is
// described and refuses other values naming the key.
#include <gtest/gtest.h>

#include <cmath>
#include <mutex>
#include <string>
#include <vector>

#include "service/daemon_config.hpp"
#include "service/engine.hpp"
#include "service/mission_pipeline.hpp"
#include "service/planner_registry.hpp"
#include "service/route_planner.hpp"
#include "tests/service/default_world_fixture.hpp"
#include "tests/service/recording_sink.hpp"

namespace skyroute {
namespace {

using testing::RecordingSink;

class MissionPointModeTest : public testing::DefaultWorldTest {
 protected:
  // Across the main ridge through a valley point 60 m up: the straight legs are blocked, so the
  // grid planners lift the legs to the flight band and dive into the point.
  MissionRequestData valleyMission(const std::string& id) const {
    MissionRequestData r;
    r.request_id = id;
    r.vehicle_id = "uav-" + id;
    r.planner = "hab-pp";
    r.begin = enu(-5000, -2000, 60);
    r.points = {enu(0, -5500, 60)};
    r.end = enu(5000, 2000, 60);
    r.fixed_order = true;
    r.limits.min_turn_radius_m = 30.0;
    return r;
  }
  // Corner to corner with two turning points, 200 m up, the default planner.
  MissionRequestData zigZagMission(const std::string& id) const {
    MissionRequestData r;
    r.request_id = id;
    r.vehicle_id = "uav-" + id;
    r.begin = enu(-4500, -4500, 200);
    r.points = {enu(-1500, 1500, 200), enu(1500, -1500, 200)};
    r.end = enu(4500, 4500, 200);
    r.fixed_order = true;
    return r;
  }
  static constexpr std::int64_t kStartNs = 1'800'000'000'000'000'000LL;
};

// The time of the trajectory at each route point after the first (leg ends), from the plan.
std::vector<double> legEndTimes(const MissionPlan& plan) {
  std::vector<double> times;
  for (const RouteLeg& leg : plan.flight->route().legs) times.push_back(leg.end_s);
  return times;
}

TEST_F(MissionPointModeTest, APointNoPassThroughRoundsBecomesAStopNamedInTheStatus) {
  EngineOptions options;
  options.pipeline.sample_dt_s = 0.05;
  RecordingSink sink;
  auto engine = Engine::create(world_, options, sink, [] { return kStartNs; });
  ASSERT_TRUE(engine.ok()) << engine.error().describe();
  const MissionRequestData r = valleyMission("valley");
  ASSERT_FALSE((*engine)->submit(r).has_value());
  ASSERT_TRUE((*engine)->planNext());
  ASSERT_FALSE(sink.statuses.empty());
  const PlanStatusData& status = sink.statuses.back();
  ASSERT_EQ(status.state, PlanState::kSucceeded) << status.field << ": " << status.message;
  EXPECT_NE(status.message.find("points[0]: stops there"), std::string::npos) << status.message;
  ASSERT_FALSE(sink.trajectories.empty());
  const TrajectoryData& t = sink.trajectories.back();
  // The samples: through the point, at rest there, and clear of the ground all along.
  double nearest_m = 1e9;
  double speed_there_mps = 0.0;
  for (const auto& s : t.samples) {
    const double d = (s.position_enu_m - r.points[0].enu_m).norm();
    if (d < nearest_m) {
      nearest_m = d;
      speed_there_mps = s.velocity_enu_mps.norm();
    }
    const double ground = heightfield_->heightAt(s.position_enu_m.x(), s.position_enu_m.y());
    ASSERT_GE(s.position_enu_m.z() - ground, r.limits.min_clearance_agl_m - 0.5) << "at t=" << s.t_rel_s;
  }
  EXPECT_LT(nearest_m, 0.05);
  EXPECT_LT(speed_there_mps, 0.05);
}

TEST_F(MissionPointModeTest, StopModeRestsAtEveryPointAndPassDoesNot) {
  for (const FixedWaypointMode mode : {FixedWaypointMode::kPass, FixedWaypointMode::kStop}) {
    SCOPED_TRACE(std::string(to_string(mode)));
    PipelineOptions options;
    options.replan.route.trajectory.fixed_waypoint_mode = mode;
    const MissionPipeline pipeline(world_, options);
    auto plan = pipeline.plan(PipelineRequest{zigZagMission("zigzag"), std::nullopt, std::nullopt}, kStartNs * 1e-9);
    ASSERT_TRUE(plan.ok()) << plan.error().describe();
    const Trajectory& trajectory = plan->flight->route().built.trajectory;
    const std::vector<double> ends = legEndTimes(*plan);
    ASSERT_EQ(ends.size(), 3u);
    std::string notes;
    for (const std::string& note : plan->notes) notes += note + "\n";
    for (int point = 0; point < 2; ++point) {
      const double speed = trajectory.evaluate(ends[static_cast<std::size_t>(point)], Derivative::kVelocity).norm();
      const std::string name = "points[" + std::to_string(point) + "]: stops there";
      if (mode == FixedWaypointMode::kStop) {
        EXPECT_LT(speed, 1e-6) << point;
        EXPECT_LT(trajectory.evaluate(ends[static_cast<std::size_t>(point)], Derivative::kAcceleration).norm(), 1e-6);
        EXPECT_NE(notes.find(name), std::string::npos) << notes;
      } else {
        EXPECT_GT(speed, 5.0) << point;
        EXPECT_EQ(notes.find(name), std::string::npos) << notes;
      }
    }
  }
}

TEST_F(MissionPointModeTest, ATrajectoryThatCannotFlyNamesThePointAndTheLimit) {
  // No time repair at all: every rebuild with stops still breaks a limit somewhere.
  PipelineOptions options;
  options.replan.route.trajectory.repair = false;
  const MissionPipeline pipeline(world_, options);
  auto plan = pipeline.plan(PipelineRequest{zigZagMission("no-repair"), std::nullopt, std::nullopt}, kStartNs * 1e-9);
  ASSERT_FALSE(plan.ok());
  const PlanError& e = plan.error();
  EXPECT_EQ(e.code, PlanErrorCode::kUnreachable);
  EXPECT_EQ(e.stage, PlanStage::kTrajectory);
  ASSERT_GE(e.point_index, 0) << e.describe();
  EXPECT_EQ(e.field, requestPointName(e.point_index, 4)) << e.describe();
  EXPECT_TRUE(e.message.find("over the limit") != std::string::npos ||
              e.message.find("under the limit") != std::string::npos)
      << e.message;
}

TEST_F(MissionPointModeTest, RrtStarRoutesWhoseLocalStretchesGrewFly) {
  // Three random missions of bench/grid_route_bench (12, 54, 71; seed 1 + index) whose RRT*
  // routes' repairs once ended with "stretching in time makes the violation worse": local
  // stretches and collision splits fought each other. They now go on with the uniform stretch
  // and fly through the point (the stop fallbacks alone would fly them only with stops).
  auto world = world_->worldFor(30.0, 5000.0);
  ASSERT_TRUE(world.ok());
  struct Mission {
    int index;
    Eigen::Vector2d points[3];
  };
  const Mission missions[] = {{12, {{4450.0, 2379.3}, {2261.8, -4943.0}, {-3889.1, -5140.7}}},
                              {54, {{-2322.9, -3723.9}, {2734.5, 4282.5}, {4131.4, -685.7}}},
                              {71, {{-2945.2, 2842.7}, {665.9, 624.8}, {378.8, -1100.3}}}};
  const PipelineOptions pipeline;
  VehicleLimits limits;
  limits.min_turn_radius_m = 30.0;
  for (const Mission& m : missions) {
    SCOPED_TRACE(m.index);
    std::vector<Eigen::Vector3d> points;
    for (const Eigen::Vector2d& p : m.points) points.push_back(enu(p.x(), p.y(), 60).enu_m);
    const RouteOptions options = pipelineReplanOptions(pipeline, pipeline.budget, 1 + m.index).route;
    auto route = legPathPlanner(RoutePlannerKind::kRrtStarLospo, pipeline.grid_legs)(*world, points, options, {});
    ASSERT_TRUE(route.ok()) << route.error().describe();
    const Status built = buildRouteTrajectory(*world, points, limits, options, *route);
    ASSERT_TRUE(built.ok()) << built.error().describe();
    // Flown through: no stop at the point, none at the legs' corners.
    EXPECT_TRUE(route->point_stops.empty()) << route->point_stops.front().reason;
    EXPECT_TRUE(route->leg_corner_stops.empty()) << route->corner_stop_reason;
    const Trajectory& t = route->built.trajectory;
    for (double time = 0.0; time <= t.duration_s(); time += 0.5) {
      const Eigen::Vector3d p = t.evaluate(time, Derivative::kPosition);
      ASSERT_GE(p.z() - heightfield_->heightAt(p.x(), p.y()), 30.0 - 0.5) << "at t=" << time;
    }
    EXPECT_LT((t.evaluate(route->legs[0].end_s, Derivative::kPosition) - points[1]).norm(), 1e-6);
  }
}

TEST(MissionPointModeConfig, ParsesDescribesAndRefusesOtherValues) {
  auto stop = parseDaemonConfig("[planning]\nmission_point_mode = \"stop\"\n", "stop.toml");
  ASSERT_TRUE(stop.ok()) << stop.error().describe();
  EXPECT_EQ(stop->engine.pipeline.replan.route.trajectory.fixed_waypoint_mode, FixedWaypointMode::kStop);
  auto defaults = parseDaemonConfig("", "empty.toml");
  ASSERT_TRUE(defaults.ok());
  EXPECT_EQ(defaults->engine.pipeline.replan.route.trajectory.fixed_waypoint_mode, FixedWaypointMode::kPass);
  const std::string described = describeDaemonConfig(*stop);
  EXPECT_NE(described.find("mission_point_mode = \"stop\""), std::string::npos) << described;
  auto back = parseDaemonConfig(described, "described.toml");
  ASSERT_TRUE(back.ok()) << back.error().describe();
  EXPECT_EQ(back->engine.pipeline.replan.route.trajectory.fixed_waypoint_mode, FixedWaypointMode::kStop);
  auto bad = parseDaemonConfig("[planning]\nmission_point_mode = \"halt\"\n", "bad.toml");
  ASSERT_FALSE(bad.ok());
  EXPECT_EQ(bad.error().field, "planning.mission_point_mode");
}

}  // namespace
}  // namespace skyroute
