// A* (8-connected) and Theta* of planning/grid/any_angle_search: A* against the Moving AI optimal
// lengths, Theta* against the exact any-angle optimum on small maps, every path checked with an
// independent geometric line-of-sight test.
#include "planning/grid/any_angle_search.hpp"

#include <cmath>

#include <gtest/gtest.h>

#include "terrain/movingai.hpp"
#include "tests/grid_fixtures.hpp"
#include "tests/planning/any_angle_reference.hpp"
#include "tests/planning/hab_maps.hpp"
#include "tests/test_data.hpp"

namespace skyroute {
namespace {

using testing::knownMaps;
using testing::pathProblem;

// Solves the first 200 problems of a MovingAI case with planner; each solved one goes to check with
// its index, and must be a valid path.
template <class Planner, class Check>
void solveFirstProblems(const testing::MovingAiCase& c, Planner planner, Check check) {
  for (std::size_t i = 0; i < 200 && i < c.problems.size(); ++i) {
    const MovingAiProblem& p = c.problems[i];
    const AnyAngleResult r = planner(c.grid, p.start, p.goal);
    ASSERT_EQ(r.status, PlannerStatus::kSolved) << "problem " << i;
    EXPECT_EQ(pathProblem(c.grid, r.path, p.start, p.goal), "") << "problem " << i;
    check(i, p, r);
  }
}

TEST(GridAStar8, MatchesMovingAiOptimalLengths) {
  SKYROUTE_MOVINGAI_CASE(room, "room-32-32-4.map", "room-32-32-4-random-1.scen");
  auto astar = [](const GridLayer& g, GridCell a, GridCell b) { return gridAStar8(g, a, b); };
  solveFirstProblems(room, astar, [](std::size_t i, const MovingAiProblem& p, const AnyAngleResult& r) {
    EXPECT_NEAR(r.length_cells, p.optimal_length, 1e-3) << "problem " << i;
    for (std::size_t k = 1; k < r.path.size(); ++k) {  // 8-connected moves, each a visible segment
      EXPECT_LE(std::max(std::abs(r.path[k].x - r.path[k - 1].x), std::abs(r.path[k].y - r.path[k - 1].y)), 1);
    }
  });
}

TEST(ThetaStar, ValidAndBetweenOptimumAndAStarOnMovingAiProblems) {
  SKYROUTE_MOVINGAI_CASE(room, "room-32-32-4.map", "room-32-32-4-random-1.scen");
  auto theta = [](const GridLayer& g, GridCell a, GridCell b) { return thetaStar(g, a, b); };
  solveFirstProblems(room, theta, [](std::size_t i, const MovingAiProblem& p, const AnyAngleResult& r) {
    EXPECT_LE(r.length_cells, p.optimal_length + 1e-3) << "problem " << i;  // never worse than 8-connected
    EXPECT_GE(r.length_cells, testing::euclid(p.start, p.goal) - 1e-9);
    EXPECT_NEAR(r.length_cells, polylineLength(r.path), 1e-9);
  });
}

// Theta* is not optimal in general (its parents are expanded cells): on these maps it stays within
// 1.5% of the visibility-graph optimum (measured: single wall +1.33%).
TEST(ThetaStar, WithinOneAndAHalfPercentOfTheAnyAngleOptimumOnKnownMaps) {
  for (const auto& m : knownMaps()) {
    const double optimum = testing::visibilityGraphOptimum(m.grid, m.start, m.goal);
    const AnyAngleResult r = thetaStar(m.grid, m.start, m.goal);
    ASSERT_EQ(r.status, PlannerStatus::kSolved) << m.name;
    EXPECT_EQ(pathProblem(m.grid, r.path, m.start, m.goal), "") << m.name;
    EXPECT_GE(r.length_cells, optimum - 1e-9) << m.name;
    EXPECT_LE(r.length_cells, optimum * 1.015) << m.name;
  }
  const auto open = knownMaps().front();
  EXPECT_NEAR(thetaStar(open.grid, open.start, open.goal).length_cells, testing::euclid(open.start, open.goal), 1e-9);
}

TEST(AnyAngleSearch, BlockedOrOutsideEndpointsAndUnreachableGoal) {
  GridLayer g = testing::gridFromText({
      ".....#....",
      ".....#....",
      ".....#....",
      ".....#....",
  });
  for (auto* search : {&gridAStar8, &thetaStar}) {
    EXPECT_EQ(search(g, GridCell{5, 0}, GridCell{0, 0}, {}).status, PlannerStatus::kStartInvalid);
    EXPECT_EQ(search(g, GridCell{-1, 0}, GridCell{0, 0}, {}).status, PlannerStatus::kStartInvalid);
    EXPECT_EQ(search(g, GridCell{0, 0}, GridCell{5, 3}, {}).status, PlannerStatus::kGoalInvalid);
    EXPECT_EQ(search(g, GridCell{0, 0}, GridCell{0, 9}, {}).status, PlannerStatus::kGoalInvalid);
    const AnyAngleResult r = search(g, GridCell{0, 0}, GridCell{9, 3}, {});
    EXPECT_EQ(r.status, PlannerStatus::kNoPath);
    EXPECT_TRUE(r.path.empty());
  }
}

TEST(AnyAngleSearch, DiagonalGapIsNotCut) {
  // Two blocked cells touching at a corner: the diagonal between them is closed (no corner cutting).
  GridLayer g = testing::gridFromText({
      "#.",
      ".#",
  });
  EXPECT_EQ(gridAStar8(g, GridCell{1, 0}, GridCell{0, 1}, {}).status, PlannerStatus::kNoPath);
  EXPECT_EQ(thetaStar(g, GridCell{1, 0}, GridCell{0, 1}, {}).status, PlannerStatus::kNoPath);
}

TEST(AnyAngleSearch, StopsOnTheTerminationCondition) {
  const GridLayer g(200, 200);
  auto stop = TerminationCondition().withIterationBudget(1);
  const AnyAngleResult r = thetaStar(g, GridCell{0, 0}, GridCell{199, 150}, stop);
  EXPECT_EQ(r.status, PlannerStatus::kBudgetExhausted);
  EXPECT_EQ(r.stop_reason, TerminationCondition::Reason::kIterations);
}

TEST(PolylineMeasures, LengthAndTurning) {
  const std::vector<GridCell> l{{0, 0}, {3, 0}, {3, 4}};
  EXPECT_DOUBLE_EQ(polylineLength(l), 7.0);
  EXPECT_NEAR(polylineAngleChange(l), M_PI / 2, 1e-12);
  EXPECT_DOUBLE_EQ(polylineAngleChange({{0, 0}, {1, 1}, {5, 5}}), 0.0);
}

}  // namespace
}  // namespace skyroute
