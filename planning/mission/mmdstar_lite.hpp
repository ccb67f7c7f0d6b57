// Multiple Mission D* Lite (Lee, Chang & Jang, JKSAS 2019; seed 000, Fig. 8 and 9).
//
// One g/rhs map per goal (remaining mission points and E), shared by every start that leads to it
// (the vehicle and the other remaining mission points), because g does not depend on the start
// (section 3.2). Each start keeps its own queue U:
//  - preplanning (lines 33-42): per goal one queue is carried from start to start, re-keyed by
//    inconsistent cell adaptation, and each start gets a copy adapted to it at the end;
//  - replanning (lines 51-71): changed cells update the vertex once per goal, then each start's
//    ComputeShortestPath runs on its own queue; every insertion into U (from the changed cells or
//    from another start's expansions) reaches the queues of the other starts of the goal, keyed
//    with k_m = 0 for starts that are mission points not reached yet and the vehicle's k_m for the
//    vehicle's queue (lines 20-30, 60-61, 67-68). The insertions are recorded once in the field and
//    replayed into a queue when it is loaded (dstar_lite.hpp), which leaves the same live entries
//    as inserting into every queue at every update, at a fraction of the queue operations.
// Memory: n+1 maps of g/rhs (plus the queues, which hold only inconsistent cells).
// Beyond the seed: the goals' maps can be planned on several threads (they share nothing but the
// read-only move table; same results), and, off by default: a goal whose repair in one step costs
// more than a set fraction of planning it from scratch is planned afresh (setFreshPlanFraction) or,
// for a mission point, deferred (setDeferGoalMaps: its costs then come from the other points' maps,
// moves being symmetric); and a goal's map is planned from scratch by a Dijkstra bucket sweep
// rather than the seed's D* Lite searches on large grids (setSweepMinCells). All exact.
#pragma once

#include <atomic>
#include <cstdint>
#include <memory>
#include <vector>

#include "planning/grid/dstar_lite.hpp"
#include "planning/mission/mission_search.hpp"

namespace skyroute {

// Lines 34-38 for one goal and any number of starts, outside a mission: one g/rhs map and one queue
// carried from start to start with inconsistent cell adaptation (used by `grid solve` to answer
// problems that share a goal).
class SharedGoalSearch {
 public:
  SharedGoalSearch(const GridLayer& grid, GridCell goal, const GridMoves& moves = {});
  // Plans from `start` reusing everything earlier starts computed. kInvalidStart / kInvalidGoal
  // when outside or blocked.
  PlannerStatus solveFrom(GridCell start, const TerminationCondition& stop = {});
  double cost(GridCell start) const { return field_.costFrom(start); }
  std::vector<GridCell> path(GridCell start) const { return field_.pathFrom(start); }
  GridCell goal() const { return field_.goal(); }
  const SearchStats& stats() const { return stats_; }

 private:
  DStarGoalField field_;
  DStarQueue queue_;
  bool initialized_ = false;
  SearchStats stats_;
};

class MmdStarLite final : public MissionSearch {
 public:
  // points: [B, M1..Mn, E]; every point must be inside and passable (the caller validates).
  // threads: goals planned at once (each goal's map, queues and searches belong to one thread; the
  // move table is updated before they start and only read by them). Results and counters do not
  // depend on it.
  MmdStarLite(const GridLayer& grid, std::vector<GridCell> points, const GridMoves& moves = {}, int threads = 1);

  std::string_view name() const override { return "mmdstar"; }
  PlannerStatus preplan(const TerminationCondition& stop = {}) override;
  PlannerStatus applyChanges(std::span<const GridCell> changed, const TerminationCondition& stop = {}) override;
  double cost(int from_point, int to_point) const override;
  std::vector<GridCell> path(int from_point, int to_point) const override;
  GridCell nextCell(int goal_point) const override;
  std::size_t costMapCount() const override;
  void setThreads(int threads) override { threads_ = threads < 1 ? 1 : threads; }
  void moveVehicle(GridCell cell) override;
  void arriveAt(int point) override;

  // Deviation from the seed, off by default (0): when repairing a goal's map after a change has
  // cost more than `fraction` times the expansions of planning that goal from scratch, the repair
  // is abandoned and the goal planned afresh (lines 34-42 on the new grid). A change next to a goal
  // can alter nearly every g of its map; D* Lite then expands each cell twice (invalidate, settle)
  // at a higher price per expansion than a fresh search, which expands each once. Exact either way.
  void setFreshPlanFraction(double fraction) { fresh_plan_fraction_ = fraction; }
  // Goals planned afresh by that rule since construction.
  std::size_t freshPlans() const { return fresh_plans_; }

  // Deviation from the seed for large grids: a goal's map is planned from scratch (preplanning,
  // and the fresh-plan rule) by one Dijkstra bucket sweep from the goal until all its starts are
  // settled (dstarSweepInitialize) instead of D* Lite towards each start in turn (lines 34-38),
  // when the grid has at least `min_cells` cells and the goal at least kSweepMinStarts starts.
  // With many starts spread over the grid the seed's searches reach about the same cells, at
  // several times the cost per cell (heap, re-keying at every start); with few starts its
  // heuristic saves more than the sweep's cheaper cells. The maps, queues and repairs that follow
  // are the seed's. 0 = never (the seed's search; default, so counters match the paper's).
  void setSweepMinCells(std::size_t min_cells) { sweep_min_cells_ = min_cells; }
  static constexpr std::size_t kSweepMinStarts = 4;

