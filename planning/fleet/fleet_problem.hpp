// The multi-vehicle task problem of seed 002, section 2 (equations 1-9): N_u vehicles at depots
// and N_t tasks on a 4-connected grid. Each task is done by exactly one vehicle (eq. 3), a vehicle
// does at most its capacity N_i of tasks (eq. 2), every vehicle returns to its depot and stays
// there (eq. 7), one move to a 4-neighbour or a wait per time step (eq. 6), no two vehicles in one
// cell at one step (eq. 4) and, beyond the paper, no two vehicles swapping cells in one step.
// Objective: the makespan T_max = max_i T_i (eq. 1).
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "planning/core/result.hpp"
#include "terrain/grid_layer.hpp"

namespace skyroute {

struct FleetVehicle {
  std::string id;
  GridCell depot;
  int max_tasks = 0;  // N_i of eq. (2); 0 means no limit
};

struct FleetTask {
  std::string id;
  GridCell cell;
};

// An obstacle whose motion is known (from the obstacle feed, predicted forward): it covers
// cells[k] at step start_step + k and no cell before or after that window. A larger obstacle is
// several of these moving together.
struct MovingObstacle {
  std::string id;
  int start_step = 0;
  std::vector<GridCell> cells;

  std::optional<GridCell> cellAt(int step) const;
  int endStep() const { return start_step + static_cast<int>(cells.size()); }  // first step after
  // Moves (dx, dy) cells per step from `start` for `steps` steps (covers steps + 1 cells).
  static MovingObstacle straight(std::string id, GridCell start, int dx, int dy, int start_step, int steps);
};

struct FleetProblem {
  std::vector<FleetVehicle> vehicles;
  std::vector<FleetTask> tasks;
  std::vector<MovingObstacle> moving_obstacles;

  int vehicleCount() const { return static_cast<int>(vehicles.size()); }
  int taskCount() const { return static_cast<int>(tasks.size()); }
  // Capacity of vehicle i with "no limit" resolved to the number of tasks.
  int capacity(int i) const;
};

// Cheap checks first, then reachability. Every error names the offending item:
//   kInvalidArgument: no vehicles, empty or duplicate id, negative capacity, two depots on one
//                     cell, more tasks than the vehicles' capacities allow, bad obstacle window;
//   kOutsideMap:      a depot or task outside the grid;
//   kOccupied:        a depot or task on a blocked cell, a task on a depot, a moving obstacle on
//                     a depot at step 0;
//   kUnreachable:     a task no vehicle can reach (4-connected moves).
Status validateFleetProblem(const GridLayer& grid, const FleetProblem& problem);

std::string describeCell(GridCell c);  // "(x, y)"

}  // namespace skyroute
