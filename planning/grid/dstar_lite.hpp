// D* Lite (Koenig & Likhachev 2005, the optimised version with k_m) on the 8-connected GridLayer,
// searching from the goal towards the start so the costs survive start moves.
//
// The parts are split the way MMD*L (mmdstar_lite.hpp) needs them: DStarGoalField holds g and rhs
// of every cell for one goal (independent of the start, seed section 3.2), DStarQueue is the
// priority queue U of one start with its k_m, and the free functions run ComputeShortestPath and
// the edge-cost repair on a field and one queue. DStarLite is the plain single-pair planner built
// from the same parts.
//
// Sharing a field between the queues of several starts (MMD*L replanning, lines 20-30 and 63-65 of
// the seed): with the field's update log on, every vertex update that inserts a cell into the
// active queue is also recorded once in the field; another start's queue replays the records it
// has not seen when it is loaded (dstarSyncQueue), inserting the cells that are still inconsistent
// with its own start and k_m. Its live content is then exactly what inserting into every queue at
// each update would have left there, without one push per queue and update.
//
// Queue entries are deleted lazily: an entry is live while its cell is inconsistent and its k2
// equals the cell's current min(g, rhs); a stale one is dropped when it reaches the top. A live
// entry whose k1 was computed with an older k_m is a lower bound and gets re-keyed on pop, exactly
// as the optimised algorithm's "k_old < CalcKey(u)" branch.
#pragma once

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdint>
#include <memory>
#include <span>
#include <vector>

#include "planning/core/termination.hpp"
#include "planning/grid/grid_search.hpp"
#include "terrain/grid_layer.hpp"

namespace skyroute {

// Costs are sums of 1 and sqrt(2) (or 1.4) reached in different orders, so mathematically equal
// values can differ in the last bits; D* Lite's tie-break on k2 and its consistency test must see
// them as equal or it may stop one expansion too early. Distinct costs on grids up to 10^4 cells a
// side differ by far more than this tolerance.
inline constexpr double kCostTolerance = 1e-9;
inline bool costLess(double a, double b) { return a < b - kCostTolerance; }
inline bool costEqual(double a, double b) { return a == b || std::abs(a - b) <= kCostTolerance; }

struct DStarKey {
  double k1 = kInfiniteCost;
  double k2 = kInfiniteCost;
  // costLess(k1) || (costEqual(k1) && costLess(k2)), written with fewer branches: the priority
  // queue spends most of its time here. (Given !costLess(a.k1, b.k1), costEqual is a.k1 <= b.k1 + tol,
  // infinities included.)
  friend bool operator<(const DStarKey& a, const DStarKey& b) {
    return (a.k1 < b.k1 - kCostTolerance) | ((a.k1 <= b.k1 + kCostTolerance) & (a.k2 < b.k2 - kCostTolerance));
  }
};

class DStarQueue;

// Allocator for the large per-goal maps: blocks of 2 MB and more are aligned to 2 MB and marked
// for transparent huge pages (Linux madvise). A 1000 x 1000 map is 16 MB; with 4 KB pages, making
// it costs 4096 page faults and a sweep over it misses the TLB on most moves, which together were
// about a fifth of planning a goal.
template <class T>
struct HugePageAllocator {
  using value_type = T;
  HugePageAllocator() = default;
  template <class U>
  HugePageAllocator(const HugePageAllocator<U>&) {}
  T* allocate(std::size_t n);
  void deallocate(T* p, std::size_t n) noexcept;
  friend bool operator==(const HugePageAllocator&, const HugePageAllocator&) { return true; }
};
void* allocateHugePages(std::size_t bytes);
void freeHugePages(void* p, std::size_t bytes) noexcept;
template <class T>
T* HugePageAllocator<T>::allocate(std::size_t n) {
  return static_cast<T*>(allocateHugePages(n * sizeof(T)));
}
template <class T>
void HugePageAllocator<T>::deallocate(T* p, std::size_t n) noexcept {
  freeHugePages(p, n * sizeof(T));
}

// g and rhs of every cell for one goal (eqs. 1 and 2). Costs in cell edges.
class DStarGoalField {
 public:
  DStarGoalField(const GridLayer& grid, GridCell goal, const GridMoves& moves);
  // Several fields on the same grid can share one move table (MMD*L: one per mission).
  DStarGoalField(std::shared_ptr<GridMoveTable> table, GridCell goal);

  const GridLayer& grid() const { return table_->grid(); }
  const GridMoves& moves() const { return table_->moves(); }
  GridMoveTable& table() const { return *table_; }
  GridCell goal() const { return goal_; }
  std::uint32_t goalIndex() const { return goal_index_; }

