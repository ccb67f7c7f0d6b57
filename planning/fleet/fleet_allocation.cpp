#include "planning/fleet/fleet_allocation.hpp"

#include <algorithm>

namespace skyroute {

int routeSteps(const TravelTimeTable& table, int vehicle, std::span<const int> sequence) {
  if (sequence.empty()) return 0;
  long long total = table.depotToTask(vehicle, sequence.front());
  for (std::size_t k = 1; k < sequence.size(); ++k) {
    const int leg = table.taskToTask(sequence[k - 1], sequence[k]);
    if (leg == kUnreachableSteps) return kUnreachableSteps;
    total += leg;
  }
  const int back = table.taskToDepot(sequence.back(), vehicle);
  if (total >= kUnreachableSteps || back == kUnreachableSteps) return kUnreachableSteps;
  total += back;
  return total >= kUnreachableSteps ? kUnreachableSteps : static_cast<int>(total);
}

void refreshAllocationCosts(const TravelTimeTable& table, FleetAllocation& allocation) {
  allocation.route_steps.assign(allocation.sequences.size(), 0);
  allocation.makespan_steps = 0;
  allocation.sum_of_steps = 0;
  for (std::size_t i = 0; i < allocation.sequences.size(); ++i) {
    const int t = routeSteps(table, static_cast<int>(i), allocation.sequences[i]);
    allocation.route_steps[i] = t;
    allocation.makespan_steps = std::max(allocation.makespan_steps, t);
    if (t != kUnreachableSteps) allocation.sum_of_steps += t;
  }
}

}  // namespace skyroute
