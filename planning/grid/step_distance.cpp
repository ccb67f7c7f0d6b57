#include "planning/grid/step_distance.hpp"

namespace skyroute {

std::vector<int> bfsDistanceMap4(const GridLayer& grid, GridCell source) {
  std::vector<int> dist(grid.cellCount(), kUnreachableSteps);
  if (grid.blocked(source)) return dist;
  std::vector<std::size_t> queue;
  queue.reserve(grid.cellCount());
  dist[grid.index(source)] = 0;
  queue.push_back(grid.index(source));
  for (std::size_t head = 0; head < queue.size(); ++head) {
    const GridCell c = grid.cellOf(queue[head]);
    const int next = dist[queue[head]] + 1;
    for (const GridCell& m : kFourMoves) {
      const GridCell n{c.x + m.x, c.y + m.y};
      if (grid.blocked(n)) continue;
      const std::size_t i = grid.index(n);
      if (dist[i] != kUnreachableSteps) continue;
      dist[i] = next;
      queue.push_back(i);
    }
  }
  return dist;
}

std::vector<GridCell> descendDistanceMap4(const GridLayer& grid, const std::vector<int>& distance_map, GridCell from) {
  std::vector<GridCell> path;
  if (!grid.inside(from) || distance_map[grid.index(from)] == kUnreachableSteps) return path;
  GridCell c = from;
  path.push_back(c);
  while (distance_map[grid.index(c)] > 0) {
    const int want = distance_map[grid.index(c)] - 1;
    for (const GridCell& m : kFourMoves) {
      const GridCell n{c.x + m.x, c.y + m.y};
      if (grid.inside(n) && distance_map[grid.index(n)] == want) {
        c = n;
        break;
      }
    }
    path.push_back(c);
  }
  return path;
}

}  // namespace skyroute
