// Seeded random grids for the grid-search tests.
#pragma once

#include <random>
#include <vector>

#include "terrain/grid_layer.hpp"

namespace skyroute {

// Each cell blocked with probability `density`, drawn from `rng` row by row.
inline GridLayer randomGrid(int w, int h, double density, std::mt19937& rng) {
  GridLayer grid(w, h);
  std::vector<GridCell> blocked;
  std::bernoulli_distribution wall(density);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x)
      if (wall(rng)) blocked.push_back({x, y});
  grid.setStaticBlocked(blocked, true);
  return grid;
}

}  // namespace skyroute
