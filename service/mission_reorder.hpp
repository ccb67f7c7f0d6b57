// Live re-ordering of a flying mission's points (seed 000, replanning with MMD*L): the grid and the
// n+1 D* Lite searches that chose the order stay with the mission. When the obstacles change, the
// cells they cover on that grid are flipped, the searches repair their maps incrementally (lines
// 51-71 of the seed: only the cells whose cost changed are expanded), and the open TSP over the
// points still to visit is solved again from where the vehicle will be. Points already reached
// are visited in the searches, so they are never goals, nor in an order, again.
//
// An obstacle's cover: the cells within its horizontal half extent plus the vehicle radius of the
// stretch of track its centre covers from now to now + sweep_s (one segment: obstacles move on a
// line), taken whole (a cell is covered when its centre is within that distance plus half its
// diagonal, so a cell touched anywhere counts). A moving obstacle is planned around where it will
// be during the next sweep_s, which is also what the flight's replans block (ReplanOptions::
// window_s); its cover is computed when the obstacles change, not every cycle, so an obstacle
// that nobody updates does not cost a repair per cycle. Obstacles whose bottom is above the
// grid's flight band cover nothing. The points' own cells are never covered (the grid keeps them
// free of no-fly zones the same way): a point an obstacle surrounds is cut off (one sweep of the
// grid from the vehicle tells), the order stays, and the searches are repaired only once every
// point is reachable again (a repair towards a cut-off point would search the whole grid).
//
// No-fly zones published after the order was chosen cover their footprint the same way while
// they are in force within the sweep (the zones the grid was built with are blocked in it).
//
// The TSP is solved with the exact solver up to kExactPoints remaining points (the heuristic
// above), and a new order is proposed only when it is shorter than the order being flown by at
// least min_gain_cells on the new costs: orders of equal cost are not swapped back and forth.
#pragma once

#include <cstdint>
#include <memory>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "planning/core/result.hpp"
#include "planning/core/termination.hpp"
#include "service/mission_order.hpp"
#include "terrain/obstacle.hpp"

namespace skyroute {

struct MissionReorderOptions {
  bool enabled = true;           // re-order flying missions whose order MMD*L chose
  double sweep_s = 15.0;         // an obstacle covers the cells its track crosses this long ahead
  double min_gain_cells = 1.0;   // a new order must save at least this much (cell edges)
  // Threads of one repair, the replanning loop's included: the goals' maps are repaired apart
  // (same results), so a repair that changes many maps takes about half the time on two free
  // cores. 1 = the replanning loop's thread alone.
  int repair_threads = 2;
};

// What one look at the changed obstacles found. Point indices are the mission's (0 = begin,
// 1..N = points, N+1 = end).
struct ReorderCheck {
  bool repaired = false;             // cells flipped: the searches were repaired, the TSP solved
                                     // (not while a point is cut off: failure says which)
  std::size_t changed_cells = 0;     // cells whose blocked state flipped
  std::size_t covered_cells = 0;     // cells the obstacles cover now
  SearchStats search;                // the repair (cell expansions, queue operations, time)
  double time_ms = 0.0;              // cover, repair and TSP together
  double tsp_time_ms = 0.0;          // of which the TSP
  std::vector<int> old_order;        // the vehicle's point (the last reached) first, then the points left as flown
  std::vector<int> new_order;        // the same as the TSP orders them now (empty unless repaired)
  double old_cost_m = 0.0;           // both on the new costs (infinity when cut off)
  double new_cost_m = 0.0;
  std::optional<Error> failure;      // no order on the new costs (a point cut off): the order stays
  bool reordered() const { return repaired && !failure && new_order != old_order; }
};

class MissionReorder {
 public:
  static constexpr int kExactPoints = 12;  // Held-Karp up to this many points left: 2^12 * 12^2 steps

  // From the order stage's searches; null when there are none (a fixed or Euclidean order).
  // vehicle_radius_m grows every obstacle's cover.
  static std::unique_ptr<MissionReorder> create(std::shared_ptr<MissionOrderSearch> search,
                                                const MissionReorderOptions& options, double vehicle_radius_m);

  // The obstacles in force at world time now_s. reached: the points the vehicle has passed (in
  // the order passed; the last is where its route now starts from), vehicle_m where it will be
  // when a new route takes over, remaining: the points still to visit in the order being flown
  // (the end last). When the cover changed, repairs the searches and solves the TSP again.
  ReorderCheck check(std::span<const Obstacle> obstacles, double now_s, std::span<const int> reached,
                     const Eigen::Vector3d& vehicle_m, std::span<const int> remaining,
                     const TerminationCondition& stop = {}) {
    return check(obstacles, {}, now_s, reached, vehicle_m, remaining, stop);
  }
  // The same with the no-fly zones in force too: a zone the grid was not built with covers its
  // footprint (zoneCover) while it is in force during the sweep, and a lifted one uncovers it.
  ReorderCheck check(std::span<const Obstacle> obstacles, std::span<const NoFlyZone> zones, double now_s,
                     std::span<const int> reached, const Eigen::Vector3d& vehicle_m, std::span<const int> remaining,
                     const TerminationCondition& stop = {});

  // The cells the obstacles covered at the last check (sorted grid indices), for tests.
  const std::vector<std::uint32_t>& covered() const { return covered_; }
  const MissionPlanner& planner() const { return *search_->planner; }
  const GridLayer& grid() const { return *search_->grid; }
  const MissionOrderSearch& search() const { return *search_; }
  // Sorted grid indices of the cells `obstacles` cover at now_s on `grid` (see the file comment).
  static std::vector<std::uint32_t> coverOf(const GridLayer& grid, std::span<const Obstacle> obstacles, double now_s,
                                            double sweep_s, double vehicle_radius_m, double flight_ceiling_m,
                                            std::span<const GridCell> free_cells);
  // Sorted grid indices of the cells the zones cover on the search's grid at now_s: the footprint
  // (grown by the zone margin) of every zone in force at some time of [now_s, now_s + sweep_s]
  // that reaches into the flight band and that the grid was not built with, the points' cells
  // excepted (they are kept free, as the grid keeps them).
  static std::vector<std::uint32_t> zoneCover(const MissionOrderSearch& search, std::span<const NoFlyZone> zones,
                                              double now_s, double sweep_s);

 private:
  MissionReorder(std::shared_ptr<MissionOrderSearch> search, const MissionReorderOptions& options, double vehicle_radius_m);
  // The vehicle's cell, or the nearest passable one within two cells (the cover may reach it).
  std::optional<GridCell> vehicleCell(const Eigen::Vector3d& vehicle_m) const;

  std::shared_ptr<MissionOrderSearch> search_;
  MissionReorderOptions options_;
  double vehicle_radius_m_ = 0.0;
  std::vector<std::uint32_t> covered_;
  std::vector<GridCell> pending_;  // flipped cells the searches have not seen (a point was cut off)
};

// "0,2,1,3" for logs and statuses.
std::string orderText(std::span<const int> order);

}  // namespace skyroute
