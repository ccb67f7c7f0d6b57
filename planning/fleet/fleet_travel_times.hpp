// Shortest travel times on the 4-connected grid (one step per move, eq. 6 of seed 002), from
// breadth-first distance maps that respect the static obstacles but not the other vehicles, as
// the allocation stage of section 3.1 needs. The maps double as exact heuristics for the
// space-time search.
#pragma once

#include <vector>

#include "planning/fleet/fleet_problem.hpp"
#include "planning/grid/step_distance.hpp"
#include "terrain/grid_layer.hpp"

namespace skyroute {

// Travel times between every depot and task, and between tasks. The grid is undirected, so one
// map per place serves both directions.
class TravelTimeTable {
 public:
  static TravelTimeTable build(const GridLayer& grid, const FleetProblem& problem);

  int vehicleCount() const { return static_cast<int>(depot_maps_.size()); }
  int taskCount() const { return static_cast<int>(task_maps_.size()); }
  int depotToTask(int vehicle, int task) const { return depot_task_[vehicle * taskCount() + task]; }
  int taskToDepot(int task, int vehicle) const { return depotToTask(vehicle, task); }
  int taskToTask(int a, int b) const { return task_task_[a * taskCount() + b]; }
  const std::vector<int>& mapToTask(int task) const { return task_maps_[task]; }
  const std::vector<int>& mapToDepot(int vehicle) const { return depot_maps_[vehicle]; }
  double buildSeconds() const { return build_s_; }

 private:
  std::vector<std::vector<int>> depot_maps_;
  std::vector<std::vector<int>> task_maps_;
  std::vector<int> depot_task_;  // [vehicle * N_t + task]
  std::vector<int> task_task_;   // [a * N_t + b]
  double build_s_ = 0.0;
};

}  // namespace skyroute
