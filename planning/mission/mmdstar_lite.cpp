#include "planning/mission/mmdstar_lite.hpp"

#include <algorithm>
#include <atomic>
#include <thread>

namespace skyroute {

SharedGoalSearch::SharedGoalSearch(const GridLayer& grid, GridCell goal, const GridMoves& moves)
    : field_(grid, goal, moves), queue_(goal, 0.0) {}

SearchStatus SharedGoalSearch::solveFrom(GridCell start, const TerminationCondition& stop) {
  if (field_.grid().blocked(start)) return SearchStatus::kInvalidStart;
  if (field_.grid().blocked(field_.goal())) return SearchStatus::kInvalidGoal;
  queue_.setStart(start);
  if (!initialized_) {
    dstarInitialize(field_, queue_, stats_);
    initialized_ = true;
  } else {
    queue_.adapt(field_, stats_);
  }
  return dstarComputeShortestPath(field_, queue_, stats_, stop);
}

MmdStarLite::MmdStarLite(const GridLayer& grid, std::vector<GridCell> points, const GridMoves& moves, int threads)
    : MissionSearch(grid, std::move(points), moves), threads_(std::max(1, threads)) {}

template <class Work>
SearchStatus MmdStarLite::forEachGoal(Work&& work) {
  // Goals are taken in order from a shared counter: their costs differ a lot (a change near one goal
  // can cost more than all others together), so a fixed split would leave a thread idle.
  std::atomic<std::size_t> next{0};
  std::atomic<bool> stopped{false};
  const std::size_t helpers = std::min<std::size_t>(static_cast<std::size_t>(threads_), goals_.size());
  std::vector<SearchStats> stats(std::max<std::size_t>(helpers, 1));
  auto loop = [&](std::size_t t) {
    for (std::size_t i = next++; i < goals_.size() && !stopped.load(std::memory_order_relaxed); i = next++)
      if (work(goals_[i], stats[t]) == SearchStatus::kStopped) stopped = true;
  };
  std::vector<std::thread> pool;
  for (std::size_t t = 1; t < helpers; ++t) pool.emplace_back(loop, t);
  loop(0);
  for (std::thread& th : pool) th.join();
  for (const SearchStats& s : stats) stats_ += s;
  return stopped ? SearchStatus::kStopped : SearchStatus::kFound;
}

MmdStarLite::GoalSlot* MmdStarLite::slot(int goal_point) {
  for (GoalSlot& g : goals_)
    if (g.point == goal_point) return &g;
  return nullptr;
}

const MmdStarLite::GoalSlot* MmdStarLite::slot(int goal_point) const {
  for (const GoalSlot& g : goals_)
    if (g.point == goal_point) return &g;
  return nullptr;
}

const DStarGoalField* MmdStarLite::field(int goal_point) const {
  const GoalSlot* g = slot(goal_point);
  return g && !g->deferred ? g->field.get() : nullptr;
}

SearchStatus MmdStarLite::preplanGoal(GoalSlot& goal, SearchStats& stats, const TerminationCondition& stop) const {
  const std::vector<int> starts = startsFor(goal.point);
  const std::uint64_t expansions_before = stats.expansions;
  // One U carried from start to start (lines 34-38).
  DStarQueue carried(startCell(starts.front()), 0.0);
  if (useSweep(starts.size())) {
    // Beyond the seed (setSweepMinCells): one Dijkstra sweep until every start is settled, which
    // leaves the same kind of state as lines 34-38 (see dstarSweepInitialize).
    std::vector<GridCell> cells;
    for (int start_point : starts) cells.push_back(startCell(start_point));
    if (dstarSweepInitialize(*goal.field, cells, carried, stats, stop) == SearchStatus::kStopped)
      return SearchStatus::kStopped;
  } else {
    dstarInitialize(*goal.field, carried, stats);  // line 34
    for (int start_point : starts) {               // line 35
      carried.setStart(startCell(start_point));
      carried.setKm(0.0);
      carried.adapt(*goal.field, stats);  // line 37
      if (dstarComputeShortestPath(*goal.field, carried, stats, stop) == SearchStatus::kStopped)  // line 38
        return SearchStatus::kStopped;
    }
  }
  // Lines 39-41: every start keeps the final U adapted to itself.
  for (int start_point : starts) {
    StartSlot st{start_point, carried};
    st.queue.setStart(startCell(start_point));
    st.queue.setKm(start_point == vehicle_point_ ? km_ : 0.0);
    st.queue.adapt(*goal.field, stats);
    goal.starts.push_back(std::move(st));
  }
  // From now on the starts share their insertions through the field (lines 20-30).
  goal.field->setLogging(true);
  goal.plan_expansions = stats.expansions - expansions_before;
  return SearchStatus::kFound;
}

SearchStatus MmdStarLite::preplan(const TerminationCondition& stop) {
  goals_.clear();
  table_ = std::make_shared<GridMoveTable>(*grid_, moves_);
  for (int goal_point : remainingGoals()) {  // line 33
    if (startsFor(goal_point).empty()) continue;
    GoalSlot goal;
    goal.point = goal_point;
    goals_.push_back(std::move(goal));
  }
  const SearchStatus status = forEachGoal([&](GoalSlot& goal, SearchStats& stats) {
    // Made by the goal's thread: filling 16 bytes a cell is a good part of a large map's cost.
    goal.field = std::make_unique<DStarGoalField>(table_, points_[goal.point]);
    return preplanGoal(goal, stats, stop);
  });
  // After a stop, goals never started hold no map.
  std::erase_if(goals_, [](const GoalSlot& g) { return g.field == nullptr; });
  return status;
}

SearchStatus MmdStarLite::replanGoal(GoalSlot& goal, std::span<const GridCell> changed, SearchStats& stats,
                                     const TerminationCondition& stop) {
  if (goal.deferred) return SearchStatus::kFound;  // nothing to repair: its costs come from other maps
  std::vector<DStarQueue*> queues;
  for (StartSlot& st : goal.starts) {
    // Lines 60-61 / 67-68: the vehicle's queue uses its k_m; unreached mission points use 0.
    const bool is_vehicle = st.point == vehicle_point_;
    st.queue.setKm(is_vehicle ? km_ : 0.0);
    st.queue.setStart(startCell(st.point));
    queues.push_back(&st.queue);
  }
  dstarTrimLog(*goal.field, queues);
  // Lines 58-65: rhs repaired once per goal; the insertions reach each queue when it is loaded.
  dstarUpdateChangedCells(*goal.field, changed, {}, stats);
  // The repair's own count, for the fresh-plan rule (setFreshPlanFraction): its iteration budget
  // stops the repair, the caller's `stop` is checked separately.
  SearchStats repair;
  const bool bounded = fresh_plan_fraction_ > 0.0;
  TerminationCondition budget = stop;
  if (bounded)
    budget.withIterationBudget(static_cast<std::uint64_t>(fresh_plan_fraction_ * static_cast<double>(goal.plan_expansions)) + 1);
  for (DStarQueue* q : queues) {  // lines 66-70
    dstarSyncQueue(*goal.field, *q, repair);  // line 69: load U with what the others inserted
    if (dstarComputeShortestPath(*goal.field, *q, repair, bounded ? budget : stop) == SearchStatus::kStopped) {
      stats += repair;
      if (!bounded || stop.shouldStop()) return SearchStatus::kStopped;
      if (defer_goal_maps_ && goal.point != endPoint()) {
        // Over budget: leave the map stale (setDeferGoalMaps); settleDeferred does the rest.
        ++deferred_goals_;
        goal.deferred = true;
        goal.starts.clear();
        return SearchStatus::kFound;
      }
      // Over budget: plan this goal from scratch on the current grid.
      ++fresh_plans_;
      goal.starts.clear();
      goal.field->reset();
      return preplanGoal(goal, stats, stop);
    }
  }
  stats += repair;
  return SearchStatus::kFound;
}

SearchStatus MmdStarLite::applyChanges(std::span<const GridCell> changed, const TerminationCondition& stop) {
  if (changed.empty()) return SearchStatus::kFound;
  accumulateKm();  // lines 52-54
  // The shared move table follows the change here, once, before the goals' threads read it.
  if (table_) table_->update(changed);
  const SearchStatus status =
      forEachGoal([&](GoalSlot& goal, SearchStats& stats) { return replanGoal(goal, changed, stats, stop); });
  if (status == SearchStatus::kStopped) return status;
  return settleDeferred(stop);
}

SearchStatus MmdStarLite::settleDeferred(const TerminationCondition& stop) {
  for (GoalSlot& goal : goals_) {
    if (!goal.deferred) continue;
    bool sourced = true;
    for (int p : startsFor(goal.point)) {
      if (p == vehicle_point_) continue;
      const GoalSlot* source = slot(p);
      sourced = sourced && source != nullptr && !source->deferred;
    }
    if (sourced) {
      stats_ += routeVehicle(goal);
      continue;
    }
    // Two deferred goals would each need the other's map: plan this one afresh.
    ++fresh_plans_;
    goal.deferred = false;
    goal.vehicle_path.clear();
    goal.field->reset();
    SearchStats stats;
    const SearchStatus s = preplanGoal(goal, stats, stop);
    stats_ += stats;
    if (s == SearchStatus::kStopped) return s;
  }
  return SearchStatus::kFound;
}

SearchStats MmdStarLite::routeVehicle(const GoalSlot& goal) const {
  goal.route_stale = false;
  goal.vehicle_path.clear();
  goal.vehicle_cost = kInfiniteCost;
  if (!planned(vehicle_point_, goal.point)) return {};
  GridPath route = astarSearch(*grid_, vehicle_cell_, points_[goal.point], moves_);
  if (route.status == SearchStatus::kFound) {
    goal.vehicle_path = std::move(route.cells);
    goal.vehicle_cost = route.cost;
  }
  return route.stats;
}

double MmdStarLite::cost(int from_point, int to_point) const {
  if (!planned(from_point, to_point)) return kInfiniteCost;
  const GoalSlot* g = slot(to_point);
  if (g == nullptr) return kInfiniteCost;
  if (g->deferred) {
    if (from_point == vehicle_point_) return routed(*g).vehicle_cost;
    // Symmetric moves: the start's own map holds the cost from this goal (setDeferGoalMaps).
    const GoalSlot* source = slot(from_point);
    return source ? source->field->costFrom(points_[to_point]) : kInfiniteCost;
  }
  return g->field->costFrom(startCell(from_point));
}

std::vector<GridCell> MmdStarLite::path(int from_point, int to_point) const {
  if (!planned(from_point, to_point)) return {};
  const GoalSlot* g = slot(to_point);
  if (g == nullptr) return {};
  if (g->deferred) {
    if (from_point == vehicle_point_) return routed(*g).vehicle_path;
    const GoalSlot* source = slot(from_point);
    if (source == nullptr) return {};
    std::vector<GridCell> cells = source->field->pathFrom(points_[to_point]);
    std::reverse(cells.begin(), cells.end());
    return cells;
  }
  return g->field->pathFrom(startCell(from_point));
}

GridCell MmdStarLite::nextCell(int goal_point) const {
  const GoalSlot* g = slot(goal_point);
  if (g == nullptr) return vehicle_cell_;
  if (g->deferred) {
    const std::vector<GridCell>& route = routed(*g).vehicle_path;
    return route.size() >= 2 ? route[1] : vehicle_cell_;
  }
  return g->field->nextCell(vehicle_cell_);
}

std::size_t MmdStarLite::costMapCount() const { return goals_.size(); }

void MmdStarLite::moveVehicle(GridCell cell) {
  MissionSearch::moveVehicle(cell);
  for (GoalSlot& goal : goals_) {
    for (StartSlot& st : goal.starts)
      if (st.point == vehicle_point_) st.queue.setStart(cell);
    if (!goal.deferred) continue;
    // Following the route keeps its rest optimal; anywhere else needs a new one (found when asked).
    if (!goal.route_stale && goal.vehicle_path.size() >= 2 && goal.vehicle_path[1] == cell) {
      const GridCell from = goal.vehicle_path.front();
      const bool diagonal = from.x != cell.x && from.y != cell.y;
      goal.vehicle_cost -= diagonal ? moves_.diagonal_cost : 1.0;
      goal.vehicle_path.erase(goal.vehicle_path.begin());
    } else if (goal.vehicle_path.empty() || !(goal.vehicle_path.front() == cell)) {
      goal.route_stale = true;
    }
  }
}

void MmdStarLite::arriveAt(int point) {
  const int old_vehicle = vehicle_point_;
  MissionSearch::arriveAt(point);
  // Lines 73-77: the reached point stops being a goal; its queues become the vehicle's (k_m = 0),
  // and the old vehicle's queues, and now unplanned pairs, are dropped.
  goals_.erase(std::remove_if(goals_.begin(), goals_.end(), [&](const GoalSlot& g) { return g.point == point; }),
               goals_.end());
  for (GoalSlot& goal : goals_) {
    std::erase_if(goal.starts, [&](const StartSlot& st) {
      return st.point == old_vehicle || !planned(st.point, goal.point);
    });
    for (StartSlot& st : goal.starts)
      if (st.point == vehicle_point_) st.queue.setKm(0.0);
  }
  // The reached point's map, a source of the deferred goals, is gone with it; the vehicle, now
  // there, gets its own route.
  for (GoalSlot& goal : goals_)
    if (goal.deferred) goal.route_stale = true;
}

}  // namespace skyroute
