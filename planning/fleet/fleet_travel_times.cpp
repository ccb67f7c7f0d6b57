#include "planning/fleet/fleet_travel_times.hpp"

#include <chrono>

namespace skyroute {

TravelTimeTable TravelTimeTable::build(const GridLayer& grid, const FleetProblem& problem) {
  const auto start = std::chrono::steady_clock::now();
  TravelTimeTable table;
  const int nu = problem.vehicleCount();
  const int nt = problem.taskCount();
  for (const FleetVehicle& v : problem.vehicles) table.depot_maps_.push_back(bfsDistanceMap4(grid, v.depot));
  for (const FleetTask& t : problem.tasks) table.task_maps_.push_back(bfsDistanceMap4(grid, t.cell));
  auto at = [&](const std::vector<int>& map, GridCell c) {
    return grid.inside(c) ? map[grid.index(c)] : kUnreachableSteps;
  };
  table.depot_task_.resize(static_cast<std::size_t>(nu) * nt);
  table.task_task_.resize(static_cast<std::size_t>(nt) * nt);
  for (int i = 0; i < nu; ++i) {
    for (int j = 0; j < nt; ++j) table.depot_task_[i * nt + j] = at(table.depot_maps_[i], problem.tasks[j].cell);
  }
  for (int a = 0; a < nt; ++a) {
    for (int b = 0; b < nt; ++b) table.task_task_[a * nt + b] = at(table.task_maps_[a], problem.tasks[b].cell);
  }
  table.build_s_ = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return table;
}

}  // namespace skyroute
