#include "planning/hab_pp_output.hpp"

#include <algorithm>

#include "planning/any_angle_search.hpp"

namespace skyroute::habpp {

namespace {

bool validPath(const GridLayer& grid, const Path& p, GridCell start, GridCell goal) {
  if (p.empty() || !(p.front() == start) || !(p.back() == goal)) return false;
  for (std::size_t i = 1; i < p.size(); ++i) {
    if (!grid.lineOfSight(p[i - 1], p[i])) return false;
  }
  return true;
}

// The grid with every cell farther than r (Chebyshev) from all the paths' touched cells blocked.
GridLayer corridorGrid(const GridLayer& grid, const Path* paths, std::size_t count, int r) {
  const int w = grid.width(), h = grid.height();
  std::vector<std::uint8_t> keep(grid.cellCount(), 0);
  for (std::size_t k = 0; k < count; ++k) {
    const Path& path = paths[k];
    for (std::size_t s = 0; s + 1 < path.size(); ++s) {
      for (GridCell c : GridLayer::segmentCells(path[s], path[s + 1])) {
        for (int y = std::max(0, c.y - r); y <= std::min(h - 1, c.y + r); ++y) {
          for (int x = std::max(0, c.x - r); x <= std::min(w - 1, c.x + r); ++x) {
            keep[static_cast<std::size_t>(y) * w + x] = 1;
          }
        }
      }
    }
  }
  std::vector<GridCell> blocked;
  for (std::size_t i = 0; i < keep.size(); ++i) {
    const GridCell c = grid.cellOf(i);
    if (keep[i] == 0 || grid.blocked(c)) blocked.push_back(c);
  }
  GridLayer out(w, h, grid.cellSize(), grid.origin());
  out.setStaticBlocked(blocked, true);
  return out;
}

}  // namespace

Path tautPath(const GridLayer& grid, const Path& path, int corridor_cells, int tighten_passes) {
  return tautPath(grid, std::vector<Path>{path}, corridor_cells, tighten_passes);
}

Path tautPath(const GridLayer& grid, const std::vector<Path>& routes, int corridor_cells, int tighten_passes) {
  const Path& path = routes.front();
  if (path.size() <= 2) return path;
  const GridCell start = path.front(), goal = path.back();
  Path best = path;
  double best_length = polylineLength(path);
  auto offer = [&](const Path& p) {
    const double length = polylineLength(p);
    if (length < best_length - 1e-9 && validPath(grid, p, start, goal)) {
      best = p;
      best_length = length;
    }
  };
  offer(tightenPath(grid, path, tighten_passes));
  for (std::size_t k = 1; k < routes.size(); ++k) offer(routes[k]);  // each route as it is, when shorter
  if (corridor_cells > 0) {
    // The first route's corridor alone, then the union of all routes' corridors: Theta* is not
    // exactly optimal, so the wider corridor is not guaranteed to give the shorter path; the
    // shorter of the two wins.
    for (std::size_t count : {std::size_t{1}, routes.size()}) {
      const GridLayer corridor = corridorGrid(grid, routes.data(), count, corridor_cells);
      const AnyAngleResult theta = thetaStar(corridor, start, goal);
      if (theta.status == AnyAngleStatus::kExact) offer(tightenPath(grid, theta.path, tighten_passes));
      if (routes.size() == 1) break;
    }
  }
  return best;
}

}  // namespace skyroute::habpp