  // Deviation from the seed, off by default, used with the fresh-plan rule: a mission point's goal
  // whose repair outgrows the budget is not planned afresh but *deferred*: its map is left stale
  // and its queues dropped. Its matrix entries stay exact without it, because moves are symmetric
  // (c(a, b) = c(b, a)): every other start of that goal is a remaining mission point whose own map
  // has this goal among its starts, so that map's g at this goal, exact after its own repair, is
  // the cost; its path is that map's path from the goal, reversed. The one start without a map,
  // the vehicle, gets an A* on the current grid (kept while the vehicle follows it). A deferred
  // goal is planned afresh only when another mission start of it is deferred too. A change next to
  // a goal, which alters nearly every g of that goal's map, then costs the budget plus one A*
  // instead of a whole map. The end point E is never a start, so it is planned afresh as before.
  void setDeferGoalMaps(bool on) { defer_goal_maps_ = on; }
  // Goals deferred by that rule since construction.
  std::size_t deferredGoals() const { return deferred_goals_; }

  // Deviation from the seed, off by default: each pair of remaining goals {a, b} (mission points
  // and E) is searched in one of the two maps only, since moves are symmetric (c(a, b) = c(b, a)):
  // for a < b, in a's map when a + b is odd, in b's when even (E then serves as a start of the
  // mission maps that host its pairs). Every map hosts about half
  // of its pairs, so a change next to a goal repairs that goal's map for half as many starts, and
  // the other half of that goal's pairs are repaired near their far end in the other maps, on the
  // other threads. The vehicle stays a start of every map (it is no goal). The rule depends only on
  // the points' numbers, so pairs never move between maps; at an arrival the old vehicle's queue
  // of a map that did not host the reached point becomes the new vehicle's (re-keyed, and searched
  // to the new start at once), and E's map is made then if it hosted nothing. Exact. Not combined
  // with setDeferGoalMaps (which needs every goal's other maps to hold it): deferral wins.
  void setSymmetricPairs(bool on) { symmetric_pairs_ = on; }

  // The shared map of a remaining goal (nullptr otherwise, or when deferred); for tests.
  const DStarGoalField* field(int goal_point) const;

 private:
  struct StartSlot {
    int point = 0;
    DStarQueue queue;
  };
  struct GoalSlot {
    int point = 0;
    std::unique_ptr<DStarGoalField> field;
    std::vector<StartSlot> starts;
    std::uint64_t plan_expansions = 0;  // of its last planning from scratch (lines 34-42)
    // setDeferGoalMaps: the map is stale, the costs come from the other goals' maps and, for the
    // vehicle, from vehicle_path (vehicle cell .. goal, empty when none) and vehicle_cost.
    // The route is found again lazily (route_stale) when the vehicle leaves it, by the const
    // readers (cost, path, nextCell): like the rest of the planner, not for concurrent callers.
    bool deferred = false;
    mutable bool route_stale = false;
    mutable std::vector<GridCell> vehicle_path;
    mutable double vehicle_cost = kInfiniteCost;
  };

  GoalSlot* slot(int goal_point);
  // Lines 34-42 for one goal whose field exists.
  PlannerStatus preplanGoal(GoalSlot& goal, SearchStats& stats, const TerminationCondition& stop) const;
  // Lines 57-71 for one goal (the move table already follows the change; `touched`: the cells
  // whose rhs it can alter, dstarTouchedCells).
  PlannerStatus replanGoal(GoalSlot& goal, std::span<const std::uint32_t> touched, SearchStats& stats,
                          const TerminationCondition& stop);
  // Runs work(goal, stats) for every goal on up to threads_ threads; a stopped status (isStopped) if any stopped.
  template <class Work>
  PlannerStatus forEachGoal(Work&& work);
  const GoalSlot* slot(int goal_point) const;
  // After every goal's repair: plans afresh the deferred goals that lack a source map, routes the
  // vehicle to the others.
  PlannerStatus settleDeferred(const TerminationCondition& stop);
  // A* from the vehicle to a deferred goal on the current grid; returns its counters.
  SearchStats routeVehicle(const GoalSlot& goal) const;
  const GoalSlot& routed(const GoalSlot& goal) const {
    if (goal.route_stale) routeVehicle(goal);
    return goal;
  }
  bool splitPairs() const { return symmetric_pairs_ && !defer_goal_maps_; }
  // The points whose queue lives in goal_point's map: startsFor(goal_point), or with split pairs
  // the vehicle and the other remaining goals whose pair with it this map hosts.
  std::vector<int> mapStarts(int goal_point) const;
  // With split pairs: the goal whose map holds the pair {a, b} of two remaining goals.
  // The lower of the two when a + b is odd, the higher when even: each goal hosts about half of
  // the others, above and below it alike.
  static int hostOf(int a, int b) { return (a + b) % 2 == 1 ? std::min(a, b) : std::max(a, b); }
  // The map and start in it that give the cost of from -> to (nullptr when none).
  struct PairSource {
    const GoalSlot* map = nullptr;
    GridCell start;
    bool reversed = false;  // the map's goal is `from`: its path runs to -> from
  };
  PairSource pairSource(int from_point, int to_point) const;
  // Arrival with split pairs: gives every remaining map a queue for the new vehicle point.
  void arriveSplit(int old_vehicle);
  bool useSweep(std::size_t starts) const {
    return sweep_min_cells_ > 0 && grid_->cellCount() >= sweep_min_cells_ && starts >= kSweepMinStarts;
  }

  std::shared_ptr<GridMoveTable> table_;  // shared by every field
  std::vector<GoalSlot> goals_;
  int threads_ = 1;
  double fresh_plan_fraction_ = 0.0;
  std::size_t sweep_min_cells_ = 0;
  bool defer_goal_maps_ = false;
  bool symmetric_pairs_ = false;
  std::atomic<std::size_t> deferred_goals_{0};
  std::atomic<std::size_t> fresh_plans_{0};
};

}  // namespace skyroute