  double g(std::size_t i) const { return cost_[i].g; }
  double rhs(std::size_t i) const { return cost_[i].rhs; }
  double minCost(std::size_t i) const { return std::min(cost_[i].g, cost_[i].rhs); }
  bool consistent(std::size_t i) const { return costEqual(cost_[i].g, cost_[i].rhs); }
  // Cost to the goal of a cell whose search is complete (g); infinity when not reached.
  double costFrom(GridCell c) const { return grid().inside(c) ? cost_[grid().index(c)].g : kInfiniteCost; }

  // rhs from the successors: min over moves of c(u, s') + g(s') (eq. 2, u != goal).
  double bestRhs(std::size_t i) const {
    double best = kInfiniteCost;
    unsigned m = table_->mask(i);
    while (m != 0) {
      const int k = std::countr_zero(m);
      m &= m - 1;
      const double v = table_->cost(k) + cost_[static_cast<std::size_t>(static_cast<std::ptrdiff_t>(i) + table_->delta(k))].g;
      if (v < best) best = v;
    }
    return best;
  }
  // Greedy step towards the goal: the neighbour minimising c(u, s') + g(s'); `from` when none.
  GridCell nextCell(GridCell from) const;
  // The path from `start` to the goal following nextCell; empty when it does not reach the goal.
  std::vector<GridCell> pathFrom(GridCell start) const;

  // The update log (see the file comment); off by default.
  void setLogging(bool on);
  bool logging() const { return logging_; }
  // Back to the state just after construction (every cost infinite, log empty and off), keeping the
  // memory: planning a goal afresh then costs no page faults for a new 16-bytes-a-cell map.
  void reset();
  std::size_t logSize() const { return log_.size(); }

  std::size_t memoryBytes() const {
    return cost_.capacity() * sizeof(Cost) + logged_.capacity() + log_.capacity() * sizeof(std::uint32_t);
  }

 private:
  friend class DStarQueue;
  friend PlannerStatus dstarComputeShortestPath(DStarGoalField&, DStarQueue&, SearchStats&, const TerminationCondition&);
  friend void dstarUpdateChangedCells(DStarGoalField&, std::span<const GridCell>, std::span<DStarQueue* const>,
                                      SearchStats&);
  friend void dstarUpdateTouchedCells(DStarGoalField&, std::span<const std::uint32_t>, std::span<DStarQueue* const>,
                                      SearchStats&);
  friend void dstarInitialize(DStarGoalField&, DStarQueue&, SearchStats&);
  friend PlannerStatus dstarSweepInitialize(DStarGoalField&, std::span<const GridCell>, DStarQueue&, SearchStats&,
                                           const TerminationCondition&);
  friend void dstarSyncQueue(DStarGoalField&, DStarQueue&, SearchStats&);
  friend void dstarTrimLog(DStarGoalField&, std::span<DStarQueue* const>);

  // g and rhs side by side: every access reads both.
  struct Cost {
    double g;
    double rhs;
  };
  // Moves `queue`'s cursor to the end of the log.
  void readLog(DStarQueue& queue);
  void record(std::uint32_t u) {
    if (logged_[u] == 0) {
      logged_[u] = 1;
      log_.push_back(u);
    }
  }

  std::shared_ptr<GridMoveTable> table_;
  GridCell goal_;
  std::uint32_t goal_index_;
  std::vector<Cost, HugePageAllocator<Cost>> cost_;
  bool pristine_ = true;  // every cost still infinite as constructed
  bool logging_ = false;
  std::vector<std::uint32_t> log_;  // cells whose key changed while they were inconsistent
  // 1: in log_ after every queue's cursor, so not recorded again (every queue will read it).
  std::vector<std::uint8_t> logged_;
  std::size_t log_fresh_ = 0;  // log_ entries from here on have their flag set
};

// Priority queue U of one start: the start cell, its k_m and a lazily cleaned queue.
//
// The queue is two-tier: a 4-ary heap holds every entry whose k1 lies below a moving limit (a
// multiple of kBucketWidth), and the others wait unsorted in buckets of kBucketWidth by k1. Most
// entries of a queue shared by many starts (the frontier of a map searched towards other starts)
// lie far above the current search's bound and are then never sorted. The top is the heap's once
// no bucket entry can compare below it: a bucket is moved into the heap when the heap's top k1 is
// within the tie tolerance of the bucket's lower edge, so ties on k1 are still broken by k2 across
// the limit.
class DStarQueue {
 public:
  struct Entry {
    DStarKey key;
    std::uint32_t cell;
  };

  DStarQueue() = default;
  DStarQueue(GridCell start, double km) : start_(start), km_(km) {}

  GridCell start() const { return start_; }
  void setStart(GridCell start) { start_ = start; }
  double km() const { return km_; }
  void setKm(double km) { km_ = km; }

