#include "planning/mission/mmdstar_lite.hpp"

#include <algorithm>
#include <atomic>
#include <thread>

namespace skyroute {

SharedGoalSearch::SharedGoalSearch(const GridLayer& grid, GridCell goal, const GridMoves& moves)
    : field_(grid, goal, moves), queue_(goal, 0.0) {}

PlannerStatus SharedGoalSearch::solveFrom(GridCell start, const TerminationCondition& stop) {
  if (field_.grid().blocked(start)) return PlannerStatus::kStartInvalid;
  if (field_.grid().blocked(field_.goal())) return PlannerStatus::kGoalInvalid;
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
PlannerStatus MmdStarLite::forEachGoal(Work&& work) {
  // Goals are taken in order from a shared counter: their costs differ a lot (a change near one goal
  // can cost more than all others together), so a fixed split would leave a thread idle.
  std::atomic<std::size_t> next{0};
  std::atomic<bool> stopped{false};
  std::atomic<PlannerStatus> stopped_as{PlannerStatus::kSolved};  // how a stopped goal's search ended
  const std::size_t helpers = std::min<std::size_t>(static_cast<std::size_t>(threads_), goals_.size());
  std::vector<SearchStats> stats(std::max<std::size_t>(helpers, 1));
  auto loop = [&](std::size_t t) {
    for (std::size_t i = next++; i < goals_.size() && !stopped.load(std::memory_order_relaxed); i = next++)
      if (const PlannerStatus s = work(goals_[i], stats[t]); isStopped(s)) {
        stopped_as = s;
        stopped = true;
      }
  };
  std::vector<std::thread> pool;
  for (std::size_t t = 1; t < helpers; ++t) pool.emplace_back(loop, t);
  loop(0);
  for (std::thread& th : pool) th.join();
  for (const SearchStats& s : stats) stats_ += s;
  return stopped ? stopped_as.load() : PlannerStatus::kSolved;
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

std::vector<int> MmdStarLite::mapStarts(int goal_point) const {
  if (!splitPairs()) return startsFor(goal_point);
  std::vector<int> out;
  if (planned(vehicle_point_, goal_point)) out.push_back(vehicle_point_);
  // Any two remaining goals need their pair (a mission point to another or to E).
  for (int p : remainingGoals())
    if (p != goal_point && hostOf(p, goal_point) == goal_point) out.push_back(p);
  return out;
}

MmdStarLite::PairSource MmdStarLite::pairSource(int from_point, int to_point) const {
  PairSource source;
  if (!planned(from_point, to_point)) return source;
  if (from_point == vehicle_point_ || hostOf(from_point, to_point) == to_point) {
    source.map = slot(to_point);
    source.start = startCell(from_point);
  } else {
    source.map = slot(from_point);
    source.start = points_[to_point];
    source.reversed = true;
  }
  return source;
}

PlannerStatus MmdStarLite::preplanGoal(GoalSlot& goal, SearchStats& stats, const TerminationCondition& stop) const {
  const std::vector<int> starts = mapStarts(goal.point);
  const std::uint64_t expansions_before = stats.expansions;
  // One U carried from start to start (lines 34-38).
  DStarQueue carried(startCell(starts.front()), 0.0);
  if (useSweep(starts.size())) {
    // Beyond the seed (setSweepMinCells): one Dijkstra sweep until every start is settled, which
    // leaves the same kind of state as lines 34-38 (see dstarSweepInitialize).
    std::vector<GridCell> cells;
    for (int start_point : starts) cells.push_back(startCell(start_point));
    if (const PlannerStatus s = dstarSweepInitialize(*goal.field, cells, carried, stats, stop); isStopped(s)) return s;
  } else {
    dstarInitialize(*goal.field, carried, stats);  // line 34
    for (int start_point : starts) {               // line 35
      carried.setStart(startCell(start_point));
      carried.setKm(0.0);
      carried.adapt(*goal.field, stats);  // line 37
      if (const PlannerStatus s = dstarComputeShortestPath(*goal.field, carried, stats, stop); isStopped(s)) return s;
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
  return PlannerStatus::kSolved;
}

PlannerStatus MmdStarLite::preplan(const TerminationCondition& stop) {
  goals_.clear();
  table_ = std::make_shared<GridMoveTable>(*grid_, moves_);
  for (int goal_point : remainingGoals()) {  // line 33
    if (mapStarts(goal_point).empty()) continue;
    GoalSlot goal;
    goal.point = goal_point;
    goals_.push_back(std::move(goal));
  }
  const PlannerStatus status = forEachGoal([&](GoalSlot& goal, SearchStats& stats) {
    // Made by the goal's thread: filling 16 bytes a cell is a good part of a large map's cost.
    goal.field = std::make_unique<DStarGoalField>(table_, points_[goal.point]);
    return preplanGoal(goal, stats, stop);
  });
  // After a stop, goals never started hold no map.
  std::erase_if(goals_, [](const GoalSlot& g) { return g.field == nullptr; });
  return status;
}

PlannerStatus MmdStarLite::replanGoal(GoalSlot& goal, std::span<const std::uint32_t> touched, SearchStats& stats,
                                     const TerminationCondition& stop) {
  if (goal.deferred) return PlannerStatus::kSolved;  // nothing to repair: its costs come from other maps
  // Split pairs: a map hosting no pair now (E's, between arrivals) is planned afresh when it is needed.
  if (goal.starts.empty()) return PlannerStatus::kSolved;
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
  dstarUpdateTouchedCells(*goal.field, touched, {}, stats);
  // The repair's own count, for the fresh-plan rule (setFreshPlanFraction): its iteration budget
  // stops the repair, the caller's `stop` is checked separately.
  SearchStats repair;
  const bool bounded = fresh_plan_fraction_ > 0.0;
  TerminationCondition budget = stop;
  if (bounded)
    budget.withIterationBudget(static_cast<std::uint64_t>(fresh_plan_fraction_ * static_cast<double>(goal.plan_expansions)) + 1);
  for (DStarQueue* q : queues) {  // lines 66-70
    dstarSyncQueue(*goal.field, *q, repair);  // line 69: load U with what the others inserted
    if (const PlannerStatus s = dstarComputeShortestPath(*goal.field, *q, repair, bounded ? budget : stop); isStopped(s)) {
      stats += repair;
      if (!bounded) return s;
      if (stop.shouldStop()) return stoppedStatus(stop.reason());
      if (defer_goal_maps_ && goal.point != endPoint()) {
        // Over budget: leave the map stale (setDeferGoalMaps); settleDeferred does the rest.
        ++deferred_goals_;
        goal.deferred = true;
        goal.starts.clear();
        return PlannerStatus::kSolved;
      }
      // Over budget: plan this goal from scratch on the current grid.
      ++fresh_plans_;
      goal.starts.clear();
      goal.field->reset();
      return preplanGoal(goal, stats, stop);
    }
  }
  stats += repair;
  return PlannerStatus::kSolved;
}

PlannerStatus MmdStarLite::applyChanges(std::span<const GridCell> changed, const TerminationCondition& stop) {
  if (changed.empty()) return PlannerStatus::kSolved;
  accumulateKm();  // lines 52-54
  // The shared move table follows the change here, once, before the goals' threads read it.
  if (table_) table_->update(changed);
  const std::vector<std::uint32_t> touched = dstarTouchedCells(*grid_, changed);
  const PlannerStatus status =
      forEachGoal([&](GoalSlot& goal, SearchStats& stats) { return replanGoal(goal, touched, stats, stop); });
  if (isStopped(status)) return status;
  return settleDeferred(stop);
}

PlannerStatus MmdStarLite::settleDeferred(const TerminationCondition& stop) {
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
    const PlannerStatus s = preplanGoal(goal, stats, stop);
    stats_ += stats;
    if (isStopped(s)) return s;
  }
  return PlannerStatus::kSolved;
}

SearchStats MmdStarLite::routeVehicle(const GoalSlot& goal) const {
  goal.route_stale = false;
  goal.vehicle_path.clear();
  goal.vehicle_cost = kInfiniteCost;
  if (!planned(vehicle_point_, goal.point)) return {};
  GridPath route = astarSearch(*grid_, vehicle_cell_, points_[goal.point], moves_);
  if (route.status == PlannerStatus::kSolved) {
    goal.vehicle_path = std::move(route.cells);
    goal.vehicle_cost = route.cost;
  }
  return route.stats;
}

double MmdStarLite::cost(int from_point, int to_point) const {
  if (!planned(from_point, to_point)) return kInfiniteCost;
  if (splitPairs()) {
    const PairSource source = pairSource(from_point, to_point);
    return source.map ? source.map->field->costFrom(source.start) : kInfiniteCost;
  }
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
  if (splitPairs()) {
    const PairSource source = pairSource(from_point, to_point);
    if (source.map == nullptr) return {};
    std::vector<GridCell> cells = source.map->field->pathFrom(source.start);
    if (source.reversed) std::reverse(cells.begin(), cells.end());
    return cells;
  }
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
  if (splitPairs()) {
    arriveSplit(old_vehicle);
    return;
  }
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

void MmdStarLite::arriveSplit(int old_vehicle) {
  const GridCell at = points_[vehicle_point_];
  for (GoalSlot& goal : goals_) {
    const auto has = [&](int p) {
      return std::any_of(goal.starts.begin(), goal.starts.end(), [&](const StartSlot& st) { return st.point == p; });
    };
    if (!has(vehicle_point_) && planned(vehicle_point_, goal.point)) {
      // The pair {reached point, goal} was the reached point's map's: this map needs a queue for the
      // new vehicle start. The old vehicle's is turned into it, else a copy of another start's
      // (every queue sharing the field holds every inconsistent cell once synchronised), re-keyed
      // for the new start with k_m = 0 (line 77) and searched to it now, so its cost is exact as
      // the reached point's own queue would have left it.
      auto old = std::find_if(goal.starts.begin(), goal.starts.end(), [&](const StartSlot& st) { return st.point == old_vehicle; });
      if (old == goal.starts.end() && !goal.starts.empty()) {
        goal.starts.push_back(goal.starts.front());
        old = goal.starts.end() - 1;
      }
      if (old != goal.starts.end()) {
        old->point = vehicle_point_;
        old->queue.setStart(at);
        old->queue.setKm(0.0);
        old->queue.adapt(*goal.field, stats_);
        dstarSyncQueue(*goal.field, old->queue, stats_);
        (void)dstarComputeShortestPath(*goal.field, old->queue, stats_, {});
      }
    }
    // Keep the vehicle's queue and those of the remaining goals this map hosts.
    std::erase_if(goal.starts, [&](const StartSlot& st) {
      return st.point != vehicle_point_ && (visited(st.point) || st.point == old_vehicle);
    });
    for (StartSlot& st : goal.starts)
      if (st.point == vehicle_point_) st.queue.setKm(0.0);
  }
  // A map left without any queue (E's, whose pairs were all hosted by the mission points' maps, once
  // the last of them is reached) is planned afresh for the vehicle; likewise a goal that had none.
  for (int goal_point : remainingGoals()) {
    GoalSlot* goal = slot(goal_point);
    if (goal != nullptr && !goal->starts.empty()) continue;
    if (mapStarts(goal_point).empty()) continue;
    if (goal == nullptr) {
      goals_.push_back(GoalSlot{});
      goal = &goals_.back();
      goal->point = goal_point;
      goal->field = std::make_unique<DStarGoalField>(table_, points_[goal_point]);
    } else {
      goal->field->reset();
    }
    (void)preplanGoal(*goal, stats_, {});
  }
}

}  // namespace skyroute
