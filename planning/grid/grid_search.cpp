#include "planning/grid/grid_search.hpp"

#include <algorithm>
#include <chrono>
#include <functional>
#include <queue>

namespace skyroute {

std::string_view to_string(SearchStatus status) {
  switch (status) {
    case SearchStatus::kFound: return "found";
    case SearchStatus::kNoPath: return "no_path";
    case SearchStatus::kInvalidStart: return "invalid_start";
    case SearchStatus::kInvalidGoal: return "invalid_goal";
    case SearchStatus::kStopped: return "stopped";
  }
  return "unknown";
}

namespace {

constexpr std::uint32_t kNoParent = std::numeric_limits<std::uint32_t>::max();

struct OpenEntry {
  double f;
  double g;
  std::uint32_t cell;
  // Min-heap on f; among equal f prefer the larger g (deeper node), a usual A* tie-break.
  bool operator>(const OpenEntry& o) const { return f > o.f || (f == o.f && g < o.g); }
};

GridPath bestFirst(const GridLayer& grid, GridCell start, GridCell goal, const GridMoves& moves,
                   const TerminationCondition& stop, bool use_heuristic) {
  const auto t0 = std::chrono::steady_clock::now();
  GridPath out;
  auto finish = [&]() {
    out.stats.time_ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
    return out;
  };
  if (grid.blocked(start)) {
    out.status = SearchStatus::kInvalidStart;
    return finish();
  }
  if (grid.blocked(goal)) {
    out.status = SearchStatus::kInvalidGoal;
    return finish();
  }
  std::vector<double> g(grid.cellCount(), kInfiniteCost);
  std::vector<std::uint32_t> parent(grid.cellCount(), kNoParent);
  std::vector<std::uint8_t> closed(grid.cellCount(), 0);
  std::priority_queue<OpenEntry, std::vector<OpenEntry>, std::greater<>> open;
  auto h = [&](GridCell c) { return use_heuristic ? moves.estimate(c, goal) : 0.0; };
  const auto si = static_cast<std::uint32_t>(grid.index(start));
  const auto gi = grid.index(goal);
  g[si] = 0.0;
  open.push({h(start), 0.0, si});
  ++out.stats.queue_pushes;
  while (!open.empty()) {
    if ((out.stats.queue_pops & 1023) == 0) {
      out.stop_reason = stop.reason(out.stats.expansions);
      if (out.stop_reason != TerminationCondition::Reason::kNone) {
        out.status = SearchStatus::kStopped;
        return finish();
      }
    }
    const OpenEntry top = open.top();
    open.pop();
    ++out.stats.queue_pops;
    if (closed[top.cell] || top.g > g[top.cell]) continue;
    closed[top.cell] = 1;
    ++out.stats.expansions;
    if (top.cell == gi) break;
    const GridCell u = grid.cellOf(top.cell);
    forEachMove(grid, u, moves, [&](GridCell v, double c) {
      const auto vi = static_cast<std::uint32_t>(grid.index(v));
      if (closed[vi]) return;
      const double nv = top.g + c;
      if (nv < g[vi]) {
        g[vi] = nv;
        parent[vi] = top.cell;
        open.push({nv + h(v), nv, vi});
        ++out.stats.queue_pushes;
      }
    });
  }
  if (!closed[gi]) {
    out.status = SearchStatus::kNoPath;
    return finish();
  }
  out.status = SearchStatus::kFound;
  out.cost = g[gi];
  for (std::uint32_t i = static_cast<std::uint32_t>(gi); i != kNoParent; i = parent[i]) out.cells.push_back(grid.cellOf(i));
  std::reverse(out.cells.begin(), out.cells.end());
  return finish();
}

}  // namespace

GridPath astarSearch(const GridLayer& grid, GridCell start, GridCell goal, const GridMoves& moves,
                     const TerminationCondition& stop) {
  return bestFirst(grid, start, goal, moves, stop, true);
}

GridPath dijkstraSearch(const GridLayer& grid, GridCell start, GridCell goal, const GridMoves& moves,
                        const TerminationCondition& stop) {
  return bestFirst(grid, start, goal, moves, stop, false);
}

std::vector<double> dijkstraCostField(const GridLayer& grid, GridCell source, const GridMoves& moves) {
  std::vector<double> dist(grid.cellCount(), kInfiniteCost);
  if (grid.blocked(source)) return dist;
  using Entry = std::pair<double, std::uint32_t>;
  std::priority_queue<Entry, std::vector<Entry>, std::greater<>> open;
  dist[grid.index(source)] = 0.0;
  open.push({0.0, static_cast<std::uint32_t>(grid.index(source))});
  while (!open.empty()) {
    // Named members, not a structured binding: clang before 16 cannot capture one in the lambda.
    const double d = open.top().first;
    const std::uint32_t i = open.top().second;
    open.pop();
    if (d > dist[i]) continue;
    forEachMove(grid, grid.cellOf(i), moves, [&](GridCell v, double c) {
      const std::size_t vi = grid.index(v);
      if (d + c < dist[vi]) {
        dist[vi] = d + c;
        open.push({d + c, static_cast<std::uint32_t>(vi)});
      }
    });
  }
  return dist;
}

std::vector<std::uint8_t> reachableCells(const GridLayer& grid, GridCell source, const GridMoves& moves) {
  std::vector<std::uint8_t> seen(grid.cellCount(), 0);
  if (grid.blocked(source)) return seen;
  std::vector<GridCell> stack{source};
  seen[grid.index(source)] = 1;
  while (!stack.empty()) {
    const GridCell u = stack.back();
    stack.pop_back();
    forEachMove(grid, u, moves, [&](GridCell v, double) {
      std::uint8_t& s = seen[grid.index(v)];
      if (!s) {
        s = 1;
        stack.push_back(v);
      }
    });
  }
  return seen;
}

}  // namespace skyroute
