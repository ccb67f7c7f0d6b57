#include "planning/dstar_lite.hpp"

#include <chrono>
#include <functional>

namespace skyroute {

namespace {

struct EntryGreater {
  bool operator()(const DStarQueue::Entry& a, const DStarQueue::Entry& b) const { return b.key < a.key; }
};

// UpdateVertex after u's g or rhs may have changed: insert u into every queue when it is
// inconsistent and its key changed; a consistent u leaves only stale entries behind (lazy remove).
void updateVertex(const DStarGoalField& field, std::uint32_t u, double old_min, bool was_inconsistent,
                  std::span<DStarQueue* const> queues, SearchStats& stats) {
  if (field.consistent(u)) return;
  if (was_inconsistent && costEqual(field.minCost(u), old_min)) return;
  for (DStarQueue* q : queues) q->push(u, q->calcKey(field, u), stats);
}

}  // namespace

DStarGoalField::DStarGoalField(const GridLayer& grid, GridCell goal, const GridMoves& moves)
    : grid_(&grid),
      moves_(moves),
      goal_(goal),
      goal_index_(static_cast<std::uint32_t>(grid.inside(goal) ? grid.index(goal) : 0)),
      g_(grid.cellCount(), kInfiniteCost),
      rhs_(grid.cellCount(), kInfiniteCost) {}

double DStarGoalField::bestRhs(std::uint32_t i) const {
  double best = kInfiniteCost;
  forEachMove(*grid_, grid_->cellOf(i), moves_, [&](GridCell s, double c) {
    const double v = c + g_[grid_->index(s)];
    if (v < best) best = v;
  });
  return best;
}

GridCell DStarGoalField::nextCell(GridCell from) const {
  double best = kInfiniteCost;
  GridCell next = from;
  forEachMove(*grid_, from, moves_, [&](GridCell s, double c) {
    const double v = c + g_[grid_->index(s)];
    if (v < best) {
      best = v;
      next = s;
    }
  });
  return next;
}

std::vector<GridCell> DStarGoalField::pathFrom(GridCell start) const {
  std::vector<GridCell> path;
  if (!grid_->inside(start) || !(costFrom(start) < kInfiniteCost)) return path;
  path.push_back(start);
  GridCell cur = start;
  // Each step strictly lowers g on a consistent path; the bound only guards against a caller
  // asking before the search finished.
  for (std::size_t steps = 0; !(cur == goal_) && steps < grid_->cellCount(); ++steps) {
    const GridCell next = nextCell(cur);
    if (next == cur) return {};
    path.push_back(next);
    cur = next;
  }
  if (!(cur == goal_)) return {};
  return path;
}

DStarKey DStarQueue::calcKey(const DStarGoalField& field, std::uint32_t cell) const {
  const double m = field.minCost(cell);
  return DStarKey{m + field.moves().estimate(start_, field.grid().cellOf(cell)) + km_, m};
}

void DStarQueue::push(std::uint32_t cell, DStarKey key, SearchStats& stats) {
  heap_.push_back(Entry{key, cell});
  std::push_heap(heap_.begin(), heap_.end(), EntryGreater{});
  ++stats.queue_pushes;
}

const DStarQueue::Entry* DStarQueue::top(const DStarGoalField& field, SearchStats& stats) {
  while (!heap_.empty()) {
    const Entry& e = heap_.front();
    if (!field.consistent(e.cell) && costEqual(e.key.k2, field.minCost(e.cell))) return &heap_.front();
    std::pop_heap(heap_.begin(), heap_.end(), EntryGreater{});
    heap_.pop_back();
    ++stats.queue_pops;
  }
  return nullptr;
}

DStarQueue::Entry DStarQueue::pop(SearchStats& stats) {
  std::pop_heap(heap_.begin(), heap_.end(), EntryGreater{});
  const Entry e = heap_.back();
  heap_.pop_back();
  ++stats.queue_pops;
  return e;
}

void DStarQueue::adapt(const DStarGoalField& field, SearchStats& stats) {
  std::vector<Entry> live;
  live.reserve(heap_.size());
  for (const Entry& e : heap_) {
    if (!field.consistent(e.cell) && costEqual(e.key.k2, field.minCost(e.cell))) live.push_back(Entry{calcKey(field, e.cell), e.cell});
  }
  std::sort(live.begin(), live.end(), [](const Entry& a, const Entry& b) { return a.cell < b.cell; });
  live.erase(std::unique(live.begin(), live.end(), [](const Entry& a, const Entry& b) { return a.cell == b.cell; }),
             live.end());
  std::make_heap(live.begin(), live.end(), EntryGreater{});
  stats.queue_pushes += live.size();
  heap_ = std::move(live);
}

void dstarInitialize(DStarGoalField& field, DStarQueue& queue, SearchStats& stats) {
  std::fill(field.g_.begin(), field.g_.end(), kInfiniteCost);
  std::fill(field.rhs_.begin(), field.rhs_.end(), kInfiniteCost);
  field.rhs_[field.goal_index_] = 0.0;
  queue.push(field.goal_index_, queue.calcKey(field, field.goal_index_), stats);
}

SearchStatus dstarComputeShortestPath(DStarGoalField& field, DStarQueue& queue, std::span<DStarQueue* const> mirrors,
                                      SearchStats& stats, const TerminationCondition& stop) {
  const auto t0 = std::chrono::steady_clock::now();
  const GridLayer& grid = field.grid();
  const GridMoves& moves = field.moves();
  const std::uint32_t s = static_cast<std::uint32_t>(grid.index(queue.start()));
  const std::uint32_t goal = field.goal_index_;
  std::vector<DStarQueue*> all;  // the active queue and its mirrors: where vertex updates go
  all.reserve(mirrors.size() + 1);
  all.push_back(&queue);
  all.insert(all.end(), mirrors.begin(), mirrors.end());
  SearchStatus status = SearchStatus::kFound;
  std::uint64_t iterations = 0;
  for (;;) {
    const DStarQueue::Entry* top = queue.top(field, stats);
    const bool start_inconsistent = !field.consistent(s);
    if (top == nullptr) break;  // start is then consistent: no live entry means no inconsistent cell
    if (!(top->key < queue.calcKey(field, s)) && !start_inconsistent) break;
    if ((++iterations & 1023) == 0 && stop.shouldStop(stats.expansions)) {
      status = SearchStatus::kStopped;
      break;
    }
    const DStarQueue::Entry e = queue.pop(stats);
    const std::uint32_t u = e.cell;
    const DStarKey k_new = queue.calcKey(field, u);
    if (e.key < k_new) {  // k_old < CalcKey(u): only this queue's k_m or start moved; re-key
      queue.push(u, k_new, stats);
      continue;
    }
    ++stats.expansions;
    const GridCell uc = grid.cellOf(u);
    if (costLess(field.rhs_[u], field.g_[u])) {  // overconsistent: settle and relax the predecessors
      field.g_[u] = field.rhs_[u];
      const double gu = field.g_[u];
      forEachMove(grid, uc, moves, [&](GridCell p, double c) {
        const auto pi = static_cast<std::uint32_t>(grid.index(p));
        if (pi == goal || !costLess(c + gu, field.rhs_[pi])) return;
        const double old_min = field.minCost(pi);
        const bool was_inconsistent = !field.consistent(pi);
        field.rhs_[pi] = c + gu;
        updateVertex(field, pi, old_min, was_inconsistent, all, stats);
      });
    } else {  // underconsistent: invalidate and let the predecessors that used u look again
      const double g_old = field.g_[u];
      field.g_[u] = kInfiniteCost;
      updateVertex(field, u, g_old, true, all, stats);
      forEachMove(grid, uc, moves, [&](GridCell p, double c) {
        const auto pi = static_cast<std::uint32_t>(grid.index(p));
        if (pi == goal || !costEqual(field.rhs_[pi], c + g_old)) return;
        const double old_min = field.minCost(pi);
        const bool was_inconsistent = !field.consistent(pi);
        field.rhs_[pi] = field.bestRhs(pi);
        updateVertex(field, pi, old_min, was_inconsistent, all, stats);
      });
    }
  }
  if (status == SearchStatus::kFound && !(field.g_[s] < kInfiniteCost)) status = SearchStatus::kNoPath;
  stats.time_ms += std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
  return status;
}

void dstarUpdateChangedCells(DStarGoalField& field, std::span<const GridCell> changed,
                             std::span<DStarQueue* const> queues, SearchStats& stats) {
  const GridLayer& grid = field.grid();
  std::vector<std::uint32_t> touched;
  touched.reserve(changed.size() * 9);
  for (const GridCell& c : changed) {
    for (int dy = -1; dy <= 1; ++dy) {
      for (int dx = -1; dx <= 1; ++dx) {
        const GridCell n{c.x + dx, c.y + dy};
        if (grid.inside(n)) touched.push_back(static_cast<std::uint32_t>(grid.index(n)));
      }
    }
  }
  std::sort(touched.begin(), touched.end());
  touched.erase(std::unique(touched.begin(), touched.end()), touched.end());
  for (const std::uint32_t u : touched) {
    if (u == field.goal_index_) continue;
    const double old_min = field.minCost(u);
    const bool was_inconsistent = !field.consistent(u);
    field.rhs_[u] = field.bestRhs(u);
    updateVertex(field, u, old_min, was_inconsistent, queues, stats);
  }
}

DStarLite::DStarLite(const GridLayer& grid, GridCell start, GridCell goal, const GridMoves& moves)
    : field_(grid, goal, moves), queue_(start, 0.0), last_start_(start) {
  if (grid.passable(goal)) dstarInitialize(field_, queue_, stats_);
}

SearchStatus DStarLite::computeShortestPath(const TerminationCondition& stop) {
  if (field_.grid().blocked(queue_.start())) return SearchStatus::kInvalidStart;
  if (field_.grid().blocked(field_.goal())) return SearchStatus::kInvalidGoal;
  // k_m grows by the start's move since the keys were last computed (seed line 52). Doing it here
  // rather than only on edge changes keeps every stored key a lower bound however the caller
  // interleaves moves, changes and searches.
  if (!(last_start_ == queue_.start())) {
    queue_.setKm(queue_.km() + field_.moves().estimate(last_start_, queue_.start()));
    last_start_ = queue_.start();
  }
  return dstarComputeShortestPath(field_, queue_, {}, stats_, stop);
}

void DStarLite::updateCells(std::span<const GridCell> changed) {
  if (changed.empty()) return;
  if (!(last_start_ == queue_.start())) {
    queue_.setKm(queue_.km() + field_.moves().estimate(last_start_, queue_.start()));
    last_start_ = queue_.start();
  }
  DStarQueue* const q = &queue_;
  dstarUpdateChangedCells(field_, changed, std::span<DStarQueue* const>(&q, 1), stats_);
}

}  // namespace skyroute
