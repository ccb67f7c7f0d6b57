// A* and Dijkstra on the GridLayer under the move rules of grid_moves.hpp, a cost field and a
// reachability flood fill: the reference searches for A*, Dijkstra, D* Lite and MMD*L.
#pragma once

#include <cstdint>
#include <string_view>
#include <vector>

#include "planning/core/termination.hpp"
#include "planning/grid/grid_moves.hpp"
#include "terrain/grid_layer.hpp"

namespace skyroute {

// Counters every search reports; queue operations count pushes and pops of its priority queue.
struct SearchStats {
  std::uint64_t expansions = 0;
  std::uint64_t queue_pushes = 0;
  std::uint64_t queue_pops = 0;
  double time_ms = 0.0;

  SearchStats& operator+=(const SearchStats& o) {
    expansions += o.expansions;
    queue_pushes += o.queue_pushes;
    queue_pops += o.queue_pops;
    time_ms += o.time_ms;
    return *this;
  }
};

enum class SearchStatus {
  kFound,         // cost and path are optimal
  kNoPath,        // start and goal are valid but not connected
  kInvalidStart,  // outside the grid or blocked
  kInvalidGoal,   // outside the grid or blocked
  kStopped,       // the termination condition fired first
};
std::string_view to_string(SearchStatus status);

struct GridPath {
  SearchStatus status = SearchStatus::kNoPath;
  double cost = kInfiniteCost;   // cell edges
  std::vector<GridCell> cells;   // start .. goal, empty unless found
  SearchStats stats;
  TerminationCondition::Reason stop_reason = TerminationCondition::Reason::kNone;  // why, when kStopped
};

// A* with the moves' heuristic; closed cells are never reopened (the heuristic is consistent).
GridPath astarSearch(const GridLayer& grid, GridCell start, GridCell goal, const GridMoves& moves = {},
                     const TerminationCondition& stop = {});
// Dijkstra from start until goal is settled: the heuristic-free reference.
GridPath dijkstraSearch(const GridLayer& grid, GridCell start, GridCell goal, const GridMoves& moves = {},
                        const TerminationCondition& stop = {});
// Exact cost from `source` to every cell (infinity where unreachable or blocked), indexed by
// GridLayer::index: the reference for cost matrices.
std::vector<double> dijkstraCostField(const GridLayer& grid, GridCell source, const GridMoves& moves = {});

// Cells reachable from `source` (1) or not (0), by the same moves; for early "unreachable" errors.
std::vector<std::uint8_t> reachableCells(const GridLayer& grid, GridCell source, const GridMoves& moves = {});

}  // namespace skyroute
