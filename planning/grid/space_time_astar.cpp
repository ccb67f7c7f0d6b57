#include "planning/grid/space_time_astar.hpp"

#include <algorithm>
#include <chrono>
#include <cstdlib>
#include <queue>
#include <unordered_set>

#include "planning/grid/step_distance.hpp"

namespace skyroute {

void CellTimeReservations::reservePath(int agent, int start_step, const std::vector<GridCell>& cells, bool park_at_end) {
  for (std::size_t k = 0; k < cells.size(); ++k) reserveCellAt(agent, cells[k], start_step + static_cast<int>(k));
  if (park_at_end && !cells.empty()) {
    const GridCell last = cells.back();
    const std::uint32_t cell = static_cast<std::uint32_t>(last.y * width_ + last.x);
    parked_.emplace(cell, Park{agent, start_step + static_cast<int>(cells.size()) - 1});
    agent_parks_[agent].push_back(cell);
  }
}

void CellTimeReservations::reserveCellAt(int agent, GridCell cell, int step) {
  const std::uint64_t k = key(cell, step);
  held_.emplace(k, agent);
  agent_keys_[agent].push_back(k);
  horizon_ = std::max(horizon_, step);
}

void CellTimeReservations::clearAgent(int agent) {
  auto erase_from = [agent](auto& multimap, const auto& keys) {
    for (const auto& k : keys) {
      auto [lo, hi] = multimap.equal_range(k);
      for (auto it = lo; it != hi;) {
        const bool mine = [&] {
          if constexpr (std::is_same_v<std::decay_t<decltype(it->second)>, int>) return it->second == agent;
          else return it->second.agent == agent;
        }();
        it = mine ? multimap.erase(it) : std::next(it);
      }
    }
  };
  if (auto it = agent_keys_.find(agent); it != agent_keys_.end()) {
    erase_from(held_, it->second);
    agent_keys_.erase(it);
  }
  if (auto it = agent_parks_.find(agent); it != agent_parks_.end()) {
    erase_from(parked_, it->second);
    agent_parks_.erase(it);
  }
  // The horizon stays an upper bound; that only makes searches a little more careful.
}

std::vector<int> CellTimeReservations::holders(GridCell cell, int step) const {
  std::vector<int> out;
  auto [lo, hi] = held_.equal_range(key(cell, step));
  for (auto it = lo; it != hi; ++it) out.push_back(it->second);
  auto [plo, phi] = parked_.equal_range(static_cast<std::uint32_t>(cell.y * width_ + cell.x));
  for (auto it = plo; it != phi; ++it) {
    if (it->second.from_step <= step) out.push_back(it->second.agent);
  }
  return out;
}

bool CellTimeReservations::heldByOther(GridCell cell, int step, int self) const {
  auto [lo, hi] = held_.equal_range(key(cell, step));
  for (auto it = lo; it != hi; ++it) {
    if (it->second != self) return true;
  }
  auto [plo, phi] = parked_.equal_range(static_cast<std::uint32_t>(cell.y * width_ + cell.x));
  for (auto it = plo; it != phi; ++it) {
    if (it->second.agent != self && it->second.from_step <= step) return true;
  }
  return false;
}

bool CellTimeReservations::moveAllowed(GridCell from, GridCell to, int step, int self) const {
  if (heldByOther(to, step + 1, self)) return false;
  if (from == to) return true;
  for (int a : holders(to, step)) {
    if (a == self) continue;
    for (int b : holders(from, step + 1)) {
      if (a == b) return false;  // a goes to -> from while we go from -> to
    }
  }
  return true;
}

bool CellTimeReservations::freeFrom(GridCell cell, int step, int self) const {
  auto [plo, phi] = parked_.equal_range(static_cast<std::uint32_t>(cell.y * width_ + cell.x));
  for (auto it = plo; it != phi; ++it) {
    if (it->second.agent != self) return false;
  }
  for (int t = step; t <= horizon_; ++t) {
    if (heldByOther(cell, t, self)) return false;
  }
  return true;
}

std::string_view to_string(SpaceTimeStatus status) {
  switch (status) {
    case SpaceTimeStatus::kFound: return "found";
    case SpaceTimeStatus::kStartBlocked: return "start blocked";
    case SpaceTimeStatus::kGoalBlocked: return "goal blocked";
    case SpaceTimeStatus::kNoPath: return "no path";
    case SpaceTimeStatus::kBudgetExhausted: return "expansion budget exhausted";
    case SpaceTimeStatus::kStopped: return "stopped";
  }
  return "unknown";
}

SpaceTimePath planSpaceTime(const GridLayer& grid, const CellTimeReservations& reservations, const SpaceTimeQuery& q,
                            const TerminationCondition& stop) {
  const auto started = std::chrono::steady_clock::now();
  SpaceTimePath out;
  out.start_step = q.start_step;
  auto finish = [&](SpaceTimeStatus s) {
    out.status = s;
    out.time_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - started).count();
    return out;
  };
  if (grid.blocked(q.start)) return finish(SpaceTimeStatus::kStartBlocked);
  if (grid.blocked(q.goal)) return finish(SpaceTimeStatus::kGoalBlocked);

