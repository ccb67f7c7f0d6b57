// Reference grid searches for the HAB-PP planners and `skyroute grid path`: A* on the 8-connected
// grid (astarSearch of grid_search.hpp, with the move rules of grid_moves.hpp) and Theta*
// (any-angle: a node may take its grandparent as parent when GridLayer::lineOfSight allows, so
// paths are straight segments between cell centres). Both are deterministic; they are the
// yardsticks the HAB-PP benchmark compares against, and the `--algo astar|theta` choices of the CLI.
//
// Their results carry an "AnyAngle" prefix (a polyline of cell centres and its Euclidean length)
// so they do not collide with the general grid searches' GridPath.
#pragma once

#include <cstdint>
#include <string_view>
#include <vector>

#include "planning/core/polyline.hpp"
#include "planning/core/termination.hpp"
#include "terrain/grid_layer.hpp"

namespace skyroute {

enum class AnyAngleStatus {
  kExact,          // a path from start to goal
  kInvalidStart,   // start outside the grid or blocked
  kInvalidGoal,    // goal outside the grid or blocked
  kNoPath,         // the open list ran empty: the goal is unreachable
  kTerminated,     // the termination condition stopped the search (see stop_reason)
};

std::string_view to_string(AnyAngleStatus status);

struct AnyAngleResult {
  AnyAngleStatus status = AnyAngleStatus::kNoPath;
  std::vector<GridCell> path;  // cell centres, start first; consecutive ones joined by straight segments
  double length_cells = 0.0;   // Euclidean length in cell edges
  std::uint64_t expansions = 0;
  double time_s = 0.0;
  TerminationCondition::Reason stop_reason = TerminationCondition::Reason::kNone;
};

// 8-connected A* with the octile heuristic (astarSearch); the path lists every cell it visits.
AnyAngleResult gridAStar8(const GridLayer& grid, GridCell start, GridCell goal,
                          const TerminationCondition& stop = {});

// Basic Theta* (Nash et al. 2007) with the Euclidean heuristic; the path lists only turning points.
AnyAngleResult thetaStar(const GridLayer& grid, GridCell start, GridCell goal,
                         const TerminationCondition& stop = {});

// Sum over interior points of the absolute turning angle in radians (0 for a straight path).
double polylineAngleChange(const std::vector<GridCell>& path);

}  // namespace skyroute
