// The visiting order of a mission's points (seed 000): MMD*L path costs on the terrain's flight
// band grid and an open TSP from the begin point to the end point. When the grid cannot carry the
// mission (two points in one cell, a point in a blocked cell, the band cut), the order falls back
// to straight-line distances, and says why; the 3D leg planner decides feasibility afterwards.
#pragma once

#include <memory>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "planning/core/result.hpp"
#include "planning/core/termination.hpp"
#include "planning/grid/grid_search.hpp"
#include "terrain/heightfield.hpp"
#include "terrain/no_fly_zone.hpp"

namespace skyroute {

struct MissionOrderOptions {
  int max_cells_per_axis = 200;   // the order grid's cell edge is the terrain extent / this, at
                                  // least the DEM cell: MMD*L stays well under a second
  double band_margin_m = 300.0;   // the flight band reaches this far above the highest point
  GridMoves moves;                // sqrt(2) diagonals, octile heuristic, no corner cutting
  // Repairs of the searches kept for live re-ordering (mission_reorder.hpp), bounded as
  // MissionOptions does (the first order does not depend on them): a goal's repair that costs more
  // than this share of planning it from scratch is given up, and the goal deferred (its costs
  // taken from the other points' maps) or planned afresh. Off (the seed's repair): at mission
  // scale on the embedded terrain 0.25 with deferral measured the same as the seed's repair, and
  // 0.05 worse (docs/benchmarks.md, bench/mission_reorder_bench --fresh --defer).
  double fresh_plan_fraction = 0.0;
  bool defer_goal_maps = false;
  // Each pair of points searched in one of its two maps (MmdStarLite::setSymmetricPairs): exact,
  // and a quarter less repair work at mission scale, a third less at the largest update
  // (docs/benchmarks.md, bench/mission_reorder_bench --symmetric).
  bool symmetric_pairs = true;
};

// The grid and the MMD*L searches an order was chosen with, kept so a flying mission can be
// re-ordered when obstacles change (mission_reorder.hpp) by repairing them instead of planning
// afresh. (MissionPlanner is only declared here: its plan type shares a name with the pipeline's.)
class MissionPlanner;
struct MissionOrderSearch {
  MissionOrderSearch();
  ~MissionOrderSearch();

  std::unique_ptr<GridLayer> grid;   // on the heap: the searches keep its address
  std::vector<GridCell> cells;       // each point's cell, in the points' numbering
  double flight_ceiling_m = 0.0;     // top of the grid's flight band
  double band_floor_m = 0.0;         // the lowest ground plus the clearance: no flight below
  std::vector<NoFlyZone> zones;      // the no-fly zones the grid was built with (blocked for good)
  double zone_margin_m = 0.0;        // each zone's polygon grown by this
  std::unique_ptr<MissionPlanner> planner;  // preplanned on `grid`
};

struct MissionOrder {
  std::vector<int> order;         // indices into the points: 0 first, the last point last
  std::string method;             // "fixed", "mmdstar" or "euclidean"
  std::string fallback_reason;    // why MMD*L was not used ("" when it was, or fixed)
  double cost_m = 0.0;            // the order's cost by the method's metric
  double cell_size_m = 0.0;       // of the order grid (mmdstar)
  std::uint64_t expansions = 0;   // MMD*L cell expansions
  double time_ms = 0.0;
  // cost_matrix_m[from][to] in metres over all points, the costs the order was chosen from: MMD*L
  // path costs (infinity where MMD*L plans no path: into the begin point, out of the end point, a
  // point to itself) or straight-line distances (euclidean). Empty for a fixed order, which
  // compares nothing.
  std::vector<std::vector<double>> cost_matrix_m;
  // mmdstar: the searches behind the order, for live re-ordering (null otherwise).
  std::shared_ptr<MissionOrderSearch> search;
};

// points_m: begin, mission points, end (ENU metres). fixed keeps the given order. The order grid
// blocks the no-fly zones grown by zone_margin_m (terrain/grid_from_terrain.hpp).
// Errors: kTimeout / kCancelled from `stop`; kInvalidArgument for fewer than two points.
Result<MissionOrder> orderMissionPoints(const Heightfield& terrain, const std::vector<Eigen::Vector3d>& points_m,
                                        double min_clearance_m, double ceiling_m, bool fixed,
                                        const MissionOrderOptions& options = {},
                                        const TerminationCondition& stop = {},
                                        const std::vector<NoFlyZone>& no_fly_zones = {}, double zone_margin_m = 0.0);

}  // namespace skyroute
