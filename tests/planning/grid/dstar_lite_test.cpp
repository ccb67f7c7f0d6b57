// D* Lite against the Moving AI optimal lengths and, while the start moves and cells change,
// against a fresh Dijkstra on the changed grid.
#include <random>

#include <gtest/gtest.h>

#include "tests/grid_fixtures.hpp"

#include "planning/grid/dstar_lite.hpp"
#include "planning/grid/grid_search.hpp"
#include "terrain/movingai.hpp"
#include "tests/test_data.hpp"

namespace skyroute {
namespace {

using testing::cornerCuttingMoves;

void checkScenario(const std::string& map_path, const std::string& scen_path) {
  const auto scenario = testing::loadMovingAiCase(map_path, scen_path);
  ASSERT_TRUE(scenario);
  for (std::size_t i = 0; i < scenario->problems.size(); ++i) {
    const MovingAiProblem& pr = scenario->problems[i];
    DStarLite search(scenario->grid, pr.start, pr.goal);
    ASSERT_EQ(search.computeShortestPath(), PlannerStatus::kSolved) << "problem " << i;
    EXPECT_NEAR(search.cost(), pr.optimal_length, 1e-3) << "problem " << i;
    const auto path = search.path();
    ASSERT_FALSE(path.empty()) << "problem " << i;
    EXPECT_EQ(path.front(), pr.start);
    EXPECT_EQ(path.back(), pr.goal);
    EXPECT_GT(search.stats().expansions, 0u);
  }
}

TEST(DStarLite, MatchesMovingAiRoom) {
  SKYROUTE_REQUIRE_SHARED(map, "movingai/room-32-32-4.map");
  SKYROUTE_REQUIRE_SHARED(scen, "movingai/room-32-32-4-random-1.scen");
  checkScenario(map, scen);
}

TEST(DStarLite, MatchesMovingAiRandom64) {
  SKYROUTE_REQUIRE_SHARED(map, "movingai/random-64-64-20.map");
  SKYROUTE_REQUIRE_SHARED(scen, "movingai/random-64-64-20-random-1.scen");
  checkScenario(map, scen);
}

TEST(DStarLite, MatchesMovingAiBoston) {
  SKYROUTE_REQUIRE_SHARED(map, "movingai/Boston_0_256.map");
  SKYROUTE_REQUIRE_SHARED(scen, "movingai/Boston_0_256.map.scen");
  checkScenario(map, scen);
}

GridCell randomFree(const GridLayer& grid, std::mt19937& rng) {
  std::uniform_int_distribution<int> ux(0, grid.width() - 1), uy(0, grid.height() - 1);
  for (;;) {
    const GridCell c{ux(rng), uy(rng)};
    if (grid.passable(c)) return c;
  }
}

// Runs body(moves, grid, rng, trial) on `trials` random grids for each move set, the generator
// seeded afresh for each set.
template <class Body>
void onRandomGrids(unsigned seed, int trials, int width, int height, double blocked_share, Body body) {
  for (const GridMoves moves : {GridMoves{}, GridMoves::paper(), cornerCuttingMoves()}) {
    std::mt19937 rng(seed);
    for (int trial = 0; trial < trials; ++trial) {
      GridLayer grid = randomGrid(width, height, blocked_share, rng);
      body(moves, grid, rng, trial);
    }
  }
}

// The vehicle walks towards the goal; every few steps random cells flip (obstacles added and
// removed, never at the vehicle or the goal). After each repair the cost equals Dijkstra's.
TEST(DStarLite, ReplanningMatchesDijkstraWhileStartMovesAndCellsChange) {
  onRandomGrids(42, 8, 50, 40, 0.2, [&](const GridMoves& moves, GridLayer& grid, std::mt19937& rng, int trial) {
    const GridCell start = randomFree(grid, rng);
    const GridCell goal = randomFree(grid, rng);
    DStarLite search(grid, start, goal, moves);
    search.computeShortestPath();
    GridCell at = start;
    int moved = 0;
    for (int step = 0; step < 60 && !(at == goal); ++step) {
      std::vector<GridCell> flip;
      for (int k = 0; k < 6; ++k) {
        const GridCell c{std::uniform_int_distribution<int>(0, grid.width() - 1)(rng),
                         std::uniform_int_distribution<int>(0, grid.height() - 1)(rng)};
        if (!(c == at) && !(c == goal)) flip.push_back(c);
      }
      std::vector<GridCell> changed;
      for (const GridCell& c : flip) {
        const bool now_blocked = grid.staticBlocked(c);
        const std::vector<GridCell> one{c};
        for (const GridCell& d : grid.setStaticBlocked(one, !now_blocked)) changed.push_back(d);
      }
      search.updateCells(changed);
      const PlannerStatus status = search.computeShortestPath();
      const auto field = dijkstraCostField(grid, goal, moves);
      const double expected = field[grid.index(at)];
      if (expected < kInfiniteCost) {
        ASSERT_EQ(status, PlannerStatus::kSolved);
        ASSERT_NEAR(search.cost(), expected, 1e-9) << "trial " << trial << " step " << step;
        at = search.nextCell();
        search.moveStart(at);
        ++moved;
      } else {
        ASSERT_EQ(status, PlannerStatus::kNoPath);
        EXPECT_EQ(search.cost(), kInfiniteCost);
      }
    }
    if (moved > 1) {
      EXPECT_GT(search.km(), 0.0) << "k_m should have grown as the start moved";
    }
  });
}

// The move table, built at once or refreshed cell by cell after changes, allows exactly the moves
// moveCost allows, for each move rule.
TEST(GridMoveTable, MasksMatchMoveCost) {
  std::mt19937 rng(11);
  for (const GridMoves moves : {GridMoves{}, GridMoves::paper(), cornerCuttingMoves()}) {
    GridLayer grid = randomGrid(37, 23, 0.3, rng);
    GridMoveTable table(grid, moves);
    for (int round = 0; round < 2; ++round) {
      for (int y = 0; y < grid.height(); ++y) {
        for (int x = 0; x < grid.width(); ++x) {
          const GridCell c{x, y};
          for (int k = 0; k < 8; ++k) {
            const GridOffset d = kGridOffsets[static_cast<std::size_t>(k)];
            const bool allowed = moveCost(grid, c, d, moves) < kInfiniteCost;
            ASSERT_EQ(((table.mask(grid.index(c)) >> k) & 1u) != 0, allowed) << x << "," << y << " move " << k;
            if (allowed) {
              ASSERT_EQ(table.cost(k), moveCost(grid, c, d, moves));
            }
          }
        }
      }
      // Flip some cells and let the table follow them.
      std::vector<GridCell> changed;
      for (int i = 0; i < 40; ++i) {
        const GridCell c{std::uniform_int_distribution<int>(0, grid.width() - 1)(rng),
                         std::uniform_int_distribution<int>(0, grid.height() - 1)(rng)};
        const std::vector<GridCell> one{c};
        for (const GridCell& d : grid.setStaticBlocked(one, !grid.staticBlocked(c))) changed.push_back(d);
      }
      table.update(changed);
    }
  }
}

// The bucket sweep (dstarSweepInitialize) leaves what D* Lite needs: g of every settled cell is
// Dijkstra's, rhs is the minimum over the successors everywhere, every inconsistent cell is in the
// frontier queue once, a search from any start stops at once, and repairs after changes are exact.
TEST(DStarLite, SweepLeavesAStateThatRepairsExactly) {
  onRandomGrids(7, 6, 60, 50, 0.25, [&](const GridMoves& moves, GridLayer& grid, std::mt19937& rng, int trial) {
    const GridCell goal = randomFree(grid, rng);
    std::vector<GridCell> starts;
    for (int k = 0; k < 5; ++k) starts.push_back(randomFree(grid, rng));
    const auto exact = dijkstraCostField(grid, goal, moves);
    bool all_reached = true;
    for (const GridCell& s : starts) all_reached = all_reached && exact[grid.index(s)] < kInfiniteCost;
    DStarGoalField field(grid, goal, moves);
    DStarQueue frontier(starts.front(), 0.0);
    SearchStats stats;
    const PlannerStatus status = dstarSweepInitialize(field, starts, frontier, stats, {});
    ASSERT_EQ(status, all_reached ? PlannerStatus::kSolved : PlannerStatus::kNoPath) << "trial " << trial;
    double farthest = 0.0;
    for (const GridCell& s : starts) {
      const double e = exact[grid.index(s)];
      if (e < kInfiniteCost) {
        ASSERT_NEAR(field.costFrom(s), e, 1e-9);
        farthest = std::max(farthest, e);
      } else {
        EXPECT_EQ(field.costFrom(s), kInfiniteCost);
      }
    }
    std::size_t inconsistent = 0;
    for (std::size_t i = 0; i < grid.cellCount(); ++i) {
      if (field.g(i) < kInfiniteCost) {
        ASSERT_NEAR(field.g(i), exact[i], 1e-9) << "cell " << i;
      }
      if (i != field.goalIndex()) {
        ASSERT_TRUE(costEqual(field.rhs(i), field.bestRhs(i))) << "cell " << i;
      }
      if (!field.consistent(i)) {
        ++inconsistent;
        EXPECT_GE(field.rhs(i), farthest) << "an open cell below a start's cost";
      }
    }
    EXPECT_EQ(frontier.size(), inconsistent);
    EXPECT_GT(stats.expansions, 0u);
    // Each start's queue: a copy re-keyed for it; the search has nothing left to do.
    for (const GridCell& s : starts) {
      DStarQueue q = frontier;
      q.setStart(s);
      q.adapt(field, stats);
      const auto before = stats.expansions;
      dstarComputeShortestPath(field, q, stats, {});
      EXPECT_EQ(stats.expansions, before);
    }
    // Then the seed's repair from that state, for the first start, while cells flip.
    DStarQueue q = frontier;
    q.adapt(field, stats);
    DStarQueue* const queues[] = {&q};
    for (int round = 0; round < 5; ++round) {
      std::vector<GridCell> changed;
      for (int k = 0; k < 10; ++k) {
        const GridCell c{std::uniform_int_distribution<int>(0, grid.width() - 1)(rng),
                         std::uniform_int_distribution<int>(0, grid.height() - 1)(rng)};
        if (c == goal || c == starts.front()) continue;
        const std::vector<GridCell> one{c};
        for (const GridCell& d : grid.setStaticBlocked(one, !grid.staticBlocked(c))) changed.push_back(d);
      }
      dstarUpdateChangedCells(field, changed, queues, stats);
      dstarComputeShortestPath(field, q, stats, {});
      const double e = dijkstraCostField(grid, goal, moves)[grid.index(starts.front())];
      if (e < kInfiniteCost) {
        ASSERT_NEAR(field.costFrom(starts.front()), e, 1e-9) << "trial " << trial << " round " << round;
      } else {
        ASSERT_EQ(field.costFrom(starts.front()), kInfiniteCost);
      }
    }
  });
}

TEST(DStarLite, ReplanningExpandsFarFewerCellsThanPlanningAgain) {
  std::mt19937 rng(5);
  GridLayer grid = randomGrid(120, 120, 0.2, rng);
  const GridCell start{5, 5}, goal{110, 110};
  grid.setStaticBlocked(std::vector<GridCell>{start, goal}, false);
  DStarLite search(grid, start, goal);
  ASSERT_EQ(search.computeShortestPath(), PlannerStatus::kSolved);
  const auto first = search.stats().expansions;
  // Block one cell on the current path, near the start.
  const auto path = search.path();
  ASSERT_GT(path.size(), 4u);
  const auto changed = grid.setStaticBlocked(std::vector<GridCell>{path[3]}, true);
  search.updateCells(changed);
  ASSERT_EQ(search.computeShortestPath(), PlannerStatus::kSolved);
  const auto repair = search.stats().expansions - first;
  EXPECT_NEAR(search.cost(), dijkstraCostField(grid, goal)[grid.index(start)], 1e-9);
  EXPECT_LT(repair, first / 2) << "repair " << repair << " first " << first;
}

TEST(DStarLite, InvalidEndpointsAndUnreachableGoal) {
  GridLayer grid(10, 10);
  grid.setStaticBlocked(std::vector<GridCell>{{3, 3}}, true);
  EXPECT_EQ(DStarLite(grid, {3, 3}, {0, 0}).computeShortestPath(), PlannerStatus::kStartInvalid);
  EXPECT_EQ(DStarLite(grid, {0, 0}, {3, 3}).computeShortestPath(), PlannerStatus::kGoalInvalid);
  EXPECT_EQ(DStarLite(grid, {0, 0}, {20, 3}).computeShortestPath(), PlannerStatus::kGoalInvalid);
  // Wall off column 5 completely.
  std::vector<GridCell> wall;
  for (int y = 0; y < 10; ++y) wall.push_back({5, y});
  grid.setStaticBlocked(wall, true);
  DStarLite cut(grid, {0, 0}, {9, 9});
  EXPECT_EQ(cut.computeShortestPath(), PlannerStatus::kNoPath);
  EXPECT_TRUE(cut.path().empty());
}

}  // namespace
}  // namespace skyroute