  // CalcKey (eq. 3) for this queue's start and k_m.
  DStarKey calcKey(const DStarGoalField& field, std::uint32_t cell) const {
    const GridCell c = field.grid().cellOf(cell);
    return calcKey(field, cell, c.x, c.y);
  }
  DStarKey calcKey(const DStarGoalField& field, std::uint32_t cell, int x, int y) const {
    const double m = field.minCost(cell);
    return DStarKey{m + field.moves().estimate(start_, GridCell{x, y}) + km_, m};
  }

  void push(std::uint32_t cell, DStarKey key, SearchStats& stats) {
    const std::size_t b = bucketOf(key.k1);
    if (b < limit_) {
      heap_.push_back(Entry{key, cell});
      siftUp(heap_.size() - 1);
    } else {
      placeFar(b, Entry{key, cell});
    }
    ++stats.queue_pushes;
  }
  // Top live entry after dropping stale ones, or nullptr when none is left.
  const Entry* top(const DStarGoalField& field, SearchStats& stats) {
    for (;;) {
      if (far_count_ != 0 && (heap_.empty() || heap_.front().key.k1 + kCostTolerance >= edgeOf(first_far_))) {
        loadBucket();
        continue;
      }
      if (heap_.empty()) return nullptr;
      const Entry& e = heap_.front();
      if (!field.consistent(e.cell) && costEqual(e.key.k2, field.minCost(e.cell))) return &heap_.front();
      removeTop();
      ++stats.queue_pops;
    }
  }
  // The entry top() returned.
  Entry pop(SearchStats& stats) {
    const Entry e = heap_.front();
    removeTop();
    ++stats.queue_pops;
    return e;
  }
  // Inconsistent cell adaptation (seed 3.3, lines 31-32): recompute every live cell's key for the
  // current start and k_m, drop stale entries, and rebuild the queue.
  void adapt(const DStarGoalField& field, SearchStats& stats);
  std::size_t size() const { return heap_.size() + far_count_; }

 private:
  friend class DStarGoalField;
  friend void dstarSyncQueue(DStarGoalField&, DStarQueue&, SearchStats&);
  friend void dstarTrimLog(DStarGoalField&, std::span<DStarQueue* const>);
  friend PlannerStatus dstarComputeShortestPath(DStarGoalField&, DStarQueue&, SearchStats&, const TerminationCondition&);
  static constexpr std::size_t kArity = 4;  // shallower than binary, children share a cache line
  // A power of two, so bucket edges are exact; keys are sums of move costs near 1.
  static constexpr double kBucketWidth = 2.0;
  // Keys beyond (unbounded k_m growth, or a huge grid) share the last bucket: still correct, as a
  // bucket only promises k1 >= its lower edge.
  static constexpr std::size_t kMaxBucket = std::size_t{1} << 20;
  static std::size_t bucketOf(double k1) {
    const double b = k1 / kBucketWidth;
    return b < static_cast<double>(kMaxBucket) ? static_cast<std::size_t>(b) : kMaxBucket;
  }
  static double edgeOf(std::size_t bucket) { return static_cast<double>(bucket) * kBucketWidth; }
  void placeFar(std::size_t bucket, const Entry& e) {
    if (bucket >= far_.size()) far_.resize(bucket + 1);
    far_[bucket].push_back(e);
    if (far_count_ == 0 || bucket < first_far_) first_far_ = bucket;
    ++far_count_;
  }
  // Moves the lowest non-empty bucket into the heap and raises the limit past it.
  void loadBucket();
  void siftUp(std::size_t i);
  void siftDown(std::size_t i, Entry e);
  // Of the children from index `first` (the heap holding n entries), the one with the smallest key.
  std::size_t smallestChild(std::size_t first, std::size_t n) const;
  // Pops the root bottom-up (Floyd): the hole walks down the smaller children to a leaf and the
  // last entry, usually among the largest, sifts up from there; this saves the comparison with it
  // at every level, and the removals are most of the queue's time.
  void removeTop();

