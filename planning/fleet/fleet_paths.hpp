// Collision-free paths for an allocation (seed 002, section 3.3). Every vehicle first follows
// shortest paths (static obstacles only) through its tasks and home. Then time is stepped
// forward; at the first conflict (two vehicles in one cell, two vehicles swapping cells, or a
// vehicle meeting a moving obstacle) the vehicles involved are re-planned, one at a time and the
// one with more slack first, from where they are to their next task with space-time A*, which
// treats the conflicting cell-times, and every other cell-time the other vehicles and moving
// obstacles hold, as obstacles. (Blocking only the one conflicting cell-time, as the paper words
// it, sends both vehicles into the same wait and the same conflict one step later.) When a pair
// keeps conflicting, or no detour exists, the vehicle with more slack - the one least likely to
// raise the makespan - waits one step where it is, as the paper prescribes. A vehicle cornered at
// the conflict (a parked vehicle in a corridor) may start its detour a few steps earlier.
//
// The result keeps, per vehicle, its time-stamped cell path (cells[t] at step t), the step at
// which each task is done and its return step, which is what a service needs to build one
// trajectory per vehicle.
#pragma once

#include <cstdint>
#include <string_view>
#include <vector>

#include "planning/core/termination.hpp"
#include "planning/fleet/fleet_allocation.hpp"
#include "planning/fleet/fleet_problem.hpp"
#include "planning/fleet/fleet_travel_times.hpp"
#include "terrain/grid_layer.hpp"

namespace skyroute {

struct VehiclePlan {
  int vehicle = 0;              // index into FleetProblem::vehicles
  std::vector<int> tasks;       // task indices in visiting order
  std::vector<GridCell> cells;  // cells[t] is the cell at step t, t = 0 .. finish_step
  std::vector<int> task_steps;  // task_steps[k]: the step at which tasks[k] is done
  int finish_step = 0;          // T_i: home for good from this step on (eq. 7)

  // The cell at any step: the depot before departure is cells[0], after return cells.back().
  GridCell cellAt(int step) const;
};

struct FleetPathOptions {
  int max_detours_per_pair = 3;                 // then the vehicle with more slack waits
  int max_backtrack_steps = 8;                  // a detour may start this many steps before the conflict
  int max_resolutions = 0;                      // 0: 100 + 50 * vehicles + 10 * tasks
  std::uint64_t max_expansions_per_search = 1'000'000;
};

enum class FleetPathStatus { kSolved, kUnresolved, kStopped };
std::string_view to_string(FleetPathStatus status);

struct FleetPaths {
  FleetPathStatus status = FleetPathStatus::kUnresolved;
  std::vector<VehiclePlan> vehicles;
  int makespan_steps = 0;          // max_i T_i
  long long sum_of_steps = 0;      // sum_i T_i
  int conflicts_resolved = 0;      // conflicts met while stepping through time
  int detours = 0;                 // resolved by a space-time A* re-plan
  int waits = 0;                   // resolved by a one-step wait
  std::uint64_t expansions = 0;    // over all space-time searches
  double time_s = 0.0;
  std::string detail;              // why, when not solved
};

FleetPaths buildFleetPaths(const GridLayer& grid, const FleetProblem& problem, const TravelTimeTable& table,
                           const FleetAllocation& allocation, const FleetPathOptions& options = {},
                           const TerminationCondition& stop = TerminationCondition());

}  // namespace skyroute
