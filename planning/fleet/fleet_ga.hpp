// The genetic-algorithm allocation that seed 002 compares GMTPA against (its section 4, after its
// reference [9]); the same path stage follows it. A random-key encoding: each task carries the
// vehicle that does it and a key in [0, 1); a vehicle visits its tasks in increasing key order.
// Fitness: the makespan of the decoded allocation on the travel-time table, then the sum of route
// times. Tournament selection, uniform crossover on task genes, three mutations (move a task to
// another vehicle, swap two tasks' genes, reverse a stretch of one vehicle's order), elitism.
// Capacities are kept by a deterministic repair. All randomness comes from the seed.
#pragma once

#include <cstdint>

#include "planning/core/result.hpp"
#include "planning/core/termination.hpp"
#include "planning/fleet/fleet_allocation.hpp"
#include "planning/fleet/fleet_problem.hpp"
#include "planning/fleet/fleet_travel_times.hpp"

namespace skyroute {

struct FleetGaOptions {
  std::uint64_t seed = 1;
  int population = 100;      // individuals per generation
  int generations = 300;     // upper bound on generations
  int tournament = 3;        // tournament size of the selection
  int elite = 2;             // best individuals copied unchanged
  double crossover_rate = 0.9;
  double mutation_rate = 0.3;  // probability of each of the three mutations per child
};

// Errors: kInvalidArgument naming a bad option; kUnreachable when no individual is feasible.
// Stops early (with the best found so far) when `stop` fires.
Result<FleetAllocation> allocateGenetic(const FleetProblem& problem, const TravelTimeTable& table,
                                        const FleetGaOptions& options = {},
                                        const TerminationCondition& stop = TerminationCondition());

}  // namespace skyroute