  GridCell start_;
  double km_ = 0.0;
  std::vector<Entry> heap_;               // every entry whose bucket is below limit_
  std::size_t limit_ = 0;                 // buckets below this are in the heap
  std::vector<std::vector<Entry>> far_;   // by bucket, from limit_ on
  std::size_t far_count_ = 0;
  std::size_t first_far_ = 0;             // lowest non-empty bucket when far_count_ > 0
  std::size_t log_cursor_ = 0;      // the field's log entries before this are in the queue
  std::size_t compacted_size_ = 0;  // size after the last adapt: grows of stale entries trigger one
};

// ComputeShortestPath (optimised D* Lite; lines 09-19 of the seed) with `queue` as U. When the
// field logs, every insertion is recorded for the other queues sharing the field (lines 20-30).
PlannerStatus dstarComputeShortestPath(DStarGoalField& field, DStarQueue& queue, SearchStats& stats,
                                      const TerminationCondition& stop);

// Repairs rhs after the blocked state of `changed` cells flipped (the grid already shows the new
// state): every move touching a changed cell, including diagonals cut at its corner, has both ends
// in its 8-neighbourhood, so those cells' rhs is recomputed and the vertex updated in every queue
// of `queues` and, when the field logs, recorded for the others (seed lines 63-65).
void dstarUpdateChangedCells(DStarGoalField& field, std::span<const GridCell> changed,
                             std::span<DStarQueue* const> queues, SearchStats& stats);
// The same in two parts, for many fields on one grid (MMD*L's goals): the cells whose rhs a change
// can alter (each changed cell's 3x3 block, sorted, once), then the repair of one field from that
// list (the move table must already follow the change).
std::vector<std::uint32_t> dstarTouchedCells(const GridLayer& grid, std::span<const GridCell> changed);
void dstarUpdateTouchedCells(DStarGoalField& field, std::span<const std::uint32_t> touched,
                             std::span<DStarQueue* const> queues, SearchStats& stats);

// Loading a start's queue (line 26/69 "load U"): inserts the logged cells it has not seen yet that
// are still inconsistent, keyed with its current start and k_m; adapts it when stale entries have
// piled up.
void dstarSyncQueue(DStarGoalField& field, DStarQueue& queue, SearchStats& stats);
// Drops the log entries every queue of `queues` (all queues sharing the field) has seen.
void dstarTrimLog(DStarGoalField& field, std::span<DStarQueue* const> queues);

// Initialize() (lines 01-05) for a new field: puts the goal into `queue`.
void dstarInitialize(DStarGoalField& field, DStarQueue& queue, SearchStats& stats);

// A cheaper first search of a new field than Initialize() plus ComputeShortestPath towards each
// start in turn (seed lines 34-38), for a goal with many starts on a large grid: Dijkstra from the
// goal with a bucket queue of width 1 (Dial), which settles cells in order of g until every cell
// of `starts` is settled, then finishes that bucket. Every move costs at least 1, so no cell of a
// bucket can lower another cell of the same bucket: settling a bucket's cells in any order is exact
// (each g the minimum over the relaxations, as Dijkstra's). It leaves the state D* Lite needs for
// later repairs: every settled cell consistent (g = rhs), rhs = min over successors of c + g
// everywhere, and every inconsistent cell (the frontier, all with rhs above every start's g) pushed
// into `frontier` keyed for its start and k_m; the caller then gives each start a copy adapted to
// it (lines 39-41), so those starts' searches stop at once. Expansions count settled cells and queue
// operations the bucket queue's pushes and pops, so they are not comparable with the seed's.
// kNoPath when some start was not reached (its g stays infinite, as D* Lite would leave it);
// A stopped status (isStopped) when `stop` fired (the field is then partly built and must be reset before reuse).
PlannerStatus dstarSweepInitialize(DStarGoalField& field, std::span<const GridCell> starts, DStarQueue& frontier,
                                  SearchStats& stats, const TerminationCondition& stop);

// Plain single-pair D* Lite.
class DStarLite {
 public:
  DStarLite(const GridLayer& grid, GridCell start, GridCell goal, const GridMoves& moves = {});
  // Many pairs on one grid can share a move table (the per-pair baseline of MMD*L).
  DStarLite(std::shared_ptr<GridMoveTable> table, GridCell start, GridCell goal);

  // kInvalidStart / kInvalidGoal when outside or blocked (checked before any search).
  PlannerStatus computeShortestPath(const TerminationCondition& stop = {});
  // The vehicle moved; k_m grows by h(last, new) before the next vertex update or search (line 52).
  void moveStart(GridCell start) { queue_.setStart(start); }
  // The grid's blocked state of these cells changed; call computeShortestPath afterwards.
  void updateCells(std::span<const GridCell> changed);

  GridCell start() const { return queue_.start(); }
  GridCell goal() const { return field_.goal(); }
  double km() const { return queue_.km(); }
  double cost() const { return field_.costFrom(queue_.start()); }
  std::vector<GridCell> path() const { return field_.pathFrom(queue_.start()); }
  GridCell nextCell() const { return field_.nextCell(queue_.start()); }
  const DStarGoalField& field() const { return field_; }
  const SearchStats& stats() const { return stats_; }
  void resetStats() { stats_ = SearchStats{}; }

 private:
  DStarGoalField field_;
  DStarQueue queue_;
  GridCell last_start_;
  SearchStats stats_;
};

}  // namespace skyroute
