#include "planning/colony/hab_pp_output.hpp"

#include <algorithm>
#include <cmath>

#include "planning/grid/any_angle_search.hpp"

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

Path replanWindows(const GridLayer& grid, const Path& path, const WindowOptions& options, int tighten_passes) {
  if ((options.segments < 2 && options.span_cells <= 0.0) || path.size() <= 2) return path;
  const GridCell start = path.front(), goal = path.back();
  Path best = path;
  double best_length = polylineLength(best);
  // Windows already re-planned without gain (ends and piece unchanged): a change elsewhere leaves
  // them as they were, so later passes skip them instead of running the same Theta* again.
  struct Tried {
    GridCell from, to;
    double piece;
  };
  std::vector<Tried> tried;
  for (int pass = 0; pass < options.max_passes; ++pass) {
    bool changed = false;
    for (std::size_t i = 0; i + 2 < best.size(); ++i) {
      std::size_t j = i + 1;
      double piece = segmentLength(best[i], best[j]);
      while (j + 1 < best.size() && (j < i + static_cast<std::size_t>(std::max(options.segments, 1)) ||
                                     piece + segmentLength(best[j], best[j + 1]) <= options.span_cells)) {
        piece += segmentLength(best[j], best[j + 1]);
        ++j;
      }
      if (j < i + 2) continue;
      const bool known = std::any_of(tried.begin(), tried.end(), [&](const Tried& t) {
        return t.from == best[i] && t.to == best[j] && std::abs(t.piece - piece) < 1e-9;
      });
      if (known) continue;
      GridCell lo = best[i], hi = best[i];
      for (std::size_t k = i + 1; k <= j; ++k) {
        lo = GridCell{std::min(lo.x, best[k].x), std::min(lo.y, best[k].y)};
        hi = GridCell{std::max(hi.x, best[k].x), std::max(hi.y, best[k].y)};
      }
      const int m = options.margin_cells;
      lo = GridCell{std::max(0, lo.x - m), std::max(0, lo.y - m)};
      hi = GridCell{std::min(grid.width() - 1, hi.x + m), std::min(grid.height() - 1, hi.y + m)};
      const GridLayer box = grid.cropped(lo, hi.x - lo.x + 1, hi.y - lo.y + 1);
      const AnyAngleResult local =
          thetaStar(box, GridCell{best[i].x - lo.x, best[i].y - lo.y}, GridCell{best[j].x - lo.x, best[j].y - lo.y});
      if (local.status != AnyAngleStatus::kExact || local.length_cells >= piece - 1e-9) {
        tried.push_back(Tried{best[i], best[j], piece});
        continue;
      }
      Path next(best.begin(), best.begin() + static_cast<std::ptrdiff_t>(i));
      for (const GridCell& c : local.path) next.push_back(GridCell{c.x + lo.x, c.y + lo.y});
      next.insert(next.end(), best.begin() + static_cast<std::ptrdiff_t>(j) + 1, best.end());
      next = tightenPath(grid, next, tighten_passes);
      const double length = polylineLength(next);
      if (length < best_length - 1e-9 && validPath(grid, next, start, goal)) {
        best = std::move(next);
        best_length = length;
        changed = true;
      }
    }
    if (!changed) break;
  }
  return best;
}

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
