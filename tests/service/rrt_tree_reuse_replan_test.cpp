// RRT* tree reuse in the replanning loop (ReplanOptions::rrt_tree_reuse): on the embedded default
// terrain a route must go round a fixed obstacle (so its first leg grows a real tree); a second
// obstacle then appears ahead of the vehicle, and the replan grows the kept tree, re-rooted at the
// takeover point. The new trajectory is checked independently against both obstacles and the
// terrain every 10 ms up to the goal.
#include <cmath>
#include <cstdio>

#include <gtest/gtest.h>

#include "service/flight_replanner.hpp"
#include "service/moving_obstacle_scenario.hpp"
#include "terrain/terrain_world.hpp"
#include "tests/test_data.hpp"
#include "trajectory/derivative.hpp"

namespace skyroute {
namespace {

Obstacle fixedCylinder(std::uint64_t id, const Eigen::Vector3d& centre_m, double radius_m) {
  Obstacle o;
  o.id = id;
  o.shape = ObstacleShape::kCylinder;
  o.size_m = Eigen::Vector3d(radius_m, 0.0, 20000.0);  // too tall to climb over
  o.center_m = centre_m;
  return o;
}

struct ReplanOutcome {
  ReplanStep step;
  std::size_t first_tree_nodes = 0;
};

// Plans the route round the first obstacle, drops the second one ahead at now_s and replans once.
ReplanOutcome replanAroundANewObstacle(bool tree_reuse) {
  CollisionWorldOptions world_options = seed003ScenarioWorldOptions();
  world_options.ceiling_m = 12000.0;
  auto world = loadTerrainWorld(testing::projectDataPath("default_terrain.tif"), world_options);
  EXPECT_TRUE(world.ok()) << world.error().describe();
  if (!world.ok()) return {};
  const Heightfield& terrain = *world->heightfield;
  const Eigen::AlignedBox2d box = terrain.boundsEn();
  auto above = [&](double e, double n) { return Eigen::Vector3d(e, n, terrain.heightAt(e, n) + 300.0); };
  const double w = box.sizes().x(), north = box.center().y();
  const std::vector<Eigen::Vector3d> points{above(box.min().x() + 0.05 * w, north), above(box.max().x() - 0.05 * w, north)};
  const Obstacle first = fixedCylinder(1, Eigen::Vector3d(box.center().x(), north, 0.0), 0.08 * w);
  world->collision->upsertObstacle(first);

  ReplanOptions options;
  options.route.seed = 3;
  options.route.leg_budget_ms = 0.0;  // iteration budgets: the same result on any machine
  options.route.leg_max_iterations = 3000;
  options.replan_budget_ms = 0.0;
  options.replan_leg_max_iterations = 400;
  options.rrt_tree_reuse = tree_reuse;
  auto replanner = FlightReplanner::start(world->collision, points, seed003ScenarioLimits(), options, 0.0);
  EXPECT_TRUE(replanner.ok()) << replanner.error().describe();
  if (!replanner.ok()) return {};
  FlightReplanner& r = **replanner;
  ReplanOutcome out;
  out.first_tree_nodes = r.route().legs.front().rrt.tree_size;

  const double now_s = 20.0;
  const Eigen::Vector3d ahead = r.stateAt(now_s + 25.0).position_m;
  const Obstacle second = fixedCylinder(2, Eigen::Vector3d(ahead.x(), ahead.y(), 0.0), 400.0);
  world->collision->upsertObstacle(second);
  EXPECT_FALSE(r.clearAhead(now_s, options.horizon_s));
  out.step = r.step(now_s);
  EXPECT_TRUE(out.step.replanned) << (out.step.failure ? out.step.failure->describe() : std::string("no failure"));
  if (!out.step.replanned) return out;
  EXPECT_TRUE(r.clearAhead(now_s, options.horizon_s));
  // Independently, every 10 ms to the goal: outside both obstacles grown by the vehicle radius
  // and above the terrain's clearance.
  for (double t = now_s; t < r.arrivalWorldS(); t += 0.01) {
    const Eigen::Vector3d p = r.stateAt(t).position_m;
    EXPECT_FALSE(first.contains(p, t, world_options.vehicle_radius_m)) << "t=" << t;
    EXPECT_FALSE(second.contains(p, t, world_options.vehicle_radius_m)) << "t=" << t;
    EXPECT_GE(p.z() - terrain.heightAt(p.x(), p.y()), world_options.min_clearance_m - 0.5) << "t=" << t;
    if (::testing::Test::HasFailure()) break;
  }
  EXPECT_LT((r.stateAt(r.arrivalWorldS()).position_m - points.back()).norm(), 1e-3);
  return out;
}

TEST(RrtTreeReuseReplan, ReplanGrowsTheKeptTreeAndIsClear) {
  const ReplanOutcome out = replanAroundANewObstacle(true);
  EXPECT_GT(out.first_tree_nodes, 100u) << "the first leg must grow a real tree round the first obstacle";
  EXPECT_GT(out.step.reused_tree_nodes, 0u) << "the replan did not grow the kept tree";
  std::printf("first tree %zu nodes, replan reused %zu, latency %.1f ms\n", out.first_tree_nodes,
              out.step.reused_tree_nodes, out.step.latency_ms);
}

TEST(RrtTreeReuseReplan, WithoutTheOptionEveryReplanGrowsANewTree) {
  const ReplanOutcome out = replanAroundANewObstacle(false);
  EXPECT_EQ(out.step.reused_tree_nodes, 0u);
  std::printf("latency %.1f ms\n", out.step.latency_ms);
}

}  // namespace
}  // namespace skyroute
