// MMD*L: every cost matrix entry equals Dijkstra on the same grid, before and after random
// obstacle additions and removals while the vehicle flies the mission; it agrees with per-pair
// D* Lite and with the Moving AI optimal lengths; it holds n+1 maps instead of n^2+n.
#include <random>

#include <gtest/gtest.h>

#include "tests/grid_fixtures.hpp"

#include "planning/grid/grid_search.hpp"
#include "planning/mission/mmdstar_lite.hpp"
#include "planning/mission/pairwise_dstar_lite.hpp"
#include "terrain/movingai.hpp"
#include "tests/test_data.hpp"

namespace skyroute {
namespace {

using testing::cornerCuttingMoves;

// Distinct passable points all in the component of the first one.
std::vector<GridCell> connectedPoints(const GridLayer& grid, int count, std::mt19937& rng) {
  std::uniform_int_distribution<int> ux(0, grid.width() - 1), uy(0, grid.height() - 1);
  for (;;) {
    std::vector<GridCell> pts;
    GridCell first{ux(rng), uy(rng)};
    if (grid.blocked(first)) continue;
    const auto reach = reachableCells(grid, first);
    pts.push_back(first);
    int guard = 0;
    while (static_cast<int>(pts.size()) < count && guard++ < 10000) {
      const GridCell c{ux(rng), uy(rng)};
      if (!reach[grid.index(c)]) continue;
      if (std::find(pts.begin(), pts.end(), c) != pts.end()) continue;
      pts.push_back(c);
    }
    if (static_cast<int>(pts.size()) == count) return pts;
  }
}

// Every planned entry of `search` against Dijkstra from each goal (the graph is undirected, so the
// field from the goal gives the cost from any start).
void expectMatrixMatchesDijkstra(const MissionSearch& search, const std::string& when) {
  const GridLayer& grid = search.grid();
  for (int goal : search.remainingGoals()) {
    const auto field = dijkstraCostField(grid, search.points()[goal], search.moves());
    for (int from = 0; from < search.pointCount(); ++from) {
      if (!search.planned(from, goal)) continue;
      const GridCell at = from == search.vehiclePoint() ? search.vehicleCell() : search.points()[from];
      const double expected = field[grid.index(at)];
      const double got = search.cost(from, goal);
      if (expected < kInfiniteCost) {
        ASSERT_NEAR(got, expected, 1e-9) << when << ": " << from << " -> " << goal;
      } else {
        ASSERT_EQ(got, kInfiniteCost) << when << ": " << from << " -> " << goal;
      }
    }
  }
}

// Every planned pair's path runs from its start to its goal by allowed moves and costs what the
// matrix says.
void expectPathsCostWhatTheMatrixSays(const MissionSearch& search, const std::string& when) {
  const GridLayer& grid = search.grid();
  for (int goal : search.remainingGoals()) {
    for (int from = 0; from < search.pointCount(); ++from) {
      if (!search.planned(from, goal) || !(search.cost(from, goal) < kInfiniteCost)) continue;
      const std::vector<GridCell> cells = search.path(from, goal);
      ASSERT_FALSE(cells.empty()) << when << ": " << from << " -> " << goal;
      const GridCell at = from == search.vehiclePoint() ? search.vehicleCell() : search.points()[from];
      ASSERT_EQ(cells.front(), at) << when;
      ASSERT_EQ(cells.back(), search.points()[goal]) << when;
      double sum = 0.0;
      for (std::size_t i = 1; i < cells.size(); ++i) {
        const GridOffset d{cells[i].x - cells[i - 1].x, cells[i].y - cells[i - 1].y};
        ASSERT_TRUE(std::abs(d.dx) <= 1 && std::abs(d.dy) <= 1 && (d.dx != 0 || d.dy != 0)) << when;
        const double c = moveCost(grid, cells[i - 1], d, search.moves());
        ASSERT_LT(c, kInfiniteCost) << when << ": not a move at " << i;
        sum += c;
      }
      ASSERT_NEAR(sum, search.cost(from, goal), 1e-9) << when << ": " << from << " -> " << goal;
    }
  }
}

// Identical cost matrix and counters (the goals' work does not depend on the thread that runs it).
void expectSameSearch(const MissionSearch& a, const MissionSearch& b, const std::string& when) {
  for (int from = 0; from < a.pointCount(); ++from)
    for (int to = 0; to < a.pointCount(); ++to) ASSERT_EQ(a.cost(from, to), b.cost(from, to)) << when;
  EXPECT_EQ(a.stats().expansions, b.stats().expansions) << when;
  EXPECT_EQ(a.stats().queue_pushes, b.stats().queue_pushes) << when;
  EXPECT_EQ(a.stats().queue_pops, b.stats().queue_pops) << when;
}

TEST(MmdStarLite, CostMatrixEqualsDijkstraThroughAMissionWithChanges) {
  std::size_t fresh_plans = 0, swept_fresh_plans = 0, deferred = 0;
  for (const GridMoves moves : {GridMoves{}, GridMoves::paper(), cornerCuttingMoves()}) {
    std::mt19937 rng(2024);
    for (int trial = 0; trial < 6; ++trial) {
      GridLayer grid = randomGrid(60, 50, 0.2, rng);
      const int n = 1 + trial;  // mission points
      std::vector<GridCell> points = connectedPoints(grid, n + 2, rng);
      MmdStarLite mmd(grid, points, moves);
      // The same planner with its goals on two threads: same matrix, same counters, every step.
      MmdStarLite threaded(grid, points, moves, 2);
      // And one that plans a goal afresh whenever its repair costs over 5 % of planning it anew.
      MmdStarLite fresh(grid, points, moves);
      fresh.setFreshPlanFraction(0.05);
      // And one that plans goals from scratch by the bucket sweep (any grid size), with the rule.
      MmdStarLite swept(grid, points, moves);
      swept.setSweepMinCells(1);
      swept.setFreshPlanFraction(0.05);
      // And one that defers such goals instead (their costs from the other maps, by symmetry).
      MmdStarLite deferring(grid, points, moves);
      deferring.setSweepMinCells(1);
      deferring.setFreshPlanFraction(0.05);
      deferring.setDeferGoalMaps(true);
      // And one that searches each pair of goals in one of its two maps, on two threads.
      MmdStarLite split(grid, points, moves, 2);
      split.setSymmetricPairs(true);
      PairwiseDStarLite pairwise(grid, points, moves);
      ASSERT_EQ(mmd.preplan(), PlannerStatus::kSolved);
      ASSERT_EQ(threaded.preplan(), PlannerStatus::kSolved);
      ASSERT_EQ(fresh.preplan(), PlannerStatus::kSolved);
      ASSERT_EQ(swept.preplan(), PlannerStatus::kSolved);
      ASSERT_EQ(deferring.preplan(), PlannerStatus::kSolved);
      ASSERT_EQ(split.preplan(), PlannerStatus::kSolved);
      expectMatrixMatchesDijkstra(split, "split pairs, preplanning");
      expectPathsCostWhatTheMatrixSays(split, "split pairs, preplanning");
      expectMatrixMatchesDijkstra(swept, "sweep, preplanning");
      expectSameSearch(threaded, mmd, "preplanning");
      ASSERT_EQ(pairwise.preplan(), PlannerStatus::kSolved);
      expectMatrixMatchesDijkstra(mmd, "preplanning");
      EXPECT_EQ(mmd.costMapCount(), static_cast<std::size_t>(n + 1));
      EXPECT_EQ(pairwise.costMapCount(), static_cast<std::size_t>(n * n + n));
      // Fly: head for the nearest remaining goal, flip random cells every 3 steps.
      std::vector<char> protect(grid.cellCount(), 0);
      for (const GridCell& p : points) protect[grid.index(p)] = 1;
      int step = 0;
      while (step < 400) {
        const auto goals = mmd.remainingGoals();
        int target = goals.front();
        if (target == mmd.endPoint() && goals.size() > 1) target = goals[1];
        const GridCell next = mmd.nextCell(target);
        if (next == mmd.vehicleCell()) break;  // cut off: stop this trial's flight
        mmd.moveVehicle(next);
        threaded.moveVehicle(next);
        fresh.moveVehicle(next);
        swept.moveVehicle(next);
        deferring.moveVehicle(next);
        split.moveVehicle(next);
        pairwise.moveVehicle(next);
        ++step;
        if (next == points[target]) {
          if (target == mmd.endPoint()) break;
          mmd.arriveAt(target);
          threaded.arriveAt(target);
          fresh.arriveAt(target);
          swept.arriveAt(target);
          deferring.arriveAt(target);
          split.arriveAt(target);
          expectMatrixMatchesDijkstra(split, "split pairs, after arrival");
          expectPathsCostWhatTheMatrixSays(split, "split pairs, after arrival");
          expectMatrixMatchesDijkstra(deferring, "deferring, after arrival");
          expectPathsCostWhatTheMatrixSays(deferring, "deferring, after arrival");
          pairwise.arriveAt(target);
          expectMatrixMatchesDijkstra(mmd, "after arrival");
        }
        if (step % 3 != 0) continue;
        std::vector<GridCell> changed;
        for (int k = 0; k < 8; ++k) {
          const GridCell c{std::uniform_int_distribution<int>(0, grid.width() - 1)(rng),
                           std::uniform_int_distribution<int>(0, grid.height() - 1)(rng)};
          if (protect[grid.index(c)] || c == mmd.vehicleCell()) continue;
          const std::vector<GridCell> one{c};
          for (const GridCell& d : grid.setStaticBlocked(one, !grid.staticBlocked(c))) changed.push_back(d);
        }
        ASSERT_EQ(mmd.applyChanges(changed), PlannerStatus::kSolved);
        ASSERT_EQ(threaded.applyChanges(changed), PlannerStatus::kSolved);
        ASSERT_EQ(fresh.applyChanges(changed), PlannerStatus::kSolved);
        ASSERT_EQ(swept.applyChanges(changed), PlannerStatus::kSolved);
        expectMatrixMatchesDijkstra(swept, "sweep, replanning step " + std::to_string(step));
        ASSERT_EQ(deferring.applyChanges(changed), PlannerStatus::kSolved);
        ASSERT_EQ(split.applyChanges(changed), PlannerStatus::kSolved);
        expectMatrixMatchesDijkstra(split, "split pairs, replanning step " + std::to_string(step));
        expectPathsCostWhatTheMatrixSays(split, "split pairs, replanning step " + std::to_string(step));
        expectMatrixMatchesDijkstra(deferring, "deferring, replanning step " + std::to_string(step));
        expectPathsCostWhatTheMatrixSays(deferring, "deferring, replanning step " + std::to_string(step));
        expectMatrixMatchesDijkstra(fresh, "fresh-plan rule, replanning step " + std::to_string(step));
        ASSERT_EQ(pairwise.applyChanges(changed), PlannerStatus::kSolved);
        expectSameSearch(threaded, mmd, "replanning step " + std::to_string(step));
        expectMatrixMatchesDijkstra(mmd, "replanning step " + std::to_string(step));
        expectMatrixMatchesDijkstra(pairwise, "pairwise replanning step " + std::to_string(step));
      }
      EXPECT_GT(step, 0);
      fresh_plans += fresh.freshPlans();
      swept_fresh_plans += swept.freshPlans();
      deferred += deferring.deferredGoals();
    }
  }
  EXPECT_GT(fresh_plans, 0u);  // the rule was exercised
  EXPECT_GT(swept_fresh_plans, 0u);  // the rule fired in the sweeping planner too
  EXPECT_GT(deferred, 0u);           // and goals were deferred
}

TEST(MmdStarLite, SharingSavesExpansionsOnTheSameProblems) {
  std::mt19937 rng(11);
  std::uint64_t mmd_total = 0, pair_total = 0;
  for (int trial = 0; trial < 10; ++trial) {
    GridLayer grid = randomGrid(110, 110, 0.2, rng);
    const auto points = connectedPoints(grid, 7, rng);  // n = 5
    MmdStarLite mmd(grid, points, GridMoves::paper());
    PairwiseDStarLite pairwise(grid, points, GridMoves::paper());
    mmd.preplan();
    pairwise.preplan();
    for (int from = 0; from < mmd.pointCount(); ++from)
      for (int to = 0; to < mmd.pointCount(); ++to)
        if (mmd.planned(from, to)) {
          ASSERT_NEAR(mmd.cost(from, to), pairwise.cost(from, to), 1e-9);
        }
    mmd_total += mmd.stats().expansions;
    pair_total += pairwise.stats().expansions;
  }
  EXPECT_LT(mmd_total, pair_total);
}

TEST(MmdStarLite, PathsAreValidAndCostWhatTheMatrixSays) {
  std::mt19937 rng(3);
  GridLayer grid = randomGrid(40, 40, 0.25, rng);
  const auto points = connectedPoints(grid, 6, rng);
  MmdStarLite mmd(grid, points);
  ASSERT_EQ(mmd.preplan(), PlannerStatus::kSolved);
  for (int from = 0; from < mmd.pointCount(); ++from) {
    for (int to = 0; to < mmd.pointCount(); ++to) {
      if (!mmd.planned(from, to)) {
        EXPECT_TRUE(mmd.path(from, to).empty());
        continue;
      }
      const auto path = mmd.path(from, to);
      ASSERT_FALSE(path.empty());
      EXPECT_EQ(path.front(), points[from]);
      EXPECT_EQ(path.back(), points[to]);
      double sum = 0.0;
      for (std::size_t i = 1; i < path.size(); ++i)
        sum += moveCost(grid, path[i - 1], {path[i].x - path[i - 1].x, path[i].y - path[i - 1].y}, GridMoves{});
      EXPECT_NEAR(sum, mmd.cost(from, to), 1e-9);
    }
  }
  EXPECT_FALSE(mmd.planned(0, mmd.endPoint())) << "B -> E is not needed when mission points exist";
  EXPECT_FALSE(mmd.planned(1, 0)) << "B is never a goal";
}

// Every scenario problem solved by a shared-goal search with the scenario's optimal length.
void expectScenarioOptima(const GridLayer& grid, const std::vector<MovingAiProblem>& problems) {
  for (std::size_t i = 0; i < problems.size(); ++i) {
    const MovingAiProblem& pr = problems[i];
    SharedGoalSearch search(grid, pr.goal);
    ASSERT_EQ(search.solveFrom(pr.start), PlannerStatus::kSolved) << i;
    EXPECT_NEAR(search.cost(pr.start), pr.optimal_length, 1e-3) << "problem " << i;
  }
}

// Shared-goal reuse (lines 34-38) on a real benchmark map: one map per goal, many starts, each cost
// equal to Dijkstra; and every scenario problem solved with its optimal length.
TEST(MmdStarLite, SharedGoalMatchesMovingAi) {
  SKYROUTE_MOVINGAI_CASE(random64, "random-64-64-20.map", "random-64-64-20-random-1.scen");
  const GridLayer& grid = random64.grid;
  const std::vector<MovingAiProblem>& problems = random64.problems;
  expectScenarioOptima(grid, problems);
  // Groups of 25 problems: the goal of the first, the starts of all 25.
  for (std::size_t first = 0; first + 25 <= problems.size(); first += 250) {
    const GridCell goal = problems[first].goal;
    SharedGoalSearch search(grid, goal);
    const auto field = dijkstraCostField(grid, goal);
    for (std::size_t k = first; k < first + 25; ++k) {
      const GridCell s = problems[k].start;
      search.solveFrom(s);
      EXPECT_NEAR(search.cost(s), field[grid.index(s)], 1e-9);
    }
  }
}

TEST(MmdStarLite, SharedGoalMatchesMovingAiRoom) {
  SKYROUTE_MOVINGAI_CASE(room, "room-32-32-4.map", "room-32-32-4-random-1.scen");
  expectScenarioOptima(room.grid, room.problems);
}

}  // namespace
}  // namespace skyroute
