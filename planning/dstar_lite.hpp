// D* Lite (Koenig & Likhachev 2005, the optimised version with k_m) on the 8-connected GridLayer,
// searching from the goal towards the start so the costs survive start moves.
//
// The parts are split the way MMD*L (mmdstar_lite.hpp) needs them: DStarGoalField holds g and rhs
// of every cell for one goal (independent of the start, seed section 3.2), DStarQueue is the
// priority queue U of one start with its k_m, and the free functions run ComputeShortestPath and
// the edge-cost repair on a field with one active queue plus any queues sharing the field
// (MMD*L's lines 20-30: every vertex update is mirrored into them). DStarLite is the plain
// single-pair planner built from the same parts.
//
// Queue entries are deleted lazily: an entry is live while its cell is inconsistent and its k2
// equals the cell's current min(g, rhs); a stale one is dropped when it reaches the top. A live
// entry whose k1 was computed with an older k_m is a lower bound and gets re-keyed on pop, exactly
// as the optimised algorithm's "k_old < CalcKey(u)" branch.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <span>
#include <vector>

#include "planning/grid_search.hpp"
#include "planning/termination.hpp"
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
  friend bool operator<(const DStarKey& a, const DStarKey& b) {
    return costLess(a.k1, b.k1) || (costEqual(a.k1, b.k1) && costLess(a.k2, b.k2));
  }
};

class DStarQueue;

// g and rhs of every cell for one goal (eqs. 1 and 2). Costs in cell edges.
class DStarGoalField {
 public:
  DStarGoalField(const GridLayer& grid, GridCell goal, const GridMoves& moves);

  const GridLayer& grid() const { return *grid_; }
  const GridMoves& moves() const { return moves_; }
  GridCell goal() const { return goal_; }
  std::uint32_t goalIndex() const { return goal_index_; }

  double g(std::uint32_t i) const { return g_[i]; }
  double rhs(std::uint32_t i) const { return rhs_[i]; }
  double minCost(std::uint32_t i) const { return std::min(g_[i], rhs_[i]); }
  bool consistent(std::uint32_t i) const { return costEqual(g_[i], rhs_[i]); }
  // Cost to the goal of a cell whose search is complete (g); infinity when not reached.
  double costFrom(GridCell c) const { return grid_->inside(c) ? g_[grid_->index(c)] : kInfiniteCost; }

  // rhs from the successors: min over moves of c(u, s') + g(s') (eq. 2, u != goal).
  double bestRhs(std::uint32_t i) const;
  // Greedy step towards the goal: the neighbour minimising c(u, s') + g(s'); `from` when none.
  GridCell nextCell(GridCell from) const;
  // The path from `start` to the goal following nextCell; empty when it does not reach the goal.
  std::vector<GridCell> pathFrom(GridCell start) const;

  std::size_t memoryBytes() const { return (g_.capacity() + rhs_.capacity()) * sizeof(double); }

 private:
  friend SearchStatus dstarComputeShortestPath(DStarGoalField&, DStarQueue&, std::span<DStarQueue* const>,
                                               SearchStats&, const TerminationCondition&);
  friend void dstarUpdateChangedCells(DStarGoalField&, std::span<const GridCell>, std::span<DStarQueue* const>,
                                      SearchStats&);
  friend void dstarInitialize(DStarGoalField&, DStarQueue&, SearchStats&);
  const GridLayer* grid_;
  GridMoves moves_;
  GridCell goal_;
  std::uint32_t goal_index_;
  std::vector<double> g_;
  std::vector<double> rhs_;
};

// Priority queue U of one start: the start cell, its k_m and a lazily cleaned binary heap.
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
  DStarKey calcKey(const DStarGoalField& field, std::uint32_t cell) const;

  void push(std::uint32_t cell, DStarKey key, SearchStats& stats);
  // Top live entry after dropping stale ones, or nullptr when none is left.
  const Entry* top(const DStarGoalField& field, SearchStats& stats);
  Entry pop(SearchStats& stats);
  // Inconsistent cell adaptation (seed 3.3, lines 31-32): recompute every live cell's key for the
  // current start and k_m, drop stale and duplicate entries, and rebuild the heap.
  void adapt(const DStarGoalField& field, SearchStats& stats);
  std::size_t size() const { return heap_.size(); }

 private:
  GridCell start_;
  double km_ = 0.0;
  std::vector<Entry> heap_;
};

// ComputeShortestPath (optimised D* Lite; lines 09-30 of the seed). `mirrors` are the queues of
// other starts sharing the field: every vertex update is inserted there too, with their own start
// and k_m (MMD*L replanning); empty for plain D* Lite and for MMD*L preplanning.
SearchStatus dstarComputeShortestPath(DStarGoalField& field, DStarQueue& queue, std::span<DStarQueue* const> mirrors,
                                      SearchStats& stats, const TerminationCondition& stop);

// Repairs rhs after the blocked state of `changed` cells flipped (the grid already shows the new
// state): every move touching a changed cell, including diagonals cut at its corner, has both ends
// in its 8-neighbourhood, so those cells' rhs is recomputed and the vertex updated in every queue
// of `queues` (seed lines 63-65).
void dstarUpdateChangedCells(DStarGoalField& field, std::span<const GridCell> changed,
                             std::span<DStarQueue* const> queues, SearchStats& stats);

// Initialize() (lines 01-05) for a new field: puts the goal into `queue`.
void dstarInitialize(DStarGoalField& field, DStarQueue& queue, SearchStats& stats);

// Plain single-pair D* Lite.
class DStarLite {
 public:
  DStarLite(const GridLayer& grid, GridCell start, GridCell goal, const GridMoves& moves = {});

  // kInvalidStart / kInvalidGoal when outside or blocked (checked before any search).
  SearchStatus computeShortestPath(const TerminationCondition& stop = {});
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
