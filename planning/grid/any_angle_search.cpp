#include "planning/grid/any_angle_search.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <queue>

#include "planning/grid/grid_search.hpp"

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

AnyAngleResult gridAStar8(const GridLayer& grid, GridCell start, GridCell goal, const TerminationCondition& stop) {
  GridPath found = astarSearch(grid, start, goal, GridMoves{}, stop);
  AnyAngleResult result;
  switch (found.status) {
    case SearchStatus::kFound: result.status = AnyAngleStatus::kExact; break;
    case SearchStatus::kNoPath: result.status = AnyAngleStatus::kNoPath; break;
    case SearchStatus::kInvalidStart: result.status = AnyAngleStatus::kInvalidStart; break;
    case SearchStatus::kInvalidGoal: result.status = AnyAngleStatus::kInvalidGoal; break;
    case SearchStatus::kStopped: result.status = AnyAngleStatus::kTerminated; break;
  }
  result.path = std::move(found.cells);
  result.length_cells = polylineLength(result.path);
  result.expansions = found.stats.expansions;
  result.time_s = found.stats.time_ms / 1000.0;
  result.stop_reason = found.stop_reason;
  return result;
}

namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();

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

}  // namespace

AnyAngleResult thetaStar(const GridLayer& grid, GridCell start, GridCell goal, const TerminationCondition& stop) {
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
  auto h = [&](GridCell c) { return segmentLength(c, goal); };

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
    forEachMove(grid, grid.cellOf(top.index), GridMoves{}, [&](GridCell nb, double move_cost) {
      const std::size_t ni = grid.index(nb);
      if (closed[ni] != 0) return;
      std::size_t from = top.index;
      double cand = g[from] + move_cost;
      // Path 2 of Theta*: connect straight to the parent's parent when it is visible.
      const std::size_t pp = parent[from];
      if (pp != from && grid.lineOfSight(grid.cellOf(pp), nb)) {
        from = pp;
        cand = g[pp] + segmentLength(grid.cellOf(pp), nb);
      }
      if (cand < g[ni]) {
        g[ni] = cand;
        parent[ni] = from;
        open.push({cand + h(nb), cand, ni});
      }
    });
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

}  // namespace skyroute
