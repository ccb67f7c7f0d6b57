// A task allocation: which vehicle does which tasks in which order (r_ij of eq. 3 plus the
// visiting order), with the route times T_i it implies on the travel-time table (collisions
// ignored, as in the allocation stage of seed 002, section 3.1). Produced by the greedy GMTPA
// allocation, the genetic-algorithm baseline and the exact solver alike.
#pragma once

#include <cstdint>
#include <span>
#include <string>
#include <vector>

#include "planning/fleet/fleet_travel_times.hpp"

namespace skyroute {

struct FleetAllocation {
  std::vector<std::vector<int>> sequences;  // per vehicle: task indices in visiting order
  std::vector<int> route_steps;             // per vehicle: T_i, depot -> tasks -> depot
  int makespan_steps = 0;                   // T_max = max_i T_i (a lower bound for the paths)
  long long sum_of_steps = 0;               // sum_i T_i
  std::string algorithm;                    // "greedy", "ga", "exact"
  double time_s = 0.0;                      // allocation time only (not the travel-time table)
  std::uint64_t evaluations = 0;            // candidate insertions / fitness evaluations / DP cells
};

// T_i of one vehicle's sequence; kUnreachableSteps when a leg is unreachable.
int routeSteps(const TravelTimeTable& table, int vehicle, std::span<const int> sequence);

// Recomputes route_steps, makespan_steps and sum_of_steps from the sequences.
void refreshAllocationCosts(const TravelTimeTable& table, FleetAllocation& allocation);

}  // namespace skyroute
