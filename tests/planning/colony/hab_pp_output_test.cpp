// The output stage of HAB-PP (planning/colony/hab_pp_output): the best ranked path made taut within its
// route, then windowed re-planning. Checked: every output segment passes an independent geometric
// line-of-sight test, the output is never longer than the input, it reaches the any-angle optimum
// when the input follows the optimum's route, the corridor step keeps the input's route (a shorter
// door outside the corridor stays closed to it), and the window step takes that door when a
// window of a few segments reaches it, and not when its box does not.
#include "planning/colony/hab_pp_output.hpp"

#include <random>

#include <gtest/gtest.h>

#include "planning/grid/any_angle_search.hpp"
#include "tests/grid_fixtures.hpp"
#include "tests/planning/any_angle_reference.hpp"
#include "tests/planning/hab_maps.hpp"

namespace skyroute {
namespace {

using habpp::Path;
using testing::gridFromText;
using testing::pathProblem;

TEST(HabPpOutput, EightConnectedPathsBecomeTautWithinOnePercentOfTheOptimum) {
  for (const auto& m : testing::knownMaps()) {
    SCOPED_TRACE(m.name);
    const AnyAngleResult grid_path = gridAStar8(m.grid, m.start, m.goal, TerminationCondition{});
    ASSERT_EQ(grid_path.status, AnyAngleStatus::kExact);
    const double optimum = testing::visibilityGraphOptimum(m.grid, m.start, m.goal);
    const Path out = habpp::tautPath(m.grid, grid_path.path, 2, 64);
    EXPECT_EQ(pathProblem(m.grid, out, m.start, m.goal), "");
    EXPECT_GE(polylineLength(out), optimum - 1e-9);
    // The optimum bends at obstacle corners, cell-centre paths one cell off them (single wall:
    // +1.3 %), so the yardstick is Theta* on the whole grid: the output matches it.
    const AnyAngleResult theta = thetaStar(m.grid, m.start, m.goal);
    EXPECT_LE(polylineLength(out), polylineLength(theta.path) * 1.001);
    EXPECT_LE(polylineLength(out), optimum * 1.015);
    EXPECT_LE(polylineLength(out), polylineLength(habpp::tightenPath(m.grid, grid_path.path, 64)) + 1e-9);
  }
}

// Random walls and random valid polylines (random walks of visible hops): never longer, always valid.
TEST(HabPpOutput, NeverLongerAndAlwaysValidOnRandomMaps) {
  std::mt19937 rng(17);
  int shortened = 0;
  for (int trial = 0; trial < 40; ++trial) {
    GridLayer g = randomGrid(30, 24, 0.18, rng);
    const GridCell start{0, 0}, goal{29, 23};
    g.setStaticBlocked(std::vector<GridCell>{start, goal}, false);
    // A wandering valid path: hops to random visible cells, then on to the goal by Theta*.
    Path p{start};
    for (int hop = 0; hop < 6; ++hop) {
      const GridCell c{static_cast<int>(rng() % 30), static_cast<int>(rng() % 24)};
      if (g.passable(c) && !(c == p.back()) && g.lineOfSight(p.back(), c)) p.push_back(c);
    }
    const AnyAngleResult rest = thetaStar(g, p.back(), goal);
    if (rest.status != AnyAngleStatus::kExact) continue;
    p.insert(p.end(), rest.path.begin() + 1, rest.path.end());
    ASSERT_EQ(pathProblem(g, p, start, goal), "");
    for (int corridor : {0, 1, 3}) {
      const Path out = habpp::tautPath(g, p, corridor, 64);
      EXPECT_EQ(pathProblem(g, out, start, goal), "") << "trial " << trial << " corridor " << corridor;
      EXPECT_LE(polylineLength(out), polylineLength(p) + 1e-9);
      if (polylineLength(out) < polylineLength(p) - 1e-6) ++shortened;
    }
    for (const habpp::WindowOptions o : {habpp::WindowOptions{.segments = 2, .margin_cells = 0},
                                         habpp::WindowOptions{.segments = 3, .margin_cells = 4},
                                         habpp::WindowOptions{.span_cells = 12.0, .margin_cells = 2}}) {
      const Path out = habpp::replanWindows(g, p, o, 64);
      EXPECT_EQ(pathProblem(g, out, start, goal), "") << "trial " << trial << " window " << o.segments;
      EXPECT_LE(polylineLength(out), polylineLength(p) + 1e-9);
    }
  }
  EXPECT_GT(shortened, 40) << "the wandering paths do get shorter";
}

// One door (x = 2) in the upper wall, two (x = 5 and x = 18) in the lower.
GridLayer threeDoorMap() {
  return gridFromText({
      "....................",
      "....................",
      "....................",
      "##.#################",
      "....................",
      "....................",
      "....................",
      "....................",
      "....................",
      "#####.############.#",
      "....................",
      "....................",
      "....................",
      "....................",
      "....................",
  });
}

// Whether a segment of p touches cell c.
bool passes(const Path& p, GridCell c) {
  for (std::size_t s = 0; s + 1 < p.size(); ++s) {
    for (GridCell q : GridLayer::segmentCells(p[s], p[s + 1])) {
      if (q == c) return true;
    }
  }
  return false;
}

// The input goes through the far door of the lower wall. The output pulls taut through the same door (the near door lies outside the
// corridor), so the route stays the colony's choice.
TEST(HabPpOutput, KeepsTheRouteOfTheInput) {
  const GridLayer g = threeDoorMap();
  // The lower leg runs 3 rows below the wall, so the near door lies outside the corridor (2 cells);
  // a path that ran along the wall right past that door would have it in its corridor (see
  // hab_pp_output.hpp).
  const GridCell start{2, 1}, goal{2, 14};
  // Down through the door of row 3, across, and through the door at x = 18 of row 9.
  const Path via_far_door{start, {2, 3}, {3, 5}, {8, 6}, {14, 7}, {18, 8}, {18, 12}, goal};
  ASSERT_EQ(pathProblem(g, via_far_door, start, goal), "");
  const Path out = habpp::tautPath(g, via_far_door, 2, 64);
  EXPECT_EQ(pathProblem(g, out, start, goal), "");
  EXPECT_LT(polylineLength(out), polylineLength(via_far_door) - 1.0);
  EXPECT_TRUE(passes(out, GridCell{18, 9}));
  // Through the far door the route is over 30 cells; through the near one (x = 5) about 14.
  EXPECT_GT(polylineLength(out), 30.0);
}

// Several ranked routes: the best ranked one goes through the far door, a lower ranked one through
// the near door. The union of their corridors lets the output take the shorter route, which the
// colony did find; with the best ranked route alone it keeps the far door. The output never takes
// a door that no given route passes.
TEST(HabPpOutput, TakesTheShortestOfTheRankedRoutes) {
  const GridLayer g = threeDoorMap();
  const GridCell start{2, 1}, goal{2, 14};
  const Path via_far_door{start, {2, 3}, {3, 5}, {8, 6}, {14, 7}, {18, 8}, {18, 12}, goal};
  const Path via_near_door{start, {2, 3}, {4, 6}, {5, 9}, {4, 12}, goal};
  ASSERT_EQ(pathProblem(g, via_near_door, start, goal), "");
  const Path alone = habpp::tautPath(g, std::vector<Path>{via_far_door}, 2, 64);
  EXPECT_TRUE(passes(alone, GridCell{18, 9}));
  const Path both = habpp::tautPath(g, std::vector<Path>{via_far_door, via_near_door}, 2, 64);
  EXPECT_EQ(pathProblem(g, both, start, goal), "");
  EXPECT_TRUE(passes(both, GridCell{5, 9}));
  EXPECT_FALSE(passes(both, GridCell{18, 9}));
  EXPECT_LE(polylineLength(both), polylineLength(habpp::tautPath(g, via_near_door, 2, 64)) + 1e-9);
  EXPECT_LT(polylineLength(both), 16.0);
  // Without a corridor search the shorter route still wins, as it is.
  const Path no_search = habpp::tautPath(g, std::vector<Path>{via_far_door, via_near_door}, 0, 64);
  EXPECT_LE(polylineLength(no_search), polylineLength(via_near_door) + 1e-9);
  EXPECT_TRUE(passes(no_search, GridCell{5, 9}));
}

// The corridor step keeps the far door (above); a window of three segments whose box, grown by
// its margin, holds the near door re-plans that piece through it, and the output is then as short
// as Theta* on the whole map. Windows off, or a box that does not reach the near door, keep the
// colony's route.
TEST(HabPpOutput, WindowsTakeTheNearerDoorWithinAFewTurns) {
  const GridLayer g = threeDoorMap();
  const GridCell start{2, 1}, goal{2, 14};
  const Path via_far_door{start, {2, 3}, {3, 5}, {8, 6}, {14, 7}, {18, 8}, {18, 12}, goal};
  const Path taut = habpp::tautPath(g, via_far_door, 2, 64);
  ASSERT_TRUE(passes(taut, GridCell{18, 9}));
  EXPECT_EQ(habpp::replanWindows(g, taut, habpp::WindowOptions{}, 64), taut);  // off by default

  const Path out = habpp::replanWindows(g, taut, habpp::WindowOptions{.segments = 3, .margin_cells = 8}, 64);
  EXPECT_EQ(pathProblem(g, out, start, goal), "");
  EXPECT_TRUE(passes(out, GridCell{5, 9}));
  EXPECT_FALSE(passes(out, GridCell{18, 9}));
  const AnyAngleResult theta = thetaStar(g, start, goal);
  ASSERT_EQ(theta.status, AnyAngleStatus::kExact);
  EXPECT_LE(polylineLength(out), polylineLength(theta.path) + 1e-9);

  // Locality: from (10, 6) to (10, 12) through the far door. The box of the path's vertices
  // (x 10..18) holds only the far door; grown by 8 cells it holds the near one (x = 5) too.
  const Path short_far{{10, 6}, {18, 8}, {18, 10}, {10, 12}};
  ASSERT_EQ(pathProblem(g, short_far, short_far.front(), short_far.back()), "");
  const Path kept = habpp::replanWindows(g, short_far, habpp::WindowOptions{.segments = 3, .margin_cells = 0}, 64);
  EXPECT_EQ(pathProblem(g, kept, short_far.front(), short_far.back()), "");
  EXPECT_TRUE(passes(kept, GridCell{18, 9}));
  const Path moved = habpp::replanWindows(g, short_far, habpp::WindowOptions{.segments = 3, .margin_cells = 8}, 64);
  EXPECT_TRUE(passes(moved, GridCell{5, 9}));
  EXPECT_LT(polylineLength(moved), polylineLength(kept) - 4.0);
}

}  // namespace
}  // namespace skyroute
