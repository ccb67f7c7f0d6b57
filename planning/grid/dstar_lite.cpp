#include "planning/grid/dstar_lite.hpp"

#include <sys/mman.h>

#include <chrono>
#include <cstdlib>
#include <new>

namespace skyroute {

namespace {
constexpr std::size_t kHugePage = std::size_t{2} << 20;
}

void* allocateHugePages(std::size_t bytes) {
  if (bytes < kHugePage) {
    void* p = std::malloc(std::max<std::size_t>(bytes, 1));
    if (p == nullptr) throw std::bad_alloc();
    return p;
  }
  const std::size_t rounded = (bytes + kHugePage - 1) / kHugePage * kHugePage;
  void* p = std::aligned_alloc(kHugePage, rounded);
  if (p == nullptr) throw std::bad_alloc();
  // Advice only: without transparent huge pages the memory works the same with 4 KB pages.
  (void)madvise(p, rounded, MADV_HUGEPAGE);
  return p;
}

void freeHugePages(void* p, std::size_t /*bytes*/) noexcept { std::free(p); }

DStarGoalField::DStarGoalField(const GridLayer& grid, GridCell goal, const GridMoves& moves)
    : DStarGoalField(std::make_shared<GridMoveTable>(grid, moves), goal) {}

DStarGoalField::DStarGoalField(std::shared_ptr<GridMoveTable> table, GridCell goal)
    : table_(std::move(table)),
      goal_(goal),
      goal_index_(static_cast<std::uint32_t>(table_->grid().inside(goal) ? table_->grid().index(goal) : 0)),
      cost_(table_->grid().cellCount(), Cost{kInfiniteCost, kInfiniteCost}) {}

GridCell DStarGoalField::nextCell(GridCell from) const {
  // Walks the grid itself rather than the move table: not a hot path, and right even when asked
  // between a grid change and the repair.
  double best = kInfiniteCost;
  GridCell next = from;
  forEachMove(grid(), from, moves(), [&](GridCell s, double c) {
    const double v = c + cost_[grid().index(s)].g;
    if (v < best) {
      best = v;
      next = s;
    }
  });
  return next;
}

std::vector<GridCell> DStarGoalField::pathFrom(GridCell start) const {
  std::vector<GridCell> path;
  if (!grid().inside(start) || !(costFrom(start) < kInfiniteCost)) return path;
  path.push_back(start);
  GridCell cur = start;
  // Each step strictly lowers g on a consistent path; the bound only guards against a caller
  // asking before the search finished.
  for (std::size_t steps = 0; !(cur == goal_) && steps < grid().cellCount(); ++steps) {
    const GridCell next = nextCell(cur);
    if (next == cur) return {};
    path.push_back(next);
    cur = next;
  }
  if (!(cur == goal_)) return {};
  return path;
}

void DStarQueue::siftUp(std::size_t i) {
  const Entry e = heap_[i];
  while (i > 0) {
    const std::size_t parent = (i - 1) / kArity;
    if (!(e.key < heap_[parent].key)) break;
    heap_[i] = heap_[parent];
    i = parent;
  }
  heap_[i] = e;
}

std::size_t DStarQueue::smallestChild(std::size_t first, std::size_t n) const {
  const std::size_t last = std::min(first + kArity, n);
  std::size_t best = first;
  for (std::size_t c = first + 1; c < last; ++c)
    if (heap_[c].key < heap_[best].key) best = c;
  return best;
}

void DStarQueue::siftDown(std::size_t i, Entry e) {
  const std::size_t n = heap_.size();
  for (;;) {
    const std::size_t first = i * kArity + 1;
    if (first >= n) break;
    const std::size_t best = smallestChild(first, n);
    if (!(heap_[best].key < e.key)) break;
    heap_[i] = heap_[best];
    i = best;
  }
  heap_[i] = e;
}

void DStarQueue::removeTop() {
  const Entry last = heap_.back();
  heap_.pop_back();
  const std::size_t n = heap_.size();
  if (n == 0) return;
  std::size_t i = 0;
  for (;;) {
    const std::size_t first = i * kArity + 1;
    if (first >= n) break;
    const std::size_t best = smallestChild(first, n);
    heap_[i] = heap_[best];
    i = best;
  }
  heap_[i] = last;
  siftUp(i);
}

void DStarQueue::loadBucket() {
  std::vector<Entry>& bucket = far_[first_far_];
  far_count_ -= bucket.size();
  limit_ = first_far_ + 1;
  const bool rebuild = bucket.size() > heap_.size();
  heap_.insert(heap_.end(), bucket.begin(), bucket.end());
  if (rebuild) {
    // Floyd's heap construction: linear, cheaper than one sift-up per entry for a large bucket.
    const std::size_t n = heap_.size();
    if (n > 1)
      for (std::size_t i = (n - 2) / kArity + 1; i-- > 0;) siftDown(i, heap_[i]);
  } else {
    for (std::size_t i = heap_.size() - bucket.size(); i < heap_.size(); ++i) siftUp(i);
  }
  bucket.clear();
  if (far_count_ != 0)
    while (far_[first_far_].empty() || first_far_ < limit_) {
      // Entries never sit below the limit, so the next non-empty bucket is above the loaded one.
      ++first_far_;
    }
}

void DStarQueue::adapt(const DStarGoalField& field, SearchStats& stats) {
  std::vector<Entry> live;
  live.reserve(size());
  auto keep = [&](const Entry& e) {
    if (!field.consistent(e.cell) && costEqual(e.key.k2, field.minCost(e.cell)))
      live.push_back(Entry{calcKey(field, e.cell), e.cell});
  };
  for (const Entry& e : heap_) keep(e);
  for (std::vector<Entry>& bucket : far_) {
    for (const Entry& e : bucket) keep(e);
    bucket.clear();
  }
  heap_.clear();
  far_count_ = 0;
  limit_ = 0;
  // Everything goes to the buckets; the lowest ones are loaded when the search asks for the top.
  for (const Entry& e : live) placeFar(bucketOf(e.key.k1), e);
  stats.queue_pushes += live.size();
  compacted_size_ = live.size();
}

void dstarInitialize(DStarGoalField& field, DStarQueue& queue, SearchStats& stats) {
  // A new field is already all infinity: writing 16 bytes a cell again costs more than the search
  // on a large grid that is only partly explored.
  if (!field.pristine_) std::fill(field.cost_.begin(), field.cost_.end(), DStarGoalField::Cost{kInfiniteCost, kInfiniteCost});
  field.pristine_ = false;
  field.cost_[field.goal_index_].rhs = 0.0;
  queue.push(field.goal_index_, queue.calcKey(field, field.goal_index_), stats);
}

PlannerStatus dstarComputeShortestPath(DStarGoalField& field, DStarQueue& queue, SearchStats& stats,
                                      const TerminationCondition& stop) {
  const auto t0 = std::chrono::steady_clock::now();
  GridMoveTable& table = *field.table_;
  table.sync();
  const GridLayer& grid = table.grid();
  const GridMoves moves = table.moves();
  const GridCell sc = queue.start();
  const auto s = static_cast<std::uint32_t>(grid.index(sc));
  const std::uint32_t goal = field.goal_index_;
  const double km = queue.km();
  field.pristine_ = false;
  DStarGoalField::Cost* const cost = field.cost_.data();
  const bool log = field.logging_;
  // UpdateVertex (lines 06-08) after v's rhs or g changed: insert v when it is inconsistent and its
  // key changed; a consistent v leaves only stale entries behind (lazy remove).
  auto updated = [&](std::uint32_t v, int vx, int vy, double old_min, bool was_inconsistent) {
    const double g = cost[v].g, rhs = cost[v].rhs;
    if (costEqual(g, rhs)) return;
    const double m = std::min(g, rhs);
    if (was_inconsistent && costEqual(m, old_min)) return;
    queue.push(v, DStarKey{m + moves.estimate(sc, GridCell{vx, vy}) + km, m}, stats);
    if (log) field.record(v);
  };
  PlannerStatus status = PlannerStatus::kSolved;
  std::uint64_t iterations = 0;
  for (;;) {
    const DStarQueue::Entry* top = queue.top(field, stats);
    if (top == nullptr) break;  // the start is then consistent: no live entry means no inconsistent cell
    const bool start_inconsistent = !field.consistent(s);
    if (!(top->key < queue.calcKey(field, s, sc.x, sc.y)) && !start_inconsistent) break;
    if ((++iterations & 1023) == 0 && stop.shouldStop(stats.expansions)) {
      status = stoppedStatus(stop.reason(stats.expansions));
      break;
    }
    const DStarQueue::Entry e = queue.pop(stats);
    const std::uint32_t u = e.cell;
    const GridCell uc = grid.cellOf(u);
    const DStarKey k_new = queue.calcKey(field, u, uc.x, uc.y);
    if (e.key < k_new) {  // k_old < CalcKey(u): only this queue's k_m or start moved; re-key
      queue.push(u, k_new, stats);
      continue;
    }
    ++stats.expansions;
    unsigned mask = table.mask(u);
    if (costLess(cost[u].rhs, cost[u].g)) {  // overconsistent: settle and relax the predecessors
      const double gu = cost[u].rhs;
      cost[u].g = gu;
      while (mask != 0) {
        const int k = std::countr_zero(mask);
        mask &= mask - 1;
        const auto p = static_cast<std::uint32_t>(static_cast<std::ptrdiff_t>(u) + table.delta(k));
        const double v = table.cost(k) + gu;
        if (p == goal || !costLess(v, cost[p].rhs)) continue;
        const double old_min = std::min(cost[p].g, cost[p].rhs);
        const bool was_inconsistent = !costEqual(cost[p].g, cost[p].rhs);
        cost[p].rhs = v;
        const GridOffset d = kGridOffsets[static_cast<std::size_t>(k)];
        updated(p, uc.x + d.dx, uc.y + d.dy, old_min, was_inconsistent);
      }
    } else {  // underconsistent: invalidate and let the predecessors that used u look again
      const double g_old = cost[u].g;
      cost[u].g = kInfiniteCost;
      updated(u, uc.x, uc.y, g_old, true);
      while (mask != 0) {
        const int k = std::countr_zero(mask);
        mask &= mask - 1;
        const auto p = static_cast<std::uint32_t>(static_cast<std::ptrdiff_t>(u) + table.delta(k));
        if (p == goal || !costEqual(cost[p].rhs, table.cost(k) + g_old)) continue;
        const double old_min = std::min(cost[p].g, cost[p].rhs);
        const bool was_inconsistent = !costEqual(cost[p].g, cost[p].rhs);
        cost[p].rhs = field.bestRhs(p);
        const GridOffset d = kGridOffsets[static_cast<std::size_t>(k)];
        updated(p, uc.x + d.dx, uc.y + d.dy, old_min, was_inconsistent);
      }
    }
  }
  // This queue holds its own insertions already: it has read the log up to its end.
  if (log) field.readLog(queue);
  if (status == PlannerStatus::kSolved && !(cost[s].g < kInfiniteCost)) status = PlannerStatus::kNoPath;
  stats.time_ms += std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
  return status;
}

PlannerStatus dstarSweepInitialize(DStarGoalField& field, std::span<const GridCell> starts, DStarQueue& frontier,
                                  SearchStats& stats, const TerminationCondition& stop) {
  const auto t0 = std::chrono::steady_clock::now();
  GridMoveTable& table = *field.table_;
  table.sync();
  const GridLayer& grid = table.grid();
  if (!field.pristine_) std::fill(field.cost_.begin(), field.cost_.end(), DStarGoalField::Cost{kInfiniteCost, kInfiniteCost});
  field.pristine_ = false;
  DStarGoalField::Cost* const cost = field.cost_.data();
  std::vector<std::uint32_t> targets;
  for (const GridCell& c : starts)
    if (grid.inside(c)) targets.push_back(static_cast<std::uint32_t>(grid.index(c)));
  // Cells wait in a ring of buckets by floor(rhs): a relaxation from bucket b lands at most
  // floor(b + 1 + max move cost) ahead, so the ring needs max move cost + 2 slots.
  double max_move = 1.0;
  for (int k = 0; k < 8; ++k) max_move = std::max(max_move, table.cost(k));
  std::size_t slots = 4;
  while (static_cast<double>(slots) < max_move + 2.0) slots *= 2;
  const std::size_t ring_mask = slots - 1;
  std::vector<std::vector<std::uint32_t>> ring(slots);
  const std::uint32_t goal = field.goal_index_;
  const auto row = static_cast<std::size_t>(grid.width());
  const std::size_t cells = grid.cellCount();
  constexpr std::size_t kSweepPrefetch = 8;
  cost[goal].rhs = 0.0;
  ring[0].push_back(goal);
  ++stats.queue_pushes;
  std::size_t waiting = 1;
  std::uint64_t pushes = 0;
  std::size_t targets_left = targets.size();
  auto settledTargets = [&] {
    // A handful of starts, checked once per bucket: cheaper than a per-cell test in the hot loop.
    while (targets_left > 0 && cost[targets[targets_left - 1]].g < kInfiniteCost) --targets_left;
    return targets_left == 0;
  };
  PlannerStatus status = PlannerStatus::kSolved;
  for (std::size_t b = 0; waiting > 0; ++b) {
    std::vector<std::uint32_t>& bucket = ring[b & ring_mask];
    // Relaxations from this bucket land in later ones, so it does not grow while it is walked.
    const std::size_t count = bucket.size();
    for (std::size_t i = 0; i < count; ++i) {
      // The sweep is bound by memory latency: the wavefront is a ring around the goal, too long to
      // stay in cache from one bucket to the next. Fetching the three rows around a cell a few
      // entries ahead overlaps those misses.
      if (i + kSweepPrefetch < count) {
        const std::size_t ahead = bucket[i + kSweepPrefetch];
        __builtin_prefetch(&cost[ahead]);
        if (ahead >= row) __builtin_prefetch(&cost[ahead - row]);
        if (ahead + row < cells) __builtin_prefetch(&cost[ahead + row]);
      }
      const std::uint32_t u = bucket[i];
      if (cost[u].g < kInfiniteCost) continue;  // settled from an earlier entry of this bucket
      const double gu = cost[u].rhs;
      cost[u].g = gu;
      ++stats.expansions;
      unsigned mask = table.mask(u);
      while (mask != 0) {
        const int k = std::countr_zero(mask);
        mask &= mask - 1;
        const auto p = static_cast<std::uint32_t>(static_cast<std::ptrdiff_t>(u) + table.delta(k));
        const double v = table.cost(k) + gu;
        if (v < cost[p].rhs) {  // never true for a settled p (or the goal)
          cost[p].rhs = v;
          ring[static_cast<std::size_t>(v) & ring_mask].push_back(p);
          ++waiting;
          ++pushes;
        }
      }
    }
    stats.queue_pops += bucket.size();
    waiting -= bucket.size();
    bucket.clear();
    if (settledTargets()) break;
    if (stop.shouldStop(stats.expansions)) {
      status = stoppedStatus(stop.reason(stats.expansions));
      break;
    }
  }
  stats.queue_pushes += pushes;
  if (!isStopped(status)) {
    // The frontier: every waiting cell still unsettled (once, though it may wait in two buckets).
    std::vector<std::uint32_t> open;
    for (const std::vector<std::uint32_t>& bucket : ring)
      for (const std::uint32_t u : bucket)
        if (!(cost[u].g < kInfiniteCost)) open.push_back(u);
    std::sort(open.begin(), open.end());
    open.erase(std::unique(open.begin(), open.end()), open.end());
    for (const std::uint32_t u : open) frontier.push(u, frontier.calcKey(field, u), stats);
    if (!settledTargets()) status = PlannerStatus::kNoPath;
  }
  stats.time_ms += std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
  return status;
}

std::vector<std::uint32_t> dstarTouchedCells(const GridLayer& grid, std::span<const GridCell> changed) {
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
  return touched;
}

void dstarUpdateChangedCells(DStarGoalField& field, std::span<const GridCell> changed,
                             std::span<DStarQueue* const> queues, SearchStats& stats) {
  field.table_->update(changed);
  dstarUpdateTouchedCells(field, dstarTouchedCells(field.grid(), changed), queues, stats);
}

void dstarUpdateTouchedCells(DStarGoalField& field, std::span<const std::uint32_t> touched,
                             std::span<DStarQueue* const> queues, SearchStats& stats) {
  field.pristine_ = false;
  for (const std::uint32_t u : touched) {
    if (u == field.goal_index_) continue;
    const double old_min = field.minCost(u);
    const bool was_inconsistent = !field.consistent(u);
    field.cost_[u].rhs = field.bestRhs(u);
    if (field.consistent(u)) continue;
    if (was_inconsistent && costEqual(field.minCost(u), old_min)) continue;
    for (DStarQueue* q : queues) q->push(u, q->calcKey(field, u), stats);
    if (field.logging_) field.record(u);
  }
}

void dstarSyncQueue(DStarGoalField& field, DStarQueue& queue, SearchStats& stats) {
  for (std::size_t i = queue.log_cursor_; i < field.log_.size(); ++i) {
    const std::uint32_t u = field.log_[i];
    if (!field.consistent(u)) queue.push(u, queue.calcKey(field, u), stats);
  }
  field.readLog(queue);
  // Lazy deletion leaves stale entries behind; rebuild once they outnumber the live ones.
  if (queue.size() > 2 * queue.compacted_size_ + 4096) queue.adapt(field, stats);
}

void dstarTrimLog(DStarGoalField& field, std::span<DStarQueue* const> queues) {
  std::size_t seen = field.log_.size();
  for (const DStarQueue* q : queues) seen = std::min(seen, q->log_cursor_);
  if (seen == 0) return;
  for (std::size_t i = field.log_fresh_; i < seen; ++i) field.logged_[field.log_[i]] = 0;
  field.log_.erase(field.log_.begin(), field.log_.begin() + static_cast<std::ptrdiff_t>(seen));
  field.log_fresh_ = std::max(field.log_fresh_, seen) - seen;
  for (DStarQueue* q : queues) q->log_cursor_ -= seen;
}

void DStarGoalField::readLog(DStarQueue& queue) {
  // A later key change of any logged cell must be logged again, or this queue would miss it.
  for (std::size_t i = log_fresh_; i < log_.size(); ++i) logged_[log_[i]] = 0;
  log_fresh_ = log_.size();
  queue.log_cursor_ = log_.size();
}

void DStarGoalField::reset() {
  if (!pristine_) std::fill(cost_.begin(), cost_.end(), Cost{kInfiniteCost, kInfiniteCost});
  pristine_ = true;
  log_.clear();
  std::fill(logged_.begin(), logged_.end(), std::uint8_t{0});
  log_fresh_ = 0;
  logging_ = false;
}

void DStarGoalField::setLogging(bool on) {
  logging_ = on;
  if (on && logged_.empty()) logged_.assign(cost_.size(), 0);
}

DStarLite::DStarLite(const GridLayer& grid, GridCell start, GridCell goal, const GridMoves& moves)
    : field_(grid, goal, moves), queue_(start, 0.0), last_start_(start) {
  if (grid.passable(goal)) dstarInitialize(field_, queue_, stats_);
}

DStarLite::DStarLite(std::shared_ptr<GridMoveTable> table, GridCell start, GridCell goal)
    : field_(std::move(table), goal), queue_(start, 0.0), last_start_(start) {
  if (field_.grid().passable(goal)) dstarInitialize(field_, queue_, stats_);
}

PlannerStatus DStarLite::computeShortestPath(const TerminationCondition& stop) {
  if (field_.grid().blocked(queue_.start())) return PlannerStatus::kStartInvalid;
  if (field_.grid().blocked(field_.goal())) return PlannerStatus::kGoalInvalid;
  // k_m grows by the start's move since the keys were last computed (seed line 52). Doing it here
  // rather than only on edge changes keeps every stored key a lower bound however the caller
  // interleaves moves, changes and searches.
  if (!(last_start_ == queue_.start())) {
    queue_.setKm(queue_.km() + field_.moves().estimate(last_start_, queue_.start()));
    last_start_ = queue_.start();
  }
  return dstarComputeShortestPath(field_, queue_, stats_, stop);
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
