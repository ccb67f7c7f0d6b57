// Exact allocation for small instances: the least makespan (then least sum of route times) over
// every split of the tasks among the vehicles and every visiting order, on the travel-time table
// (collisions ignored, like the other allocators). Rather than listing the N_t! C(N_t+N_u-1, N_u-1)
// sequences one by one it gets the same optimum by dynamic programming: Held-Karp per vehicle for
// the best tour of every task subset (2^N_t N_t^2), then the best split of the set among the
// vehicles (N_u 3^N_t). The paper's largest experiment (5 vehicles, 15 tasks) takes well under a
// second.
#pragma once

#include "planning/core/result.hpp"
#include "planning/core/termination.hpp"
#include "planning/fleet/fleet_allocation.hpp"
#include "planning/fleet/fleet_problem.hpp"
#include "planning/fleet/fleet_travel_times.hpp"

namespace skyroute {

struct FleetExactOptions {
  int max_tasks = 16;  // refuse larger instances (memory 2^N_t N_t ints, time 3^N_t)
};

// Errors: kInvalidArgument when the instance has more than options.max_tasks tasks;
// kUnreachable when no split respects reachability and capacities; kTimeout / kCancelled.
Result<FleetAllocation> allocateExact(const FleetProblem& problem, const TravelTimeTable& table,
                                      const FleetExactOptions& options = {},
                                      const TerminationCondition& stop = TerminationCondition());

}  // namespace skyroute
