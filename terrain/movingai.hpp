// Loaders for the Moving AI grid benchmark (Sturtevant 2012): `.map` files into a GridLayer and
// `.scen` files into problems with their optimal lengths, the independent check of every search.
#pragma once

#include <istream>
#include <string>
#include <vector>

#include "planning/core/result.hpp"
#include "terrain/grid_layer.hpp"

namespace skyroute {

// `.` `G` `S` are passable; `@` `O` `T` `W` are blocked; any other character is a parse error
// naming the line. Cell (x, y) is column x, row y, both from 0, as in the `.scen` files.
Result<GridLayer> loadMovingAiMap(const std::string& path);
// The same from a stream; source_name names it in errors (the path).
Result<GridLayer> parseMovingAiMap(std::istream& in, const std::string& source_name);

struct MovingAiProblem {
  int bucket = 0;
  std::string map_name;
  GridCell start;
  GridCell goal;
  double optimal_length = 0.0;  // 8-connected, diagonal sqrt(2), no corner cutting
  // Half a unit in the last digit this line printed optimal_length with: a cost within this of
  // optimal_length (plus the floating error of the comparison) rounds to the printed text. Each
  // line by its own digits: a generator printing 6 significant digits with %g writes 1239.0042
  // as "1239" (tolerance 0.5) and 6.242641 as "6.24264" (5e-6) in one file.
  double optimal_tolerance = 0.0;
};

// Parses a `version 1` scenario file; a malformed line is an error naming its line number.
Result<std::vector<MovingAiProblem>> loadMovingAiScenario(const std::string& path);
Result<std::vector<MovingAiProblem>> parseMovingAiScenario(std::istream& in, const std::string& source_name);

}  // namespace skyroute
