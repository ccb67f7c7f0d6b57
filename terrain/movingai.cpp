#include "terrain/movingai.hpp"

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <fstream>
#include <sstream>

namespace skyroute {
namespace {

Error parseError(const std::string& path, int line, const std::string& what) {
  return make_error(ErrorCode::kParseError, path, "line " + std::to_string(line) + ": " + what);
}

// The power of ten of the last digit `number` was printed with, negated: 2 for "1238.41", 0 for
// "1239", -3 for "1.2e5" (as the number of decimals it would have in fixed notation).
int printedDecimals(const std::string& number) {
  const std::size_t exponent_at = number.find_first_of("eE");
  const std::string mantissa = number.substr(0, exponent_at);
  const std::size_t point = mantissa.find('.');
  const int decimals = point == std::string::npos ? 0 : static_cast<int>(mantissa.size() - point - 1);
  // strtol saturates where atoi would overflow; a double's exponent is within +-400 anyway.
  const long exponent = exponent_at == std::string::npos ? 0 : std::strtol(number.c_str() + exponent_at + 1, nullptr, 10);
  return decimals - static_cast<int>(std::clamp(exponent, -400L, 400L));
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
    p.optimal_tolerance = 0.5 * std::pow(10.0, -printedDecimals(optimal_text));
    problems.push_back(p);
  }
  return problems;
}

}  // namespace skyroute
