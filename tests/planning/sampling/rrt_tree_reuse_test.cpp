// Re-rooting an RRT* tree at a takeover point after the world changed, and planning on from it.
// Kept edges are checked against the changed world with an independent dense point check, and
// kept costs against path lengths recomputed here from the positions.
#include "planning/sampling/rrt_tree_reuse.hpp"

#include <cmath>
#include <set>
#include <tuple>

#include <gtest/gtest.h>

#include "planning/sampling/rrt_star.hpp"
#include "tests/planning/synthetic_worlds.hpp"

namespace skyroute {
namespace {

using testing::BoxWorld;

const Eigen::Vector3d kStart(20, 30, 10), kGoal(80, 30, 10);

// The wall world with a new obstacle across the lower left, where the first tree has many edges.
BoxWorld changedWallWorld() {
  BoxWorld w = testing::wallWorld();
  w.addSphere(Eigen::Vector3d(30, 15, 10), 9.0);
  return w;
}

struct FirstPlan {
  RrtStarResult result;
  RrtTree tree;
};

FirstPlan firstPlan(std::uint64_t seed) {
  const BoxWorld world = testing::wallWorld();
  RrtStarOptions options;
  options.seed = seed;
  FirstPlan out;
  auto r = RrtStar(world, options).plan(kStart, kGoal, TerminationCondition().withIterationBudget(2000),
                                        TerminationCondition(), &out.tree);
  EXPECT_TRUE(r.ok());
  if (r.ok()) out.result = *r;
  return out;
}

// The point a quarter of the way along a path (where a vehicle flying it would take over).
Eigen::Vector3d alongPath(const std::vector<Eigen::Vector3d>& path, double share) {
  double left = share * polylineLength(path);
  for (std::size_t i = 0; i + 1 < path.size(); ++i) {
    const double len = (path[i + 1] - path[i]).norm();
    if (left <= len) return path[i] + (path[i + 1] - path[i]) * (left / len);
    left -= len;
  }
  return path.back();
}

// Path length from the root along the parents, summed here from the positions.
double branchLength(const RrtTree& tree, std::size_t node) {
  double length = 0.0;
  for (std::size_t v = node; v != 0; v = tree.parents[v]) length += (tree.positions_m[v] - tree.positions_m[tree.parents[v]]).norm();
  return length;
}

std::set<std::tuple<double, double, double>> positionsOf(const RrtTree& tree) {
  std::set<std::tuple<double, double, double>> out;
  for (const Eigen::Vector3d& p : tree.positions_m) out.emplace(p.x(), p.y(), p.z());
  return out;
}

TEST(RrtTreeReuse, PlannerExportsItsTreeWithParentsFirstAndTrueCosts) {
  const FirstPlan first = firstPlan(1);
  ASSERT_TRUE(first.result.solved());
  ASSERT_EQ(first.tree.size(), first.result.tree_size);
  EXPECT_FALSE(first.tree.layoutError().has_value());
  EXPECT_EQ(first.tree.positions_m.front(), kStart);
  const BoxWorld world = testing::wallWorld();
  for (std::size_t i = 1; i < first.tree.size(); ++i) {
    ASSERT_NEAR(first.tree.costs_m[i], branchLength(first.tree, i), 1e-6) << "node " << i;
    ASSERT_TRUE(world.denseCheck({first.tree.positions_m[first.tree.parents[i]], first.tree.positions_m[i]}, 0.05));
  }
}

TEST(RrtTreeReuse, RerootedTreeKeepsOnlyValidEdgesWithTrueCostsFromTheNewRoot) {
  const BoxWorld changed = changedWallWorld();
  for (std::uint64_t seed = 1; seed <= 3; ++seed) {
    const FirstPlan first = firstPlan(seed);
    ASSERT_TRUE(first.result.solved());
    const Eigen::Vector3d takeover = alongPath(first.result.path_m, 0.25);
    auto rerooted = rerootTree(first.tree, takeover, changed);
    ASSERT_TRUE(rerooted.ok()) << rerooted.error().describe();
    const RrtTree& tree = rerooted->tree;
    EXPECT_FALSE(tree.layoutError().has_value());
    EXPECT_EQ(tree.positions_m.front(), takeover);
    EXPECT_GT(rerooted->kept_nodes, first.tree.size() / 4) << "seed " << seed;
    EXPECT_GT(rerooted->blocked_edges, 0u) << "the new sphere crosses some of the first tree's edges";
    EXPECT_GT(rerooted->dropped_nodes, 0u);
    EXPECT_EQ(rerooted->kept_nodes + rerooted->dropped_nodes, first.tree.size());
    EXPECT_EQ(tree.size(), rerooted->kept_nodes + 1);
    const auto old_positions = positionsOf(first.tree);
    for (std::size_t i = 1; i < tree.size(); ++i) {
      const Eigen::Vector3d& a = tree.positions_m[tree.parents[i]];
      const Eigen::Vector3d& b = tree.positions_m[i];
      ASSERT_TRUE(changed.denseCheck({a, b}, 0.05)) << "seed " << seed << ": kept edge into node " << i
                                                      << " crosses an obstacle";
      ASSERT_TRUE(old_positions.count({b.x(), b.y(), b.z()})) << "node " << i << " is not an old node";
      ASSERT_NEAR(tree.costs_m[i], branchLength(tree, i), 1e-6) << "seed " << seed << " node " << i;
    }
  }
}

TEST(RrtTreeReuse, NodeCapKeepsTheCheapestPartStillATree) {
  const FirstPlan first = firstPlan(2);
  ASSERT_TRUE(first.result.solved());
  const BoxWorld changed = changedWallWorld();
  const Eigen::Vector3d takeover = alongPath(first.result.path_m, 0.25);
  TreeReuseOptions options;
  options.max_nodes = 50;
  auto capped = rerootTree(first.tree, takeover, changed, options);
  auto whole = rerootTree(first.tree, takeover, changed);
  ASSERT_TRUE(capped.ok() && whole.ok());
  ASSERT_EQ(capped->tree.size(), 50u);
  EXPECT_FALSE(capped->tree.layoutError().has_value());
  // The 49 kept are the 49 cheapest of the uncapped tree (Dijkstra order), with the same costs.
  std::vector<double> capped_costs(capped->tree.costs_m.begin(), capped->tree.costs_m.end());
  std::vector<double> cheapest(whole->tree.costs_m.begin(), whole->tree.costs_m.end());
  std::sort(cheapest.begin(), cheapest.end());
  cheapest.resize(50);
  std::sort(capped_costs.begin(), capped_costs.end());
  for (std::size_t i = 0; i < 50; ++i) EXPECT_NEAR(capped_costs[i], cheapest[i], 1e-9);
}

TEST(RrtTreeReuse, ReplanFromTheRerootedTreeNeedsFewerNewSamples) {
  const BoxWorld changed = changedWallWorld();
  std::uint64_t reused_first = 0, fresh_first = 0;
  for (std::uint64_t seed = 1; seed <= 5; ++seed) {
    const FirstPlan first = firstPlan(seed);
    ASSERT_TRUE(first.result.solved());
    const Eigen::Vector3d takeover = alongPath(first.result.path_m, 0.25);
    auto rerooted = rerootTree(first.tree, takeover, changed);
    ASSERT_TRUE(rerooted.ok());
    RrtStarOptions options;
    options.seed = 100 + seed;
    const RrtStar planner(changed, options);
    const TerminationCondition budget = TerminationCondition().withIterationBudget(3000);
    auto reused = planner.planFromTree(rerooted->tree, kGoal, budget, TerminationCondition());
    auto fresh = planner.plan(takeover, kGoal, budget);
    ASSERT_TRUE(reused.ok() && fresh.ok());
    ASSERT_TRUE(reused->solved()) << "seed " << seed;
    ASSERT_TRUE(fresh->solved()) << "seed " << seed;
    EXPECT_EQ(reused->seeded_nodes, rerooted->tree.size());
    EXPECT_TRUE(changed.denseCheck(reused->path_m, 0.05)) << "seed " << seed;
    EXPECT_EQ(reused->path_m.front(), takeover);
    EXPECT_EQ(reused->path_m.back(), kGoal);
    EXPECT_LE(reused->first_solution_iteration, fresh->first_solution_iteration) << "seed " << seed;
    reused_first += reused->first_solution_iteration;
    fresh_first += fresh->first_solution_iteration;
  }
  EXPECT_LT(reused_first, fresh_first);
}

TEST(RrtTreeReuse, BadTreesAndRootsAreErrorsNamingTheField) {
  const BoxWorld world = testing::wallWorld();
  RrtTree bad{{kStart, kGoal}, {kRrtTreeNoParent, 1}, {0.0, 1.0}};  // node 1 its own parent
  auto r = rerootTree(bad, kStart, world);
  ASSERT_FALSE(r.ok());
  EXPECT_EQ(r.error().field, "old_tree");
  RrtTree good{{kStart}, {kRrtTreeNoParent}, {0.0}};
  r = rerootTree(good, Eigen::Vector3d(NAN, 0, 0), world);
  ASSERT_FALSE(r.ok());
  EXPECT_EQ(r.error().field, "new_root_m");
  r = rerootTree(good, kStart, world, TreeReuseOptions{.max_nodes = 0});
  ASSERT_FALSE(r.ok());
  EXPECT_EQ(r.error().field, "max_nodes");
  const RrtStar planner(world);
  auto p = planner.planFromTree(RrtTree{}, kGoal, TerminationCondition().withIterationBudget(10), TerminationCondition());
  ASSERT_FALSE(p.ok());
  EXPECT_EQ(p.error().field, "seed_tree");
  p = planner.planFromTree(bad, kGoal, TerminationCondition().withIterationBudget(10), TerminationCondition());
  ASSERT_FALSE(p.ok());
  EXPECT_EQ(p.error().field, "seed_tree");
  // A root inside an obstacle keeps nothing.
  auto inside = rerootTree(good, Eigen::Vector3d(50, 30, 10), world);
  ASSERT_TRUE(inside.ok());
  EXPECT_EQ(inside->tree.size(), 1u);
  EXPECT_EQ(inside->kept_nodes, 0u);
}

}  // namespace
}  // namespace skyroute
