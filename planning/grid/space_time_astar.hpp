// Space-time A* on the 4-connected grid: a state is (cell, step); each step moves to a
// 4-neighbour or waits (eq. 6 of seed 002) and costs one. Cells other agents (vehicles, moving
// obstacles) hold at given steps are obstacles (eq. 4), and so is crossing an agent head-on
// (a swap). Used by the collision stage of section 3.3 to detour a vehicle to its next task and
// by the moving-obstacle avoidance of its Fig. 13.
#pragma once

#include <cstdint>
#include <string_view>
#include <unordered_map>
#include <vector>

#include "planning/core/termination.hpp"
#include "terrain/grid_layer.hpp"

namespace skyroute {

// Which agent holds which cell at which step. Agents are small integers (vehicles first, then
// moving obstacles, by the caller's convention). A path reserved with park_at_end keeps its
// last cell from its last step on, forever (a vehicle home at its depot, eq. 7).
class CellTimeReservations {
 public:
  explicit CellTimeReservations(const GridLayer& grid) : width_(grid.width()) {}

  // cells[k] is held at step start_step + k.
  void reservePath(int agent, int start_step, const std::vector<GridCell>& cells, bool park_at_end);
  void reserveCellAt(int agent, GridCell cell, int step);
  void clearAgent(int agent);

  // Holders of `cell` at `step` other than `self` (at most a few).
  bool heldByOther(GridCell cell, int step, int self) const;
  // The move from -> to over steps step -> step+1 keeps clear of every other agent: `to` is not
  // held at step+1, and no agent goes to -> from over the same step (a swap).
  bool moveAllowed(GridCell from, GridCell to, int step, int self) const;
  // No other agent holds `cell` at `step` or any later step (so `self` may stay there for good).
  bool freeFrom(GridCell cell, int step, int self) const;
  // Last step at which any time-limited reservation holds (parking is unlimited); -1 if none.
  int horizon() const { return horizon_; }

 private:
  std::uint64_t key(GridCell c, int step) const {
    return (static_cast<std::uint64_t>(static_cast<std::uint32_t>(step)) << 32) |
           static_cast<std::uint32_t>(c.y * width_ + c.x);
  }
  struct Park {
    int agent;
    int from_step;
  };
  int width_ = 0;
  int horizon_ = -1;
  std::unordered_multimap<std::uint64_t, int> held_;                 // (cell, step) -> agent
  std::unordered_multimap<std::uint32_t, Park> parked_;              // cell -> agent parked from a step
  std::unordered_map<int, std::vector<std::uint64_t>> agent_keys_;   // for clearAgent
  std::unordered_map<int, std::vector<std::uint32_t>> agent_parks_;
  std::vector<int> holders(GridCell cell, int step) const;
};

enum class SpaceTimeStatus { kFound, kStartBlocked, kGoalBlocked, kNoPath, kBudgetExhausted, kStopped };
std::string_view to_string(SpaceTimeStatus status);

struct SpaceTimeQuery {
  int self = 0;                 // the agent searching (its own reservations are ignored)
  GridCell start;
  int start_step = 0;
  GridCell goal;
  bool park_at_goal = false;    // the goal must stay free for good after arrival (a depot)
  int earliest_arrival = 0;     // do not finish before this step (e.g. to keep an appointment)
  // Exact static steps to the goal, indexed by GridLayer::index (a BFS map); null = Manhattan.
  const std::vector<int>* heuristic = nullptr;
  std::uint64_t max_expansions = 2'000'000;
};

struct SpaceTimePath {
  SpaceTimeStatus status = SpaceTimeStatus::kNoPath;
  std::vector<GridCell> cells;  // cells[k] at step start_step + k; front() = start, back() = goal
  int start_step = 0;
  std::uint64_t expansions = 0;
  double time_s = 0.0;
  bool found() const { return status == SpaceTimeStatus::kFound; }
  int arrivalStep() const { return start_step + static_cast<int>(cells.size()) - 1; }
};

// Earliest arrival at the goal. Beyond the reservations' horizon only parking remains, so states
// later than that are merged per cell, which bounds the search and makes "no path" finite.
SpaceTimePath planSpaceTime(const GridLayer& grid, const CellTimeReservations& reservations, const SpaceTimeQuery& query,
                            const TerminationCondition& stop = TerminationCondition());

}  // namespace skyroute
