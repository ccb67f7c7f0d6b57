// A multi-point mission on a GridLayer (seed section III): validate the points, plan the path-cost
// matrix between B, M1..Mn and E with MMD*L (or per-pair D* Lite), solve the open TSP for the
// visiting order, and extract every leg's path. While the vehicle flies the planner follows it and,
// when cells change, repairs the matrix incrementally and re-solves the order (which may change).
#pragma once

#include <memory>
#include <span>
#include <string_view>
#include <vector>

#include "planning/core/result.hpp"
#include "planning/core/termination.hpp"
#include "planning/grid/grid_search.hpp"
#include "planning/mission/mission_search.hpp"
#include "planning/mission/open_tsp.hpp"
#include "terrain/grid_layer.hpp"

namespace skyroute {

enum class MissionAlgorithm { kMmdStarLite, kDStarLite };
std::string_view to_string(MissionAlgorithm algorithm);

struct MissionOptions {
  GridMoves moves;
  MissionAlgorithm algorithm = MissionAlgorithm::kMmdStarLite;
  OpenTspOptions tsp;
  // MMD*L plans its goals (independent maps) on this many threads, the caller's included. 1 keeps
  // all work on the caller's thread (the engine already plans requests on its own workers).
  int threads = 1;
  // MMD*L only, a deviation from the seed (MmdStarLite::setFreshPlanFraction): 0 repairs every map
  // incrementally however large the repair; f > 0 plans a goal afresh once its repair has cost
  // more than f times that goal's planning from scratch.
  double fresh_plan_fraction = 0.0;
  // MMD*L only, a deviation from the seed (MmdStarLite::setSweepMinCells): on grids of at least
  // this many cells a goal with many starts is planned from scratch by one Dijkstra bucket sweep
  // instead of the seed's D* Lite searches (same maps, cheaper); 0 = always the seed's search.
  std::size_t sweep_min_cells = 0;
  // MMD*L only, a deviation from the seed, with fresh_plan_fraction > 0 (MmdStarLite::
  // setDeferGoalMaps): a mission point's map whose repair outgrows the budget is left stale and
  // its costs taken from the other mission points' maps (moves are symmetric) instead of being
  // planned afresh.
  bool defer_goal_maps = false;
  // MMD*L only, a deviation from the seed (MmdStarLite::setSymmetricPairs): each pair of goals is
  // searched in one of its two maps (moves are symmetric), so a map serves about half the starts.
  bool symmetric_pairs = false;
};

struct MissionLeg {
  int from_point = 0;  // 0 = B, 1..n = mission points, n+1 = E
  int to_point = 0;
  double cost = 0.0;   // cell edges
  std::vector<GridCell> cells;
};

struct MissionOrderPlan {
  std::vector<int> order;  // the vehicle's point first (B before take-off), E last
  double cost = 0.0;       // sum of the legs, cell edges
  // cost_matrix[from][to] over all n+2 points; infinity where the pair is not planned.
  std::vector<std::vector<double>> cost_matrix;
  std::vector<MissionLeg> legs;
  OpenTspResult tsp;
  SearchStats search;      // the searches of this planning step
  double tsp_time_ms = 0.0;
  double total_time_ms = 0.0;
};

// Checks cheap things before any search, each error naming the point ("begin", "points[i]",
// "end"): kOutsideMap, kOccupied (blocked cell), kInvalidArgument (a point repeats another),
// kUnreachable (not connected to begin).
Status validateMission(const GridLayer& grid, GridCell begin, const std::vector<GridCell>& missions, GridCell end,
                       const GridMoves& moves = {});

class MissionPlanner {
 public:
  // The grid is the caller's, who changes it and reports the changed cells to replan().
  static Result<MissionPlanner> create(const GridLayer& grid, GridCell begin, std::vector<GridCell> missions,
                                       GridCell end, const MissionOptions& options = {});

  // Lines 33-43: every pair, then the order. kTimeout / kCancelled when `stop` fired.
  Result<MissionOrderPlan> preplan(const TerminationCondition& stop = {});
  // Lines 51-72: the cells in `changed` flipped; repair, re-solve the order from the vehicle.
  // kUnreachable naming a point that the change cut off.
  Result<MissionOrderPlan> replan(std::span<const GridCell> changed, const TerminationCondition& stop = {});

  // The next cell towards the first point of the current order (line 49).
  GridCell nextCell() const;
  // The vehicle moved to `cell`; reaching the next point of the order marks it visited (line 73).
  void moveVehicle(GridCell cell);
  // For a caller that tracks the flight itself (the daemon's live re-ordering): the vehicle is at
  // `cell` (where it will be when a new route takes over) without reaching any point there, and
  // it reached remaining mission point `point` (1..n) whatever the order's next point was. A
  // reached point becomes the vehicle's point and is never a goal again (lines 73-77); a point
  // that is not a remaining mission point is ignored.
  void placeVehicle(GridCell cell) { search_->moveVehicle(cell); }
  void arriveAt(int point);
  // The open TSP's settings for the next planning steps (e.g. a smaller exact limit where a
  // replan must stay within a cycle).
  void setTspOptions(const OpenTspOptions& tsp) { options_.tsp = tsp; }
  // Threads of the next planning steps (MissionOptions::threads), e.g. more for the repairs of a
  // live re-ordering than for the first plan on a planning worker.
  void setThreads(int threads) {
    options_.threads = threads;
    search_->setThreads(threads);
  }
  bool finished() const { return finished_; }
  GridCell vehicleCell() const { return search_->vehicleCell(); }
  const MissionOrderPlan& plan() const { return plan_; }
  const MissionSearch& search() const { return *search_; }

 private:
  MissionPlanner(std::unique_ptr<MissionSearch> search, const MissionOptions& options)
      : search_(std::move(search)), options_(options) {}
  Result<MissionOrderPlan> finishPlan(PlannerStatus status, const TerminationCondition& stop, const SearchStats& before,
                                 double search_ms);
  std::string pointName(int point) const;

  std::unique_ptr<MissionSearch> search_;
  MissionOptions options_;
  MissionOrderPlan plan_;
  bool finished_ = false;
};

}  // namespace skyroute
