// Small maps with a known any-angle optimum for the any-angle planners' tests.
#pragma once

#include <string>
#include <vector>

#include "terrain/grid_layer.hpp"
#include "tests/planning/any_angle_reference.hpp"

namespace skyroute::testing {

struct KnownMap {
  std::string name;
  GridLayer grid;
  GridCell start;
  GridCell goal;
};

inline std::vector<KnownMap> knownMaps() {
  std::vector<KnownMap> maps;
  // Open field: the optimum is the straight segment.
  maps.push_back({"open field", GridLayer(24, 18), GridCell{1, 2}, GridCell{22, 15}});
  // Single wall: the optimum bends once past the wall's free end. 22 x 14 cells, the wall at
  // column 10 from row 2 to the bottom.
  GridLayer single_wall(22, 14);
  std::vector<GridCell> wall;
  for (int y = 2; y < 14; ++y) wall.push_back(GridCell{10, y});
  single_wall.setStaticBlocked(wall, true);
  maps.push_back({"single wall", single_wall, GridCell{3, 12}, GridCell{19, 10}});
  // Corridor: a three-cell-wide U-shaped corridor around a block.
  maps.push_back({"corridor", gridFromText({
                                  "################",
                                  "#..............#",
                                  "#..............#",
                                  "#..............#",
                                  "#...########...#",
                                  "#...########...#",
                                  "#...#......#...#",
                                  "#...#......#...#",
                                  "#...#......#...#",
                                  "#...#......#...#",
                                  "################",
                              }),
                  GridCell{2, 8}, GridCell{13, 8}});
  return maps;
}

}  // namespace skyroute::testing
