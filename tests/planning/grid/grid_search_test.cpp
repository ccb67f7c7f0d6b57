// A*, Dijkstra and the move rules against the Moving AI optimal lengths (independent reference)
// and against each other.
#include <cmath>
#include <random>

#include <gtest/gtest.h>

#include "planning/grid/grid_search.hpp"
#include "terrain/movingai.hpp"
#include "tests/grid_fixtures.hpp"
#include "tests/test_data.hpp"

namespace skyroute {
namespace {

void expectValidPath(const GridLayer& grid, const GridPath& p, const GridMoves& moves) {
  ASSERT_FALSE(p.cells.empty());
  double sum = 0.0;
  for (std::size_t i = 1; i < p.cells.size(); ++i) {
    const GridOffset d{p.cells[i].x - p.cells[i - 1].x, p.cells[i].y - p.cells[i - 1].y};
    ASSERT_LE(std::abs(d.dx), 1);
    ASSERT_LE(std::abs(d.dy), 1);
    const double c = moveCost(grid, p.cells[i - 1], d, moves);
    ASSERT_LT(c, kInfiniteCost) << "illegal move at step " << i;
    sum += c;
  }
  EXPECT_NEAR(sum, p.cost, 1e-9);
}

void checkScenario(const std::string& map_path, const std::string& scen_path, std::size_t stride) {
  const auto scenario = testing::loadMovingAiCase(map_path, scen_path);
  ASSERT_TRUE(scenario);
  const GridLayer& grid = scenario->grid;
  for (std::size_t i = 0; i < scenario->problems.size(); i += stride) {
    const MovingAiProblem& pr = scenario->problems[i];
    const GridPath a = astarSearch(grid, pr.start, pr.goal);
    ASSERT_EQ(a.status, SearchStatus::kFound) << "problem " << i;
    EXPECT_NEAR(a.cost, pr.optimal_length, 1e-3) << "A* problem " << i;
    expectValidPath(grid, a, GridMoves{});
    const GridPath d = dijkstraSearch(grid, pr.start, pr.goal);
    EXPECT_NEAR(d.cost, pr.optimal_length, 1e-3) << "Dijkstra problem " << i;
    EXPECT_LE(a.stats.expansions, d.stats.expansions) << "problem " << i;
  }
}

TEST(GridSearch, AStarAndDijkstraMatchMovingAiRoom) {
  SKYROUTE_REQUIRE_SHARED(map, "movingai/room-32-32-4.map");
  SKYROUTE_REQUIRE_SHARED(scen, "movingai/room-32-32-4-random-1.scen");
  checkScenario(map, scen, 1);
}

TEST(GridSearch, AStarAndDijkstraMatchMovingAiRandom64) {
  SKYROUTE_REQUIRE_SHARED(map, "movingai/random-64-64-20.map");
  SKYROUTE_REQUIRE_SHARED(scen, "movingai/random-64-64-20-random-1.scen");
  checkScenario(map, scen, 1);
}

TEST(GridSearch, AStarMatchesMovingAiBostonSample) {
  SKYROUTE_REQUIRE_SHARED(map, "movingai/Boston_0_256.map");
  SKYROUTE_REQUIRE_SHARED(scen, "movingai/Boston_0_256.map.scen");
  checkScenario(map, scen, 7);
}

TEST(GridSearch, NoCornerCutting) {
  GridLayer grid(3, 3);
  const std::vector<GridCell> wall{{1, 0}};
  grid.setStaticBlocked(wall, true);
  // (0,0) -> (1,1) would cut the blocked corner (1,0): it must go round through (0,1).
  EXPECT_EQ(moveCost(grid, {0, 0}, {1, 1}, GridMoves{}), kInfiniteCost);
  const GridPath p = astarSearch(grid, {0, 0}, {1, 1});
  ASSERT_EQ(p.status, SearchStatus::kFound);
  EXPECT_DOUBLE_EQ(p.cost, 2.0);
}

TEST(GridSearch, CornerCuttingOptionOnlyNeedsBothEndsFree) {
  GridLayer grid(3, 3);
  const std::vector<GridCell> walls{{1, 0}, {0, 1}};
  grid.setStaticBlocked(walls, true);
  GridMoves cut = GridMoves::paper();
  cut.corner_cutting = true;
  // Both orthogonal cells blocked: only the corner-cutting rule lets (0,0) reach (1,1) at all.
  EXPECT_EQ(moveCost(grid, {0, 0}, {1, 1}, GridMoves::paper()), kInfiniteCost);
  EXPECT_DOUBLE_EQ(moveCost(grid, {0, 0}, {1, 1}, cut), 1.4);
  EXPECT_EQ(astarSearch(grid, {0, 0}, {2, 2}, GridMoves::paper()).status, SearchStatus::kNoPath);
  const GridPath p = astarSearch(grid, {0, 0}, {2, 2}, cut);
  ASSERT_EQ(p.status, SearchStatus::kFound);
  EXPECT_NEAR(p.cost, 2.8, 1e-12);
  // A blocked end still forbids the move.
  EXPECT_EQ(moveCost(grid, {0, 0}, {1, 0}, cut), kInfiniteCost);
}

// The move table the incremental searches walk must say exactly what moveCost says, after
// reported changes (update) and after changes it was not told about (sync).
TEST(GridSearch, MoveTableFollowsTheGrid) {
  std::mt19937 rng(5);
  for (const bool cut : {false, true}) {
    GridMoves moves;
    moves.corner_cutting = cut;
    GridLayer grid(23, 17);
    GridMoveTable table(grid, moves);
    auto expectSame = [&](const char* when) {
      for (int y = 0; y < grid.height(); ++y)
        for (int x = 0; x < grid.width(); ++x)
          for (int k = 0; k < 8; ++k) {
            const double c = moveCost(grid, {x, y}, kGridOffsets[static_cast<std::size_t>(k)], moves);
            const bool allowed = (table.mask(grid.index({x, y})) >> k) & 1u;
            ASSERT_EQ(allowed, c < kInfiniteCost) << when << " at (" << x << ", " << y << ") move " << k;
            if (allowed) {
              ASSERT_EQ(table.cost(k), c);
              const GridOffset d = kGridOffsets[static_cast<std::size_t>(k)];
              ASSERT_EQ(static_cast<std::ptrdiff_t>(grid.index({x, y})) + table.delta(k),
                        static_cast<std::ptrdiff_t>(grid.index({x + d.dx, y + d.dy})));
            }
          }
    };
    expectSame("empty");
    std::uniform_int_distribution<int> ux(0, grid.width() - 1), uy(0, grid.height() - 1);
    for (int round = 0; round < 20; ++round) {
      std::vector<GridCell> flip;
      for (int k = 0; k < 15; ++k) flip.push_back({ux(rng), uy(rng)});
      std::vector<GridCell> changed;
      for (const GridCell& c : flip) {
        const std::vector<GridCell> one{c};
        for (const GridCell& d : grid.setStaticBlocked(one, !grid.staticBlocked(c))) changed.push_back(d);
      }
      if (round % 4 == 3) {
        table.sync();  // not told which cells changed
      } else {
        table.update(changed);
      }
      expectSame(round % 4 == 3 ? "after sync" : "after update");
    }
  }
}

TEST(GridSearch, PaperMovesUseDiagonal14) {
  GridLayer grid(10, 10);
  const GridPath p = astarSearch(grid, {0, 0}, {4, 3}, GridMoves::paper());
  EXPECT_NEAR(p.cost, 1.0 + 3 * 1.4, 1e-12);
  EXPECT_DOUBLE_EQ(GridMoves::paper().estimate({0, 0}, {4, 3}), 4.0);
}

TEST(GridSearch, DijkstraFieldAgreesWithAStarOnRandomGrids) {
  std::mt19937 rng(7);
  for (int trial = 0; trial < 5; ++trial) {
    GridLayer grid(40, 30);
    std::vector<GridCell> blocked;
    std::bernoulli_distribution wall(0.25);
    for (int y = 0; y < grid.height(); ++y)
      for (int x = 0; x < grid.width(); ++x)
        if (wall(rng)) blocked.push_back({x, y});
    grid.setStaticBlocked(blocked, true);
    std::uniform_int_distribution<int> ux(0, 39), uy(0, 29);
    GridCell s{ux(rng), uy(rng)};
    while (grid.blocked(s)) s = {ux(rng), uy(rng)};
    const auto field = dijkstraCostField(grid, s);
    for (int k = 0; k < 40; ++k) {
      const GridCell g{ux(rng), uy(rng)};
      const GridPath p = astarSearch(grid, s, g);
      if (grid.blocked(g)) {
        EXPECT_EQ(p.status, SearchStatus::kInvalidGoal);
      } else if (field[grid.index(g)] < kInfiniteCost) {
        ASSERT_EQ(p.status, SearchStatus::kFound);
        EXPECT_NEAR(p.cost, field[grid.index(g)], 1e-9);
      } else {
        EXPECT_EQ(p.status, SearchStatus::kNoPath);
      }
    }
  }
}

TEST(GridSearch, BadEndpointsAndTermination) {
  GridLayer grid(5, 5);
  EXPECT_EQ(astarSearch(grid, {-1, 0}, {2, 2}).status, SearchStatus::kInvalidStart);
  EXPECT_EQ(astarSearch(grid, {0, 0}, {5, 2}).status, SearchStatus::kInvalidGoal);
  auto cancel = std::make_shared<std::atomic<bool>>(true);
  GridLayer big(300, 300);
  const GridPath p = dijkstraSearch(big, {0, 0}, {299, 299}, GridMoves{}, TerminationCondition().withCancelFlag(cancel));
  EXPECT_EQ(p.status, SearchStatus::kStopped);
  EXPECT_EQ(to_string(SearchStatus::kStopped), "stopped");
}

}  // namespace
}  // namespace skyroute
