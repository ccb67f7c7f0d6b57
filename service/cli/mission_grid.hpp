// `skyroute mission --cells` / `--map`: the multi-point mission on a 2D grid (a Moving AI map or a
// DEM's flight band), points given as X,Y cells: the MMD*L (or per-pair D* Lite) cost matrix, the
// open-TSP visiting order B .. E and the legs, in cell edges.
#pragma once

#include <string>
#include <vector>

#include "terrain/grid_from_terrain.hpp"

namespace skyroute::cli {

struct MissionGridArgs {
  std::string map;                // a Moving AI .map, or else
  std::string dem;                // the DEM whose flight band is the grid
  std::string from;               // X,Y
  std::vector<std::string> via;   // X,Y each
  std::string to;                 // X,Y
  std::string algo = "mmdstar";   // mmdstar | dstar-lite
  bool paper_moves = false;
  bool json = false;
  bool with_paths = false;
  TerrainGridOptions grid_options;  // the DEM's grid
};

void runMissionOnGrid(const MissionGridArgs& args);

}  // namespace skyroute::cli
