// GMTPA end to end (seed 002): validate the problem, travel times from breadth-first searches,
// allocate (greedy Algorithm 1, the GA baseline or the exact solver), for greedy then the
// improvement stage of planning/fleet/fleet_local_search.hpp (ours, not the paper's; switch it off with
// improvement.enabled = false to run the pure Algorithm 1), build collision-free paths (section
// 3.3) and verify them with the independent checker. A plan is returned only when the
// checker finds it conflict-free and complete.
#pragma once

#include <optional>
#include <string_view>

#include "planning/core/result.hpp"
#include "planning/core/termination.hpp"
#include "planning/fleet/fleet_allocation.hpp"
#include "planning/fleet/fleet_conflict_checker.hpp"
#include "planning/fleet/fleet_exact.hpp"
#include "planning/fleet/fleet_ga.hpp"
#include "planning/fleet/fleet_local_search.hpp"
#include "planning/fleet/fleet_paths.hpp"
#include "planning/fleet/fleet_problem.hpp"

namespace skyroute {

enum class FleetAllocator { kGreedy, kGenetic, kExact };
std::string_view to_string(FleetAllocator allocator);                // "greedy", "ga", "exact"
std::optional<FleetAllocator> parseFleetAllocator(std::string_view name);

struct FleetPlannerOptions {
  FleetAllocator allocator = FleetAllocator::kGreedy;
  FleetGaOptions ga;
  FleetExactOptions exact;
  FleetImprovementOptions improvement;  // after the greedy construction only
  FleetPathOptions paths;
};

struct FleetPlan {
  FleetAllocation allocation;   // what the allocator planned (makespan without collisions)
  FleetImprovementReport improvement;  // greedy: what the improvement stage did (start = Algorithm 1)
  FleetPaths paths;             // the collision-free, time-stamped paths
  FleetCheckReport check;       // the independent checker's verdict (ok() on every returned plan)
  double table_time_s = 0.0;    // breadth-first travel times
  double total_time_s = 0.0;    // validation + table + allocation + paths + check
  int makespan() const { return paths.makespan_steps; }
};

// Per-vehicle paths and sequences in the checker's plain form.
std::vector<std::vector<GridCell>> pathsOf(const FleetPaths& paths);
std::vector<std::vector<int>> sequencesOf(const FleetPaths& paths);

// Errors: the validation errors of validateFleetProblem, the allocators' errors, kUnreachable
// when the conflicts cannot be resolved, kTimeout / kCancelled when `stop` fires, kInternal if
// the checker rejects the plan (a bug).
Result<FleetPlan> planFleet(const GridLayer& grid, const FleetProblem& problem, const FleetPlannerOptions& options = {},
                            const TerminationCondition& stop = TerminationCondition());

}  // namespace skyroute
