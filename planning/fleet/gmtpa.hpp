// GMTPA's greedy task allocation (seed 002, section 3.2, Algorithm 1). Each round evaluates every
// unassigned task j at every vehicle i and every position k = 1 .. n_i + 1 of its sequence, the
// cost being the rise of the makespan c_ijk = T'_max - T_max, and assigns the cheapest. N_t
// rounds of at most (N_t - n)(N_u + n) insertions: O(N_t^2 (N_u + N_t)).
//
// Ties (frequent: every insertion that keeps a vehicle under T_max costs 0) are broken by the
// rise of the vehicle's own route time T'_i - T_i, then by task and vehicle index, then
// the later position. The
// second key is our choice, not the paper's: among insertions that leave T_max alone it prefers
// the one that wastes least travel, which keeps room for later rounds. The order is total, so the
// result is deterministic.
#pragma once

#include "planning/core/result.hpp"
#include "planning/fleet/fleet_allocation.hpp"
#include "planning/fleet/fleet_problem.hpp"
#include "planning/fleet/fleet_travel_times.hpp"

namespace skyroute {

// Errors: kUnreachable naming a task that no vehicle with room left can reach.
Result<FleetAllocation> allocateGreedy(const FleetProblem& problem, const TravelTimeTable& table);

}  // namespace skyroute
