// The mission planner end to end: clear errors for bad points, a plan whose order is optimal for
// its matrix (brute force) and whose legs are real paths, and a full flight with sensing and
// replanning where each replanned matrix matches Dijkstra and both algorithms agree.
#include <algorithm>
#include <cmath>
#include <numeric>
#include <optional>
#include <random>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "tests/grid_fixtures.hpp"

#include "planning/grid/grid_search.hpp"
#include "planning/mission/mission_planner.hpp"

namespace skyroute {
namespace {

TEST(MissionPlanner, BadPointsGetClearErrors) {
  GridLayer grid(20, 20);
  grid.setStaticBlocked(std::vector<GridCell>{{5, 5}}, true);
  std::vector<GridCell> wall;  // closes the corner cell (19, 19)
  wall.push_back({18, 19});
  wall.push_back({18, 18});
  wall.push_back({19, 18});
  grid.setStaticBlocked(wall, true);

  struct Refused {
    GridCell begin;
    std::vector<GridCell> points;
    GridCell end;
    std::optional<ErrorCode> code;  // nullopt: any code
    std::string field;
    std::string says;  // "" = anything
  };
  const Refused cases[] = {
      {{0, 0}, {{3, 3}, {25, 2}}, {10, 10}, ErrorCode::kOutsideMap, "points[1]", "(25, 2)"},
      {{0, 0}, {{5, 5}}, {10, 10}, ErrorCode::kOccupied, "points[0]", ""},
      {{-1, 0}, {{3, 3}}, {10, 10}, std::nullopt, "begin", ""},
      {{0, 0}, {{3, 3}, {19, 19}}, {10, 10}, ErrorCode::kUnreachable, "points[1]", ""},
      {{0, 0}, {{3, 3}, {7, 7}, {3, 3}}, {10, 10}, ErrorCode::kInvalidArgument, "points[2]", "points[0]"},
      {{0, 0}, {{10, 10}}, {10, 10}, std::nullopt, "end", ""},
  };
  for (const Refused& c : cases) {
    auto refused = MissionPlanner::create(grid, c.begin, c.points, c.end);
    ASSERT_FALSE(refused.ok()) << c.field;
    if (c.code) {
      EXPECT_EQ(refused.error().code, *c.code) << c.field;
    }
    EXPECT_EQ(refused.error().field, c.field);
    EXPECT_NE(refused.error().message.find(c.says), std::string::npos) << refused.error().message;
  }

  // A round trip (begin == end) is allowed.
  EXPECT_TRUE(MissionPlanner::create(grid, {0, 0}, {{3, 3}}, {0, 0}).ok());
}

TEST(MissionPlanner, PlanIsOptimalForItsMatrixAndLegsArePaths) {
  std::mt19937 rng(17);
  GridLayer grid = randomGrid(50, 50, 0.15, rng);
  std::vector<GridCell> pts{{2, 2}, {45, 5}, {10, 40}, {30, 30}, {5, 25}, {47, 47}};
  grid.setStaticBlocked(pts, false);
  const GridCell begin = pts.front(), end = pts.back();
  const std::vector<GridCell> missions(pts.begin() + 1, pts.end() - 1);
  // MMD*L, per-pair D* Lite, and MMD*L planning its goals by the bucket sweep (4 starts each).
  std::uint64_t seed_expansions = 0;
  for (int variant = 0; variant < 3; ++variant) {
    MissionOptions options;
    options.algorithm = variant == 1 ? MissionAlgorithm::kDStarLite : MissionAlgorithm::kMmdStarLite;
    options.sweep_min_cells = variant == 2 ? 1 : 0;
    auto planner = MissionPlanner::create(grid, begin, missions, end, options);
    ASSERT_TRUE(planner.ok()) << planner.error().describe();
    auto plan = planner->preplan();
    ASSERT_TRUE(plan.ok()) << plan.error().describe();
    ASSERT_EQ(plan->order.size(), pts.size());
    EXPECT_EQ(plan->order.front(), 0);
    EXPECT_EQ(plan->order.back(), 5);
    // Brute force over the matrix.
    std::vector<int> inner{1, 2, 3, 4};
    double best = kInfiniteCost;
    do {
      double c = plan->cost_matrix[0][inner[0]] + plan->cost_matrix[inner.back()][5];
      for (std::size_t i = 1; i < inner.size(); ++i) c += plan->cost_matrix[inner[i - 1]][inner[i]];
      best = std::min(best, c);
    } while (std::next_permutation(inner.begin(), inner.end()));
    EXPECT_NEAR(plan->cost, best, 1e-9);
    // Matrix entries against Dijkstra.
    for (int to = 1; to <= 5; ++to) {
      const auto field = dijkstraCostField(grid, pts[to]);
      for (int from = 0; from <= 4; ++from) {
        if (from == to || (from == 0 && to == 5)) {
          EXPECT_EQ(plan->cost_matrix[from][to], kInfiniteCost);
          continue;
        }
        EXPECT_NEAR(plan->cost_matrix[from][to], field[grid.index(pts[from])], 1e-9);
      }
    }
    double legs = 0.0;
    for (const MissionLeg& leg : plan->legs) {
      ASSERT_FALSE(leg.cells.empty());
      EXPECT_EQ(leg.cells.front(), pts[leg.from_point]);
      EXPECT_EQ(leg.cells.back(), pts[leg.to_point]);
      legs += leg.cost;
    }
    EXPECT_NEAR(legs, plan->cost, 1e-9);
    EXPECT_GT(plan->search.expansions, 0u);
    if (variant == 0) seed_expansions = plan->search.expansions;
    if (variant == 2) {
      EXPECT_NE(plan->search.expansions, seed_expansions) << "the sweep option did not reach MMD*L";
    }
  }
}

// The seed's replanning scenario in small: obstacles unknown to the planner appear in the real
// world; the vehicle senses its 8 neighbours each step and both planners replan. Their matrices
// stay equal to each other and to Dijkstra on the known grid, and the vehicle reaches E.
TEST(MissionPlanner, FlightWithSensingAndReplanning) {
  std::mt19937 rng(31);
  int finished = 0;
  for (int trial = 0; trial < 5; ++trial) {
    GridLayer known = randomGrid(60, 60, 0.2, rng);
    GridLayer truth = known;
    const GridCell begin{20, 20}, end{40, 40};
    std::vector<GridCell> missions;
    std::uniform_int_distribution<int> u(0, 59);
    std::vector<GridCell> clear{begin, end};
    known.setStaticBlocked(clear, false);
    truth.setStaticBlocked(clear, false);
    const auto reach = reachableCells(known, begin);
    if (std::count(reach.begin(), reach.end(), std::uint8_t{1}) < 200) continue;
    while (missions.size() < 4) {
      const GridCell c{u(rng), u(rng)};
      if (known.passable(c) && reach[known.index(c)] && !(c == begin) && !(c == end) &&
          std::find(missions.begin(), missions.end(), c) == missions.end())
        missions.push_back(c);
    }
    // Extra obstacles in 10 % of the free cells, only in the real world.
    std::vector<GridCell> extra;
    std::bernoulli_distribution add(0.1);
    for (int y = 0; y < 60; ++y)
      for (int x = 0; x < 60; ++x) {
        const GridCell c{x, y};
        if (truth.passable(c) && add(rng) && !(c == begin) && !(c == end) &&
            std::find(missions.begin(), missions.end(), c) == missions.end())
          extra.push_back(c);
      }
    truth.setStaticBlocked(extra, true);
    const auto true_reach = reachableCells(truth, begin);
    bool feasible = true_reach[truth.index(end)];
    for (const GridCell& m : missions) feasible = feasible && true_reach[truth.index(m)];
    if (!feasible) continue;

    MissionOptions mmd_opt, dsl_opt;
    dsl_opt.algorithm = MissionAlgorithm::kDStarLite;
    auto mmd = MissionPlanner::create(known, begin, missions, end, mmd_opt);
    auto dsl = MissionPlanner::create(known, begin, missions, end, dsl_opt);
    ASSERT_TRUE(mmd.ok() && dsl.ok());
    ASSERT_TRUE(mmd->preplan().ok());
    ASSERT_TRUE(dsl->preplan().ok());
    for (int step = 0; step < 2000 && !mmd->finished(); ++step) {
      const GridCell next = mmd->nextCell();
      ASSERT_TRUE(truth.passable(next));
      mmd->moveVehicle(next);
      dsl->moveVehicle(next);
      std::vector<GridCell> sensed;
      for (int dy = -1; dy <= 1; ++dy)
        for (int dx = -1; dx <= 1; ++dx) {
          const GridCell c{next.x + dx, next.y + dy};
          if (known.inside(c) && truth.blocked(c) && known.passable(c)) sensed.push_back(c);
        }
      if (sensed.empty() || mmd->finished()) continue;
      const auto changed = known.setStaticBlocked(sensed, true);
      auto a = mmd->replan(changed);
      auto b = dsl->replan(changed);
      ASSERT_TRUE(a.ok()) << a.error().describe();
      ASSERT_TRUE(b.ok()) << b.error().describe();
      for (std::size_t i = 0; i < a->cost_matrix.size(); ++i)
        for (std::size_t j = 0; j < a->cost_matrix.size(); ++j)
          ASSERT_TRUE(a->cost_matrix[i][j] == b->cost_matrix[i][j] ||
                      std::abs(a->cost_matrix[i][j] - b->cost_matrix[i][j]) < 1e-9)
              << i << " -> " << j << " step " << step;
      EXPECT_NEAR(a->cost, b->cost, 1e-9);
      const int first = a->order[1];
      const auto field = dijkstraCostField(known, mmd->search().points()[first]);
      EXPECT_NEAR(a->cost_matrix[a->order[0]][first], field[known.index(next)], 1e-9);
    }
    EXPECT_TRUE(mmd->finished());
    EXPECT_EQ(mmd->vehicleCell(), end);
    ++finished;
  }
  EXPECT_GT(finished, 0);
}

TEST(MissionPlanner, ReplanReportsAPointThatWasCutOff) {
  GridLayer grid(20, 20);
  auto planner = MissionPlanner::create(grid, {0, 0}, {{15, 15}, {5, 5}}, {19, 0});
  ASSERT_TRUE(planner.ok());
  ASSERT_TRUE(planner->preplan().ok());
  std::vector<GridCell> ring;
  for (int dy = -1; dy <= 1; ++dy)
    for (int dx = -1; dx <= 1; ++dx)
      if (dx || dy) ring.push_back({15 + dx, 15 + dy});
  const auto changed = grid.setStaticBlocked(ring, true);
  auto plan = planner->replan(changed);
  ASSERT_FALSE(plan.ok());
  EXPECT_EQ(plan.error().code, ErrorCode::kUnreachable);
  EXPECT_EQ(plan.error().field, "points[0]");
}

}  // namespace
}  // namespace skyroute
