// Fixtures for the grid-search tests: seeded random grids, the seed's corner-cutting move rule, and
// Moving AI maps with their scenarios.
#pragma once

#include <optional>
#include <random>
#include <string>
#include <utility>
#include <vector>

#include <gtest/gtest.h>

#include "planning/grid/grid_moves.hpp"
#include "terrain/grid_layer.hpp"
#include "terrain/movingai.hpp"
#include "tests/test_data.hpp"

namespace skyroute {

// Each cell blocked with probability `density`, drawn from `rng` row by row.
inline GridLayer randomGrid(int w, int h, double density, std::mt19937& rng) {
  GridLayer grid(w, h);
  std::vector<GridCell> blocked;
  std::bernoulli_distribution wall(density);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x)
      if (wall(rng)) blocked.push_back({x, y});
  grid.setStaticBlocked(blocked, true);
  return grid;
}

namespace testing {

// The seed's simulation rule: diagonal moves may pass between two blocked cells.
inline GridMoves cornerCuttingMoves() {
  GridMoves m = GridMoves::paper();
  m.corner_cutting = true;
  return m;
}

// A Moving AI map and its scenario's problems (with their optimal lengths).
struct MovingAiCase {
  GridLayer grid;
  std::vector<MovingAiProblem> problems;
};

// Loads both files; a file that does not load is a test failure (and nothing comes back).
inline std::optional<MovingAiCase> loadMovingAiCase(const std::string& map_path, const std::string& scen_path) {
  auto grid = loadMovingAiMap(map_path);
  EXPECT_TRUE(grid.ok()) << grid.error().describe();
  auto problems = loadMovingAiScenario(scen_path);
  EXPECT_TRUE(problems.ok()) << problems.error().describe();
  if (!grid.ok() || !problems.ok()) return std::nullopt;
  EXPECT_FALSE(problems->empty()) << scen_path << " has no problems";
  return MovingAiCase{std::move(grid).value(), std::move(problems).value()};
}

}  // namespace testing
}  // namespace skyroute

// Declares `var` (a testing::MovingAiCase) from ../shared/data/movingai/<map> and <scen>: the test
// skips (or fails, under SKYROUTE_REQUIRE_DATA) when they are missing and fails when they do not load.
#define SKYROUTE_MOVINGAI_CASE(var, map, scen)                                                   \
  SKYROUTE_REQUIRE_SHARED(var##_map_path, "movingai/" map);                                      \
  SKYROUTE_REQUIRE_SHARED(var##_scen_path, "movingai/" scen);                                    \
  const auto var##_loaded = ::skyroute::testing::loadMovingAiCase(var##_map_path, var##_scen_path); \
  ASSERT_TRUE(var##_loaded);                                                                     \
  const ::skyroute::testing::MovingAiCase& var = *var##_loaded