  auto h = [&](GridCell c) -> int {
    if (q.heuristic == nullptr) return std::abs(c.x - q.goal.x) + std::abs(c.y - q.goal.y);
    return (*q.heuristic)[grid.index(c)];
  };
  if (h(q.start) == kUnreachableSteps) return finish(SpaceTimeStatus::kNoPath);

  // From this step on nothing time-limited is reserved: (cell, t) and (cell, t') are the same
  // state for t, t' >= merge_step, and the earliest wins.
  const int merge_step = std::max({reservations.horizon() + 1, q.start_step, q.earliest_arrival});
  auto state_key = [&](GridCell c, int step) {
    return (static_cast<std::uint64_t>(std::min(step, merge_step) - q.start_step) << 32) |
           static_cast<std::uint64_t>(grid.index(c));
  };

  struct Node {
    GridCell cell;
    int step;
    int parent;
  };
  struct Entry {
    int f;
    int step;
    std::uint64_t order;
    int node;
  };
  auto worse = [](const Entry& a, const Entry& b) {
    if (a.f != b.f) return a.f > b.f;
    if (a.step != b.step) return a.step < b.step;  // deeper first among equal f
    return a.order > b.order;                      // then first pushed
  };
  std::vector<Node> nodes;
  std::priority_queue<Entry, std::vector<Entry>, decltype(worse)> open(worse);
  std::unordered_set<std::uint64_t> closed;
  std::uint64_t pushed = 0;
  nodes.push_back(Node{q.start, q.start_step, -1});
  open.push(Entry{q.start_step + h(q.start), q.start_step, pushed++, 0});

  while (!open.empty()) {
    const Entry e = open.top();
    open.pop();
    const Node n = nodes[static_cast<std::size_t>(e.node)];
    if (!closed.insert(state_key(n.cell, n.step)).second) continue;
    ++out.expansions;
    if ((out.expansions & 1023) == 0 && stop.shouldStop()) return finish(SpaceTimeStatus::kStopped);
    if (out.expansions > q.max_expansions) return finish(SpaceTimeStatus::kBudgetExhausted);
    if (n.cell == q.goal && n.step >= q.earliest_arrival &&
        (!q.park_at_goal || reservations.freeFrom(q.goal, n.step, q.self))) {
      for (int i = e.node; i >= 0; i = nodes[static_cast<std::size_t>(i)].parent) {
        out.cells.push_back(nodes[static_cast<std::size_t>(i)].cell);
      }
      std::reverse(out.cells.begin(), out.cells.end());
      return finish(SpaceTimeStatus::kFound);
    }
    const GridCell moves[5] = {kFourMoves[0], kFourMoves[1], kFourMoves[2], kFourMoves[3], GridCell{0, 0}};
    for (const GridCell& m : moves) {
      const GridCell next{n.cell.x + m.x, n.cell.y + m.y};
      if (grid.blocked(next)) continue;
      const int hn = h(next);
      if (hn == kUnreachableSteps) continue;
      if (!reservations.moveAllowed(n.cell, next, n.step, q.self)) continue;
      if (closed.count(state_key(next, n.step + 1)) != 0) continue;
      nodes.push_back(Node{next, n.step + 1, e.node});
      open.push(Entry{n.step + 1 + hn, n.step + 1, pushed++, static_cast<int>(nodes.size()) - 1});
    }
  }
  return finish(SpaceTimeStatus::kNoPath);
}

}  // namespace skyroute
