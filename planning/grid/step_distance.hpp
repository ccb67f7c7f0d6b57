// Steps on the 4-connected grid (one step per move to a side neighbour, eq. 6 of seed 002):
// breadth-first distance maps that respect the static obstacles, and the walk down one to its
// source. The fleet's travel times and the space-time search's exact heuristic both come from here.
#pragma once

#include <limits>
#include <vector>

#include "planning/grid/grid_moves.hpp"
#include "terrain/grid_layer.hpp"

namespace skyroute {

inline constexpr int kUnreachableSteps = std::numeric_limits<int>::max();

// Steps from `source` to every cell (indexed by GridLayer::index); kUnreachableSteps for blocked
// or unreachable cells and everywhere when the source itself is blocked.
std::vector<int> bfsDistanceMap4(const GridLayer& grid, GridCell source);

// A shortest path from `from` to the source of `distance_map` (both ends included), each step to
// the first neighbour in kFourMoves order that is one step closer. Empty when unreachable.
std::vector<GridCell> descendDistanceMap4(const GridLayer& grid, const std::vector<int>& distance_map, GridCell from);

}  // namespace skyroute
