#include "planning/mission/mission_planner.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <string>

#include "planning/core/enum_names.hpp"
#include "planning/mission/mmdstar_lite.hpp"
#include "planning/mission/pairwise_dstar_lite.hpp"

namespace skyroute {

namespace {

using Clock = std::chrono::steady_clock;

double msSince(Clock::time_point t0) { return std::chrono::duration<double, std::milli>(Clock::now() - t0).count(); }

std::string describeCell(GridCell c) { return "(" + std::to_string(c.x) + ", " + std::to_string(c.y) + ")"; }

std::string nameOf(int point, int point_count) {
  if (point == 0) return "begin";
  if (point == point_count - 1) return "end";
  return "points[" + std::to_string(point - 1) + "]";
}

}  // namespace

std::string_view to_string(MissionAlgorithm algorithm) {
  constexpr EnumName<MissionAlgorithm> kNames[] = {{MissionAlgorithm::kMmdStarLite, "mmdstar"},
                                                   {MissionAlgorithm::kDStarLite, "dstar-lite"}};
  return enumName(kNames, algorithm);
}

Status validateMission(const GridLayer& grid, GridCell begin, const std::vector<GridCell>& missions, GridCell end,
                       const GridMoves& moves) {
  std::vector<GridCell> all{begin};
  all.insert(all.end(), missions.begin(), missions.end());
  all.push_back(end);
  const int count = static_cast<int>(all.size());
  for (int p = 0; p < count; ++p) {
    const GridCell c = all[p];
    const std::string name = nameOf(p, count);
    if (!grid.inside(c))
      return make_error(ErrorCode::kOutsideMap, name,
                        name + " " + describeCell(c) + " is outside the " + std::to_string(grid.width()) + " x " +
                            std::to_string(grid.height()) + " grid");
    if (grid.blocked(c)) return make_error(ErrorCode::kOccupied, name, name + " " + describeCell(c) + " is inside an obstacle");
  }
  // Mission points must differ from each other and from begin and end; begin == end is a round trip.
  for (int p = 1; p < count; ++p) {
    for (int q = 0; q < p; ++q) {
      if (p == count - 1 && q == 0) continue;
      if (all[p] == all[q]) {
        const std::string name = nameOf(p, count);
        return make_error(ErrorCode::kInvalidArgument, name,
                          name + " " + describeCell(all[p]) + " duplicates " + nameOf(q, count));
      }
    }
  }
  const std::vector<std::uint8_t> reach = reachableCells(grid, begin, moves);
  for (int p = 1; p < count; ++p) {
    if (!reach[grid.index(all[p])]) {
      const std::string name = nameOf(p, count);
      return make_error(ErrorCode::kUnreachable, name, name + " " + describeCell(all[p]) + " cannot be reached from begin");
    }
  }
  return Status::success();
}

Result<MissionPlanner> MissionPlanner::create(const GridLayer& grid, GridCell begin, std::vector<GridCell> missions,
                                              GridCell end, const MissionOptions& options) {
  if (!(options.moves.diagonal_cost >= 1.0) || !std::isfinite(options.moves.diagonal_cost))
    return make_error(ErrorCode::kInvalidArgument, "diagonal_cost", "diagonal_cost must be finite and >= 1");
  if (Status s = validateMission(grid, begin, missions, end, options.moves); !s) return s.error();
  std::vector<GridCell> points{begin};
  points.insert(points.end(), missions.begin(), missions.end());
  points.push_back(end);
  std::unique_ptr<MissionSearch> search;
  if (options.algorithm == MissionAlgorithm::kMmdStarLite)
  {
    auto mmd = std::make_unique<MmdStarLite>(grid, std::move(points), options.moves, options.threads);
    mmd->setFreshPlanFraction(options.fresh_plan_fraction);
    mmd->setSweepMinCells(options.sweep_min_cells);
    mmd->setDeferGoalMaps(options.defer_goal_maps);
    mmd->setSymmetricPairs(options.symmetric_pairs);
    search = std::move(mmd);
  }
  else
    search = std::make_unique<PairwiseDStarLite>(grid, std::move(points), options.moves);
  return MissionPlanner(std::move(search), options);
}

std::string MissionPlanner::pointName(int point) const { return nameOf(point, search_->pointCount()); }

Result<MissionOrderPlan> MissionPlanner::preplan(const TerminationCondition& stop) {
  const SearchStats before = search_->stats();
  const auto t0 = Clock::now();
  const PlannerStatus status = search_->preplan(stop);
  return finishPlan(status, stop, before, msSince(t0));
}

Result<MissionOrderPlan> MissionPlanner::replan(std::span<const GridCell> changed, const TerminationCondition& stop) {
  const SearchStats before = search_->stats();
  const auto t0 = Clock::now();
  const PlannerStatus status = search_->applyChanges(changed, stop);
  return finishPlan(status, stop, before, msSince(t0));
}

Result<MissionOrderPlan> MissionPlanner::finishPlan(PlannerStatus status, const TerminationCondition& stop,
                                               const SearchStats& before, double search_ms) {
  if (isStopped(status)) {
    const bool cancelled = stop.reason() == TerminationCondition::Reason::kCancelled;
    return make_error(cancelled ? ErrorCode::kCancelled : ErrorCode::kTimeout, "mission",
                      cancelled ? "mission planning was cancelled" : "mission planning ran out of time");
  }
  const auto t0 = Clock::now();
  MissionOrderPlan plan;
  const int count = search_->pointCount();
  plan.cost_matrix.assign(count, std::vector<double>(count, kInfiniteCost));
  for (int from = 0; from < count; ++from)
    for (int to = 0; to < count; ++to)
      if (search_->planned(from, to)) plan.cost_matrix[from][to] = search_->cost(from, to);

  // Open TSP over the vehicle's point, the remaining mission points and E.
  std::vector<int> nodes{search_->vehiclePoint()};
  for (int p : search_->remainingMissions()) nodes.push_back(p);
  nodes.push_back(search_->endPoint());
  for (std::size_t k = 1; k < nodes.size(); ++k) {
    if (search_->planned(nodes[0], nodes[k]) && !(plan.cost_matrix[nodes[0]][nodes[k]] < kInfiniteCost)) {
      const std::string name = pointName(nodes[k]);
      return make_error(ErrorCode::kUnreachable, name,
                        name + " " + describeCell(search_->points()[nodes[k]]) + " cannot be reached from " +
                            (nodes[0] == 0 && search_->vehicleCell() == search_->points()[0]
                                 ? std::string("begin")
                                 : "the vehicle at " + describeCell(search_->vehicleCell())));
    }
  }
  std::vector<std::vector<double>> sub(nodes.size(), std::vector<double>(nodes.size(), kInfiniteCost));
  for (std::size_t i = 0; i < nodes.size(); ++i)
    for (std::size_t j = 0; j < nodes.size(); ++j)
      if (i != j) sub[i][j] = plan.cost_matrix[nodes[i]][nodes[j]];
  const auto tsp_t0 = Clock::now();
  Result<OpenTspResult> tsp = solveOpenTsp(sub, options_.tsp);
  plan.tsp_time_ms = msSince(tsp_t0);
  if (!tsp.ok()) {
    Error e = tsp.error();
    e.field = "mission";
    return e;
  }
  plan.tsp = *tsp;
  for (int node : tsp->order) plan.order.push_back(nodes[static_cast<std::size_t>(node)]);
  plan.tsp.order = plan.order;
  for (std::size_t k = 1; k < plan.order.size(); ++k) {
    MissionLeg leg;
    leg.from_point = plan.order[k - 1];
    leg.to_point = plan.order[k];
    leg.cost = plan.cost_matrix[leg.from_point][leg.to_point];
    leg.cells = search_->path(leg.from_point, leg.to_point);
    plan.cost += leg.cost;
    plan.legs.push_back(std::move(leg));
  }
  const SearchStats& after = search_->stats();
  plan.search.expansions = after.expansions - before.expansions;
  plan.search.queue_pushes = after.queue_pushes - before.queue_pushes;
  plan.search.queue_pops = after.queue_pops - before.queue_pops;
  plan.search.time_ms = search_ms;
  plan.total_time_ms = search_ms + msSince(t0);
  plan_ = plan;
  return plan;
}

GridCell MissionPlanner::nextCell() const {
  if (finished_ || plan_.order.size() < 2) return search_->vehicleCell();
  return search_->nextCell(plan_.order[1]);
}

void MissionPlanner::moveVehicle(GridCell cell) {
  search_->moveVehicle(cell);
  if (plan_.order.size() < 2) return;
  const int target = plan_.order[1];
  if (!(search_->points()[target] == cell)) return;
  if (target == search_->endPoint()) {
    finished_ = true;
    return;
  }
  search_->arriveAt(target);
  // The order stays valid: drop the reached point from its front.
  plan_.order.erase(plan_.order.begin());
  if (!plan_.legs.empty()) plan_.legs.erase(plan_.legs.begin());
}

void MissionPlanner::arriveAt(int point) {
  if (point < 1 || point > search_->missionCount() || search_->visited(point)) return;
  search_->arriveAt(point);
  // The order in hand stays an order of what is left, from the reached point; its legs no longer
  // start where the vehicle is, so they go (the next replan makes new ones).
  std::erase(plan_.order, point);
  if (!plan_.order.empty()) plan_.order.front() = point;
  plan_.legs.clear();
}

}  // namespace skyroute
