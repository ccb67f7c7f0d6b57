// `skyroute fleet --map` / `--cells`: the 2D fleet problem on a grid (a Moving AI map or a DEM's
// flight band), vehicles' depots and tasks as X,Y cells: GMTPA allocation (greedy Algorithm 1,
// the GA baseline or the exact solver), collision-free time-stamped paths, verified. Writes
//   --out: {"makespan": N, "vehicles": [{"depot": [x, y], "tasks": [[x, y], ...],
//           "path": [[t, x, y], ...]}, ...]}   with one path entry per step 0 .. makespan
//   --png: the grid with each vehicle's route in its own colour.
#pragma once

#include <cstdint>
#include <string>

#include "terrain/grid_from_terrain.hpp"

namespace skyroute::cli {

struct FleetGridArgs {
  std::string map;              // a Moving AI .map, or else
  std::string dem;              // the DEM whose flight band is the grid
  std::string vehicles;         // depots "X,Y;X,Y;..."
  std::string tasks;            // "X,Y;X,Y;..."
  std::string algo = "greedy";  // greedy | ga | exact
  std::uint64_t seed = 1;       // of the GA
  int capacity = 0;             // most tasks per vehicle (0: no limit)
  double budget_s = 60.0;
  TerrainGridOptions grid_options;  // the DEM's grid
  std::string out;              // .json
  std::string png;              // .png
};

void runFleetOnGrid(const FleetGridArgs& args);

}  // namespace skyroute::cli
