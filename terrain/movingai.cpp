#include "terrain/movingai.hpp"

#include <algorithm>
#include <cmath>
#include <fstream>
#include <sstream>

namespace skyroute {
namespace {

Error parseError(const std::string& path, int line, const std::string& what) {
  return make_error(ErrorCode::kParseError, path, "line " + std::to_string(line) + ": " + what);
}

}  // namespace

Result<GridLayer> loadMovingAiMap(const std::string& path) {
  std::ifstream in(path);
  if (!in) return make_error(ErrorCode::kFileNotFound, path, "cannot open the map file");
  return parseMovingAiMap(in, path);
}

Result<GridLayer> parseMovingAiMap(std::istream& in, const std::string& path) {
  int width = -1;
  int height = -1;
  std::string line;
  int line_no = 0;
  bool in_map = false;
  while (!in_map && std::getline(in, line)) {
    ++line_no;
    std::istringstream words(line);
    std::string key;
    words >> key;
    if (key == "type" || key.empty()) continue;
    if (key == "height") {
      words >> height;
    } else if (key == "width") {
      words >> width;
    } else if (key == "map") {
      in_map = true;
    } else {
      return parseError(path, line_no, "unexpected header '" + key + "'");
    }
  }
  if (!in_map) return parseError(path, line_no, "no 'map' line");
  if (width <= 0 || height <= 0 || width > 100000 || height > 100000) {
    return parseError(path, line_no, "missing or absurd width/height");
  }
  // The rows are read before the grid is made: a header alone may declare 10^10 cells.
  std::vector<GridCell> walls;
  for (int y = 0; y < height; ++y) {
    if (!std::getline(in, line)) return parseError(path, line_no + 1, "map has fewer rows than its height");
    ++line_no;
    if (!line.empty() && line.back() == '\r') line.pop_back();
    if (static_cast<int>(line.size()) < width) return parseError(path, line_no, "row shorter than the width");
    for (int x = 0; x < width; ++x) {
      switch (line[x]) {
        case '.': case 'G': case 'S': break;
        case '@': case 'O': case 'T': case 'W': walls.push_back(GridCell{x, y}); break;
        default: return parseError(path, line_no, std::string("unknown map character '") + line[x] + "'");
      }
    }
  }
  GridLayer grid(width, height);
  grid.setStaticBlocked(walls, true);
  return grid;
}

Result<std::vector<MovingAiProblem>> loadMovingAiScenario(const std::string& path) {
  std::ifstream in(path);
  if (!in) return make_error(ErrorCode::kFileNotFound, path, "cannot open the scenario file");
  return parseMovingAiScenario(in, path);
}

Result<std::vector<MovingAiProblem>> parseMovingAiScenario(std::istream& in, const std::string& path) {
  std::vector<MovingAiProblem> problems;
  std::vector<int> decimals_of;  // per problem; -1 = printed without a decimal point
  int most_decimals = -1;
  std::string line;
  int line_no = 0;
  while (std::getline(in, line)) {
    ++line_no;
    if (!line.empty() && line.back() == '\r') line.pop_back();
    if (line.empty()) continue;
    if (line_no == 1 && line.rfind("version", 0) == 0) continue;
    std::istringstream fields(line);
    MovingAiProblem p;
    int map_width = 0;
    int map_height = 0;
    std::string optimal_text;
    if (!(fields >> p.bucket >> p.map_name >> map_width >> map_height >> p.start.x >> p.start.y >> p.goal.x >>
          p.goal.y >> optimal_text)) {
      return parseError(path, line_no, "expected 9 fields: bucket map width height sx sy gx gy optimal");
    }
    std::istringstream optimal_field(optimal_text);
    if (!(optimal_field >> p.optimal_length) || !optimal_field.eof()) {
      return parseError(path, line_no, "the optimal length '" + optimal_text + "' is not a number");
    }
    const std::size_t point = optimal_text.find('.');
    const int decimals = point == std::string::npos ? -1 : static_cast<int>(optimal_text.size() - point - 1);
    decimals_of.push_back(decimals);
    most_decimals = std::max(most_decimals, decimals);
    problems.push_back(p);
  }
  for (std::size_t i = 0; i < problems.size(); ++i) {
    // A file of whole numbers only prints exact costs (a 4-connected map): they are compared to 1e-3.
    if (most_decimals < 0) {
      problems[i].optimal_tolerance = 1e-3;
      continue;
    }
    const int decimals = decimals_of[i] >= 0 ? decimals_of[i] : most_decimals;
    problems[i].optimal_tolerance = std::pow(10.0, -decimals);
  }
  return problems;
}

}  // namespace skyroute
