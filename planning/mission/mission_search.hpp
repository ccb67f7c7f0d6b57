// The searches behind a multi-point mission (seed section III): the path costs between the begin
// point B, the mission points M1..Mn and the end E, kept up to date while the vehicle flies and the
// grid changes. Two implementations: MmdStarLite (one g/rhs map per goal shared by its starts,
// n+1 maps) and PairwiseDStarLite (one D* Lite per start/goal pair, n^2+n maps), the baseline.
//
// Points are numbered 0 = B, 1..n = mission points, n+1 = E. The vehicle starts at B; after it
// arrives at a mission point that point becomes its start ("vehicle point") and stops being a goal.
// A pair (start, goal) is planned when start != goal, start is the vehicle point or a remaining
// mission point, goal is a remaining mission point or E, and not (start is the vehicle point, goal
// is E and mission points remain): those are exactly the entries an open TSP from the vehicle
// through the remaining points to E can use (Fig. 4 of the seed).
#pragma once

#include <span>
#include <string_view>
#include <vector>

#include "planning/core/termination.hpp"
#include "planning/grid/grid_search.hpp"
#include "terrain/grid_layer.hpp"

namespace skyroute {

class MissionSearch {
 public:
  MissionSearch(const GridLayer& grid, std::vector<GridCell> points, const GridMoves& moves);
  virtual ~MissionSearch() = default;
  MissionSearch(const MissionSearch&) = delete;
  MissionSearch& operator=(const MissionSearch&) = delete;

  virtual std::string_view name() const = 0;
  // Plans every pair (seed lines 33-42 for MMD*L). A stopped status (isStopped) when the termination fired.
  virtual PlannerStatus preplan(const TerminationCondition& stop = {}) = 0;
  // The grid's blocked state of `changed` flipped (the grid already shows it): repair every
  // remaining pair incrementally (lines 51-71).
  virtual PlannerStatus applyChanges(std::span<const GridCell> changed, const TerminationCondition& stop = {}) = 0;
  // Cost of a planned pair (from the vehicle's current cell when from == vehiclePoint());
  // infinity when the pair is not planned or not connected.
  virtual double cost(int from_point, int to_point) const = 0;
  virtual std::vector<GridCell> path(int from_point, int to_point) const = 0;
  // The vehicle's next cell towards goal_point (line 49).
  virtual GridCell nextCell(int goal_point) const = 0;
  // Number of g/rhs maps currently held (memory, seed 3.5.2).
  virtual std::size_t costMapCount() const = 0;
  // The threads the next planning steps may use, the caller's included (MMD*L's goals are
  // independent maps); searches that cannot split ignore it. Results do not depend on it.
  virtual void setThreads(int threads) { (void)threads; }

  // The vehicle moved (to a neighbouring cell, usually).
  virtual void moveVehicle(GridCell cell);
  // The vehicle is at mission point `point` (1..n): it becomes the vehicle point.
  virtual void arriveAt(int point);

  int pointCount() const { return static_cast<int>(points_.size()); }
  int missionCount() const { return pointCount() - 2; }
  int endPoint() const { return pointCount() - 1; }
  const std::vector<GridCell>& points() const { return points_; }
  int vehiclePoint() const { return vehicle_point_; }
  GridCell vehicleCell() const { return vehicle_cell_; }
  bool visited(int point) const { return visited_[static_cast<std::size_t>(point)] != 0; }
  std::vector<int> remainingMissions() const;
  std::vector<int> remainingGoals() const;                // remaining mission points, then E
  std::vector<int> startsFor(int goal_point) const;       // vehicle point first, then missions
  bool planned(int from_point, int to_point) const;
  const SearchStats& stats() const { return stats_; }
  void resetStats() { stats_ = SearchStats{}; }
  const GridMoves& moves() const { return moves_; }
  const GridLayer& grid() const { return *grid_; }

 protected:
  GridCell startCell(int point) const { return point == vehicle_point_ ? vehicle_cell_ : points_[point]; }
  // k_m bookkeeping of the vehicle's start (line 52): call when edge costs changed.
  void accumulateKm();

  const GridLayer* grid_;
  std::vector<GridCell> points_;
  GridMoves moves_;
  std::vector<std::uint8_t> visited_;
  int vehicle_point_ = 0;
  GridCell vehicle_cell_;
  GridCell last_cell_;  // s_last of the seed
  double km_ = 0.0;     // the vehicle's k_m
  SearchStats stats_;
};

}  // namespace skyroute
