// Improvement stage after GMTPA's greedy construction (seed 002's Algorithm 1 stays as it is, in
// planning/gmtpa.*; this stage is our addition, not the paper's). Algorithm 1 commits each task
// for good in the round it is inserted, so a task placed early on the vehicle that later becomes
// the makespan vehicle stays there, and the greedy makespan ends 4-17 % above the optimum on the
// paper's experiment. This stage is a deterministic local search on the allocation, on the same
// travel-time table (collisions ignored, like the allocators):
//
// - Objective: the route times sorted from the longest down, compared lexicographically. Its first
//   entry is the makespan T_max; the later ones let a change that shortens the second-longest
//   route count as progress, so the search is not stuck on the plateaus of a pure min-max. Two
//   allocations that differ on a few vehicles compare as those vehicles' sorted times do.
// - Pairs: for two vehicles holding at most pair_exact_max_tasks tasks together, the best split
//   of those tasks between the two, every subset with its exact tour (Held-Karp over all subsets,
//   pruned by the pair's current longer route). Above that size, the best relocation of one task
//   or swap of two, each changed route re-ordered (Held-Karp up to exact_order_max_tasks tasks,
//   else 2-opt and Or-opt). Pairs are visited from the longest route down; the first pair that
//   improves is changed and the visit starts again. A pair is tried again only once one of its
//   vehicles has changed.
// - Triples: at a pair optimum, the same exact split among the longest route's vehicle and two
//   others, up to triple_exact_max_tasks tasks; this finds the three-way exchanges pairs miss.
// - It stops when nothing improves, when the makespan reaches a lower bound (the round trip to the
//   task whose nearest vehicle is farthest), or when max_work is spent.
// - The result is never worse than the input: the input is kept unless the search ends better by
//   makespan, then sum of route times, then sorted route times. Capacities and reachability hold.
// - Work is counted in elementary steps (table cells set up, partial paths extended, splits
//   looked at); no clock is read, so the result depends only on the input and the options.
#pragma once

#include <cstdint>

#include "planning/fleet/fleet_allocation.hpp"
#include "planning/fleet/fleet_problem.hpp"
#include "planning/fleet/fleet_travel_times.hpp"

namespace skyroute {

struct FleetImprovementOptions {
  bool enabled = true;                 // false: the pure Algorithm 1 allocation
  int exact_order_max_tasks = 6;       // Held-Karp re-ordering up to this many tasks on a vehicle
  int pair_exact_max_tasks = 10;       // exact re-split of two vehicles up to this many tasks together
  int triple_exact_max_tasks = 9;      // exact re-split of three vehicles up to this many tasks
  std::uint64_t max_work = 4'000'000;  // elementary evaluations before the search stops
};

struct FleetImprovementReport {
  int start_makespan_steps = 0;  // the input's T_max
  int moves = 0;                 // improving changes applied (re-splits, relocations, swaps)
  std::uint64_t work = 0;        // elementary evaluations spent
  bool budget_exhausted = false;
};

// Improves `start` (sequences on `table`; capacities and reachability kept) and returns the
// better allocation; `algorithm`, `time_s` and `evaluations` of the result extend the input's.
// An allocation whose routes are not all reachable is returned unchanged.
FleetAllocation improveAllocation(const FleetProblem& problem, const TravelTimeTable& table,
                                  const FleetAllocation& start, const FleetImprovementOptions& options = {},
                                  FleetImprovementReport* report = nullptr);

}  // namespace skyroute
