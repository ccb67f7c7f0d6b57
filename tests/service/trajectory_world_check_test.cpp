// The sampled trajectory against a synthetic terrain through the CollisionWorld re-check, verified
// by an independent dense check (the heightfield's height above ground and Obstacle::contains at
// every 0.01 s), with static terrain and a moving obstacle on the world clock.
#include <cmath>

#include <cpl_string.h>
#include <gtest/gtest.h>
#include <ogr_srs_api.h>

#include "terrain/collision_world.hpp"
#include "terrain/dem.hpp"
#include "terrain/heightfield.hpp"
#include "terrain/terrain_generator.hpp"
#include "service/trajectory_world_check.hpp"
#include "trajectory/trajectory_builder.hpp"
#include "tests/terrain_data.hpp"

namespace skyroute {
namespace {

std::string utmWkt() { return testing::epsgWkt(32633); }

struct World {
  std::shared_ptr<const Heightfield> heightfield;
  std::shared_ptr<CollisionWorld> collision;
};

// 160 x 160 cells of 30 m: either a flat plain at 100 m or the project's seeded hilly generator.
World makeWorld(bool hilly) {
  const int n = 160;
  std::vector<float> heights(static_cast<std::size_t>(n) * n, 100.0f);
  if (hilly) {
    TerrainGeneratorOptions g;
    g.width = n;
    g.height = n;
    g.cell_size_m = 30.0;
    g.seed = 77;
    heights = generateTerrainHeights(g);
  }
  auto dem = Dem::fromArray(n, n, heights, {500000.0, 30.0, 0.0, 5200000.0, 0.0, -30.0}, utmWkt(), "synthetic");
  EXPECT_TRUE(dem.ok()) << dem.error().describe();
  auto hf = Heightfield::build(*dem);
  EXPECT_TRUE(hf.ok()) << hf.error().describe();
  CollisionWorldOptions options;
  options.vehicle_radius_m = 5.0;
  options.min_clearance_m = 30.0;
  options.build_octree = false;
  auto world = CollisionWorld::create(*hf, options);
  EXPECT_TRUE(world.ok()) << world.error().describe();
  return {*hf, *world};
}

// Every 0.01 s: inside the DEM and at least the clearance above the (undilated) ground.
int denseTerrainViolations(const Trajectory& t, const Heightfield& hf, double clearance_m) {
  int bad = 0;
  for (double time = 0.0; time <= t.duration_s(); time += 0.01) {
    const auto agl = hf.heightAboveGround(t.evaluate(time, Derivative::kPosition));
    if (!agl || *agl < clearance_m - 1e-6) ++bad;
  }
  return bad;
}

// A path that dives into V-shaped dips just above the clearance and turns hard in plan: straight
// legs that are valid, a curve that rounds the dips below them unless repaired.
std::vector<Eigen::Vector3d> divingPath(const Heightfield& hf) {
  const Eigen::Vector2d c = hf.boundsEn().center();
  const double low = 100.0 + 30.0 + 6.0;  // plain + clearance + a few metres
  return {{c.x() - 2000, c.y() - 1500, 600}, {c.x() - 1200, c.y() - 1200, low}, {c.x() - 700, c.y() - 300, 650},
          {c.x() - 100, c.y() - 900, low},   {c.x() + 500, c.y() + 400, 700},   {c.x() + 1100, c.y() - 200, low},
          {c.x() + 1900, c.y() + 1400, 500}};
}

TEST(TerrainRecheck, RepairedTrajectoryIsClearOfTheTerrainByDenseCheck) {
  const World world = makeWorld(false);
  const auto path = divingPath(*world.heightfield);
  for (std::size_t i = 0; i + 1 < path.size(); ++i)
    ASSERT_TRUE(world.collision->isSegmentValid(path[i], path[i + 1])) << "leg " << i;
  VehicleLimits limits;
  TrajectoryOptions options;
  options.waypoint_spacing_m = 0.0;  // the curve is free to undercut the dips
  options.max_repair_rounds = 30;
  // Without the re-check the curve goes below the clearance (the test's premise)...
  auto unchecked = buildTrajectory(path, limits, options);
  ASSERT_TRUE(unchecked.ok());
  EXPECT_GT(denseTerrainViolations(unchecked->trajectory, *world.heightfield, 30.0), 0);
  // ...and with it, never.
  const MotionCheck check = collisionWorldMotionCheck(world.collision);
  auto checked = buildTrajectory(path, limits, options, &check);
  ASSERT_TRUE(checked.ok());
  EXPECT_EQ(checked->report.status, TrajectoryStatus::kRepaired) << checked->report.failure_reason;
  EXPECT_EQ(denseTerrainViolations(checked->trajectory, *world.heightfield, 30.0), 0);
  for (double t = 0.0; t <= checked->trajectory.duration_s(); t += 0.05)
    ASSERT_TRUE(world.collision->isPointValid(checked->trajectory.evaluate(t, Derivative::kPosition))) << t;
}

TEST(TerrainRecheck, HillyTerrainWithTheLosspoSpacing) {
  const World world = makeWorld(true);
  const Heightfield& hf = *world.heightfield;
  // A zigzag over the hills at 60 m above the highest ground under each leg (checked valid).
  const Eigen::AlignedBox2d box = hf.boundsEn();
  const Eigen::Vector2d lo = box.min() + Eigen::Vector2d(400, 400), hi = box.max() - Eigen::Vector2d(400, 400);
  std::vector<Eigen::Vector2d> plan{lo, {hi.x(), lo.y() + 800}, {lo.x() + 500, 0.5 * (lo.y() + hi.y())},
                                    {hi.x() - 300, hi.y() - 600}, hi};
  auto ground_max = [&](const Eigen::Vector2d& a, const Eigen::Vector2d& b) {
    double m = -1e9;
    for (int k = 0; k <= 400; ++k) m = std::max(m, hf.heightAt(a.x() + (b.x() - a.x()) * k / 400.0, a.y() + (b.y() - a.y()) * k / 400.0));
    return m;
  };
  std::vector<Eigen::Vector3d> path;
  for (std::size_t i = 0; i < plan.size(); ++i) {
    double z = -1e9;
    if (i > 0) z = std::max(z, ground_max(plan[i - 1], plan[i]));
    if (i + 1 < plan.size()) z = std::max(z, ground_max(plan[i], plan[i + 1]));
    path.emplace_back(plan[i].x(), plan[i].y(), z + 60.0);
  }
  for (std::size_t i = 0; i + 1 < path.size(); ++i)
    ASSERT_TRUE(world.collision->isSegmentValid(path[i], path[i + 1])) << "leg " << i;
  const MotionCheck check = collisionWorldMotionCheck(world.collision);
  TrajectoryOptions options;
  options.waypoint_spacing_m = 150.0;
  auto built = buildTrajectory(path, VehicleLimits{}, options, &check);
  ASSERT_TRUE(built.ok());
  EXPECT_NE(built->report.status, TrajectoryStatus::kInfeasible) << built->report.failure_reason;
  EXPECT_EQ(denseTerrainViolations(built->trajectory, hf, 30.0), 0);
}

TEST(TerrainRecheck, MovingObstacleOnTheWorldClock) {
  const World world = makeWorld(false);
  const Eigen::Vector2d c = world.heightfield->boundsEn().center();
  const std::vector<Eigen::Vector3d> path{{c.x() - 2000, c.y(), 400}, {c.x() + 2000, c.y(), 400}};
  auto free_flight = buildTrajectory(path, VehicleLimits{});
  ASSERT_TRUE(free_flight.ok());
  // When does the vehicle pass the centre? The obstacle waits 600 m north until then, then sweeps
  // south across the route at 20 m/s (reaching it 30 s after the vehicle has gone).
  double t_cross = 0.0;
  for (double t = 0; t < free_flight->trajectory.duration_s(); t += 0.01)
    if (free_flight->trajectory.evaluate(t, Derivative::kPosition).x() >= c.x()) { t_cross = t; break; }
  Obstacle sphere;
  sphere.id = 1;
  sphere.shape = ObstacleShape::kSphere;
  sphere.size_m = Eigen::Vector3d::Constant(100.0);
  sphere.motion = BackAndForth{{c.x(), c.y() + 600, 400}, {c.x(), c.y() - 600, 400}, 20.0, t_cross};
  world.collision->upsertObstacle(sphere);

  // Timeless: the sphere's sweep blocks the straight route itself; the report says so.
  const MotionCheck timeless = collisionWorldMotionCheck(world.collision);
  auto blocked = buildTrajectory(path, VehicleLimits{}, {}, &timeless);
  ASSERT_TRUE(blocked.ok());
  EXPECT_EQ(blocked->report.status, TrajectoryStatus::kInfeasible);
  EXPECT_NE(blocked->report.failure_reason.find("itself blocked"), std::string::npos) << blocked->report.failure_reason;

  // On the world clock (trajectory starts at world time 0): clear, confirmed densely.
  const MotionCheck timed = collisionWorldMotionCheck(world.collision, 0.0);
  auto clear = buildTrajectory(path, VehicleLimits{}, {}, &timed);
  ASSERT_TRUE(clear.ok());
  EXPECT_EQ(clear->report.status, TrajectoryStatus::kFeasible) << clear->report.failure_reason;
  for (double t = 0; t <= clear->trajectory.duration_s(); t += 0.01)
    ASSERT_FALSE(sphere.contains(clear->trajectory.evaluate(t, Derivative::kPosition), t, 5.0)) << t;

  // Started 30 s later on the world clock, the vehicle reaches the centre just as the sphere does:
  // the path itself is blocked then, and the dense check agrees that they would meet.
  const MotionCheck late = collisionWorldMotionCheck(world.collision, 30.0);
  auto met = buildTrajectory(path, VehicleLimits{}, {}, &late);
  ASSERT_TRUE(met.ok());
  EXPECT_EQ(met->report.status, TrajectoryStatus::kInfeasible);
  bool meets = false;
  for (double t = 0; t <= met->trajectory.duration_s(); t += 0.01)
    meets = meets || sphere.contains(met->trajectory.evaluate(t, Derivative::kPosition), t + 30.0, 5.0);
  EXPECT_TRUE(meets);
}

}  // namespace
}  // namespace skyroute
