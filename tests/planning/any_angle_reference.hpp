// Independent references for the any-angle planners' tests: a geometric line-of-sight check that
// shares no code with GridLayer::lineOfSight (it clips the segment against every cell square near
// it), path validation built on it, and the exact optimum over paths whose vertices are cell
// centres (Dijkstra on the visibility graph of all free cells; small maps only, O(n^2)).
#pragma once

#include <algorithm>
#include <cmath>
#include <limits>
#include <queue>
#include <string>
#include <vector>

#include "terrain/grid_layer.hpp"

namespace skyroute::testing {

// Does the segment a-b touch the closed unit square centred on c? (Liang-Barsky clipping.)
// Corners sit at half-integers and segments join integer points, so a segment either passes
// through a corner exactly or misses it by at least 0.5 / length: a 1e-9 slack is exact here.
inline bool segmentTouchesCell(double ax, double ay, double bx, double by, GridCell c) {
  constexpr double kSlack = 1e-9;
  double t0 = 0.0, t1 = 1.0;
  const double d[2] = {bx - ax, by - ay};
  const double p[2] = {ax, ay};
  const double lo[2] = {c.x - 0.5 - kSlack, c.y - 0.5 - kSlack};
  const double hi[2] = {c.x + 0.5 + kSlack, c.y + 0.5 + kSlack};
  for (int k = 0; k < 2; ++k) {
    if (d[k] == 0.0) {
      if (p[k] < lo[k] || p[k] > hi[k]) return false;
      continue;
    }
    double ta = (lo[k] - p[k]) / d[k], tb = (hi[k] - p[k]) / d[k];
    if (ta > tb) std::swap(ta, tb);
    t0 = std::max(t0, ta);
    t1 = std::min(t1, tb);
    if (t0 > t1) return false;
  }
  return true;
}

// Every cell the segment touches (including at a single corner point) lies inside and is free.
inline bool geometricLineOfSight(const GridLayer& g, GridCell a, GridCell b) {
  for (int y = std::min(a.y, b.y) - 1; y <= std::max(a.y, b.y) + 1; ++y) {
    for (int x = std::min(a.x, b.x) - 1; x <= std::max(a.x, b.x) + 1; ++x) {
      if (segmentTouchesCell(a.x, a.y, b.x, b.y, GridCell{x, y}) && (!g.inside(GridCell{x, y}) || g.blocked(GridCell{x, y}))) {
        return false;
      }
    }
  }
  return true;
}

// Empty string when the path joins start to goal with segments the geometric check accepts.
inline std::string pathProblem(const GridLayer& g, const std::vector<GridCell>& path, GridCell start, GridCell goal) {
  if (path.empty()) return "empty path";
  if (!(path.front() == start)) return "does not begin at the start";
  if (!(path.back() == goal)) return "does not end at the goal";
  for (std::size_t i = 1; i < path.size(); ++i) {
    if (!geometricLineOfSight(g, path[i - 1], path[i])) {
      return "segment " + std::to_string(i - 1) + " (" + std::to_string(path[i - 1].x) + "," +
             std::to_string(path[i - 1].y) + ")-(" + std::to_string(path[i].x) + "," + std::to_string(path[i].y) +
             ") crosses a blocked cell";
    }
  }
  return "";
}

inline double euclid(GridCell a, GridCell b) { return std::hypot(double(a.x - b.x), double(a.y - b.y)); }

// Shortest path with vertices at free cell centres and geometrically visible segments; infinity
// when the goal cannot be reached.
inline double visibilityGraphOptimum(const GridLayer& g, GridCell start, GridCell goal) {
  std::vector<GridCell> free;
  for (int y = 0; y < g.height(); ++y) {
    for (int x = 0; x < g.width(); ++x) {
      if (g.passable(GridCell{x, y})) free.push_back(GridCell{x, y});
    }
  }
  const double inf = std::numeric_limits<double>::infinity();
  std::vector<double> dist(free.size(), inf);
  std::vector<char> done(free.size(), 0);
  std::size_t s = 0, t = 0;
  for (std::size_t i = 0; i < free.size(); ++i) {
    if (free[i] == start) s = i;
    if (free[i] == goal) t = i;
  }
  dist[s] = 0.0;
  for (;;) {  // dense Dijkstra: O(n^2), lines of sight tested lazily
    std::size_t u = free.size();
    for (std::size_t i = 0; i < free.size(); ++i) {
      if (!done[i] && dist[i] < inf && (u == free.size() || dist[i] < dist[u])) u = i;
    }
    if (u == free.size()) return inf;
    if (u == t) return dist[t];
    done[u] = 1;
    for (std::size_t v = 0; v < free.size(); ++v) {
      if (done[v]) continue;
      const double c = dist[u] + euclid(free[u], free[v]);
      if (c < dist[v] && geometricLineOfSight(g, free[u], free[v])) dist[v] = c;
    }
  }
}

// A grid from rows of text ('#' blocked, anything else free); row 0 is y = 0.
inline GridLayer gridFromText(const std::vector<std::string>& rows) { return GridLayer::fromRows(rows); }

}  // namespace skyroute::testing
