// An independent check of a fleet plan, written without the planner's code: it takes plain
// per-vehicle cell paths (cells[t] at step t, home for good after the last) and task sequences,
// and lists every violation of the problem of seed 002, section 2: a vertex conflict (eq. 4), a
// swap (two vehicles exchanging cells in one step), a vehicle meeting a moving obstacle, a move
// longer than one 4-neighbour step (eq. 6), a blocked cell, a path not starting or ending at its
// depot (eq. 7), a task not done exactly once or done by a vehicle whose path misses it (eq. 3, 5),
// a vehicle over its capacity (eq. 2).
#pragma once

#include <string>
#include <vector>

#include "planning/fleet/fleet_problem.hpp"
#include "terrain/grid_layer.hpp"

namespace skyroute {

struct FleetConflict {
  enum class Kind { kVertex, kSwap };
  Kind kind = Kind::kVertex;
  int a = 0;      // vehicle index
  int b = 0;      // vehicle index, or vehicle count + moving obstacle index
  int step = 0;   // vertex: the step both are in `cell`; swap: the step the exchange ends
  GridCell cell;  // vertex: the shared cell; swap: a's cell at `step`
  friend bool operator==(const FleetConflict&, const FleetConflict&) = default;
};

struct FleetCheckReport {
  std::vector<FleetConflict> conflicts;
  std::vector<std::string> violations;  // everything else, one readable line each
  bool ok() const { return conflicts.empty() && violations.empty(); }
  std::string summary() const;  // the first few problems, for messages
};

FleetCheckReport checkFleetPlan(const GridLayer& grid, const FleetProblem& problem,
                                const std::vector<std::vector<GridCell>>& paths,
                                const std::vector<std::vector<int>>& sequences);

}  // namespace skyroute
