#include "planning/grid_search.hpp"

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
    if ((out.stats.queue_pops & 1023) == 0 && stop.shouldStop(out.stats.expansions)) {
      out.status = SearchStatus::kStopped;
      return finish();
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

GridMoveTable::GridMoveTable(const GridLayer& grid, const GridMoves& moves)
    : grid_(&grid), moves_(moves), mask_(grid.cellCount(), 0) {
  for (int k = 0; k < 8; ++k) {
    const GridOffset d = kGridOffsets[static_cast<std::size_t>(k)];
    delta_[static_cast<std::size_t>(k)] = static_cast<std::ptrdiff_t>(d.dy) * grid.width() + d.dx;
    cost_[static_cast<std::size_t>(k)] = (d.dx != 0 && d.dy != 0) ? moves.diagonal_cost : 1.0;
  }
  rebuild();
}

void GridMoveTable::refresh(GridCell c) {
  // The same rule as moveCost, from the 3x3 block read once.
  bool blocked[3][3];
  for (int dy = -1; dy <= 1; ++dy)
    for (int dx = -1; dx <= 1; ++dx) blocked[dy + 1][dx + 1] = grid_->blocked(GridCell{c.x + dx, c.y + dy});
  std::uint8_t m = 0;
  if (!blocked[1][1]) {
    for (int k = 0; k < 8; ++k) {
      const GridOffset d = kGridOffsets[static_cast<std::size_t>(k)];
      if (blocked[d.dy + 1][d.dx + 1]) continue;
      if (d.dx != 0 && d.dy != 0 && !moves_.corner_cutting && (blocked[1][d.dx + 1] || blocked[d.dy + 1][1])) continue;
      m = static_cast<std::uint8_t>(m | (1u << k));
    }
  }
  mask_[grid_->index(c)] = m;
}

void GridMoveTable::rebuild() {
  // The same rule as refresh, for every cell at once: the blocked state is copied once into a grid
  // with a blocked border, so each 3x3 block is read by plain offsets with no bounds tests (about
  // five times faster than refresh per cell, which was 5 % of planning a 1000 x 1000 mission).
  const int w = grid_->width(), h = grid_->height();
  const std::size_t pw = static_cast<std::size_t>(w) + 2;
  std::vector<std::uint8_t> padded(pw * (static_cast<std::size_t>(h) + 2), 1);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x)
      padded[(static_cast<std::size_t>(y) + 1) * pw + static_cast<std::size_t>(x) + 1] =
          grid_->blocked(GridCell{x, y}) ? 1 : 0;
  std::array<std::ptrdiff_t, 8> to{}, side_x{}, side_y{};
  for (int k = 0; k < 8; ++k) {
    const GridOffset d = kGridOffsets[static_cast<std::size_t>(k)];
    to[static_cast<std::size_t>(k)] = static_cast<std::ptrdiff_t>(d.dy) * static_cast<std::ptrdiff_t>(pw) + d.dx;
    side_x[static_cast<std::size_t>(k)] = d.dx;
    side_y[static_cast<std::size_t>(k)] = static_cast<std::ptrdiff_t>(d.dy) * static_cast<std::ptrdiff_t>(pw);
  }
  for (int y = 0; y < h; ++y) {
    for (int x = 0; x < w; ++x) {
      const std::size_t c = (static_cast<std::size_t>(y) + 1) * pw + static_cast<std::size_t>(x) + 1;
      std::uint8_t m = 0;
      if (padded[c] == 0) {
        for (std::size_t k = 0; k < 8; ++k) {
          if (padded[c + static_cast<std::size_t>(to[k])] != 0) continue;
          const bool diagonal = k >= 4;  // kGridOffsets lists the straight moves first
          if (diagonal && !moves_.corner_cutting &&
              (padded[c + static_cast<std::size_t>(side_x[k])] != 0 || padded[c + static_cast<std::size_t>(side_y[k])] != 0))
            continue;
          m = static_cast<std::uint8_t>(m | (1u << k));
        }
      }
      mask_[static_cast<std::size_t>(y) * static_cast<std::size_t>(w) + static_cast<std::size_t>(x)] = m;
    }
  }
  version_ = grid_->version();
}

void GridMoveTable::update(std::span<const GridCell> changed) {
  if (version_ == grid_->version()) return;
  for (const GridCell& c : changed)
    for (int dy = -1; dy <= 1; ++dy)
      for (int dx = -1; dx <= 1; ++dx) {
        const GridCell n{c.x + dx, c.y + dy};
        if (grid_->inside(n)) refresh(n);
      }
  version_ = grid_->version();
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
