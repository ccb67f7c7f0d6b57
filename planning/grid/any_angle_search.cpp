#include "planning/grid/any_angle_search.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <queue>

namespace skyroute {

std::string_view to_string(AnyAngleStatus status) {
  switch (status) {
    case AnyAngleStatus::kExact: return "exact";
    case AnyAngleStatus::kInvalidStart: return "invalid start";
    case AnyAngleStatus::kInvalidGoal: return "invalid goal";
    case AnyAngleStatus::kNoPath: return "no path";
    case AnyAngleStatus::kTerminated: return "terminated";
  }
  return "unknown";
}

double polylineLength(const std::vector<GridCell>& path) {
  double length = 0.0;
  for (std::size_t i = 1; i < path.size(); ++i) {
    length += std::hypot(static_cast<double>(path[i].x - path[i - 1].x),
                         static_cast<double>(path[i].y - path[i - 1].y));
  }
  return length;
}

double polylineAngleChange(const std::vector<GridCell>& path) {
  double total = 0.0;
  for (std::size_t i = 1; i + 1 < path.size(); ++i) {
    const double ax = path[i].x - path[i - 1].x;
    const double ay = path[i].y - path[i - 1].y;
    const double bx = path[i + 1].x - path[i].x;
    const double by = path[i + 1].y - path[i].y;
    // atan2 of cross and dot is exact for parallel segments, where acos of a rounded cosine is not.
    total += std::abs(std::atan2(ax * by - ay * bx, ax * bx + ay * by));
  }
  return total;
}

namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();
constexpr int kDx[8] = {1, -1, 0, 0, 1, 1, -1, -1};
constexpr int kDy[8] = {0, 0, 1, -1, 1, -1, 1, -1};

double euclid(GridCell a, GridCell b) {
  return std::hypot(static_cast<double>(a.x - b.x), static_cast<double>(a.y - b.y));
}

double octile(GridCell a, GridCell b) {
  const double dx = std::abs(a.x - b.x);
  const double dy = std::abs(a.y - b.y);
  return std::max(dx, dy) + (std::sqrt(2.0) - 1.0) * std::min(dx, dy);
}

struct OpenEntry {
  double f;
  double g;
  std::size_t index;
  // Ties on f go to the larger g (deeper node), then to the smaller index, so runs are reproducible.
  bool operator>(const OpenEntry& o) const {
    if (f != o.f) return f > o.f;
    if (g != o.g) return g < o.g;
    return index > o.index;
  }
};

enum class Mode { kAStar8, kTheta };

AnyAngleResult search(const GridLayer& grid, GridCell start, GridCell goal, const TerminationCondition& stop,
                      Mode mode) {
  const auto t0 = std::chrono::steady_clock::now();
  AnyAngleResult result;
  auto finish = [&](AnyAngleStatus status) {
    result.status = status;
    result.time_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    return result;
  };
  if (grid.blocked(start)) return finish(AnyAngleStatus::kInvalidStart);
  if (grid.blocked(goal)) return finish(AnyAngleStatus::kInvalidGoal);

  const std::size_t n = grid.cellCount();
  std::vector<double> g(n, kInf);
  std::vector<std::size_t> parent(n, n);
  std::vector<std::uint8_t> closed(n, 0);
  auto h = [&](GridCell c) { return mode == Mode::kAStar8 ? octile(c, goal) : euclid(c, goal); };

  std::priority_queue<OpenEntry, std::vector<OpenEntry>, std::greater<>> open;
  const std::size_t s = grid.index(start);
  const std::size_t t = grid.index(goal);
  g[s] = 0.0;
  parent[s] = s;
  open.push({h(start), 0.0, s});
  while (!open.empty()) {
    if ((result.expansions & 255u) == 0) {
      const auto reason = stop.reason(result.expansions);
      if (reason != TerminationCondition::Reason::kNone) {
        result.stop_reason = reason;
        return finish(AnyAngleStatus::kTerminated);
      }
    }
    const OpenEntry top = open.top();
    open.pop();
    if (closed[top.index] != 0 || top.g > g[top.index]) continue;
    closed[top.index] = 1;
    ++result.expansions;
    if (top.index == t) break;
    const GridCell c = grid.cellOf(top.index);
    for (int k = 0; k < 8; ++k) {
      const GridCell nb{c.x + kDx[k], c.y + kDy[k]};
      if (grid.blocked(nb)) continue;
      if (k >= 4 && (grid.blocked(GridCell{c.x + kDx[k], c.y}) || grid.blocked(GridCell{c.x, c.y + kDy[k]}))) {
        continue;  // no corner cutting
      }
      const std::size_t ni = grid.index(nb);
      if (closed[ni] != 0) continue;
      std::size_t from = top.index;
      double cand = g[from] + (k >= 4 ? std::sqrt(2.0) : 1.0);
      if (mode == Mode::kTheta) {
        // Path 2 of Theta*: connect straight to the parent's parent when it is visible.
        const std::size_t pp = parent[from];
        if (pp != from && grid.lineOfSight(grid.cellOf(pp), nb)) {
          from = pp;
          cand = g[pp] + euclid(grid.cellOf(pp), nb);
        }
      }
      if (cand < g[ni]) {
        g[ni] = cand;
        parent[ni] = from;
        open.push({cand + h(nb), cand, ni});
      }
    }
  }
  if (closed[t] == 0) return finish(AnyAngleStatus::kNoPath);
  for (std::size_t i = t;; i = parent[i]) {
    result.path.push_back(grid.cellOf(i));
    if (i == s) break;
  }
  std::reverse(result.path.begin(), result.path.end());
  result.length_cells = polylineLength(result.path);
  return finish(AnyAngleStatus::kExact);
}

}  // namespace

AnyAngleResult gridAStar8(const GridLayer& grid, GridCell start, GridCell goal, const TerminationCondition& stop) {
  return search(grid, start, goal, stop, Mode::kAStar8);
}

AnyAngleResult thetaStar(const GridLayer& grid, GridCell start, GridCell goal, const TerminationCondition& stop) {
  return search(grid, start, goal, stop, Mode::kTheta);
}

}  // namespace skyroute
