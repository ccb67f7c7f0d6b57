#include "service/mission_order.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <numeric>

#include "planning/mission/mission_planner.hpp"
#include "planning/mission/open_tsp.hpp"
#include "terrain/grid_from_terrain.hpp"
#include "terrain/grid_layer.hpp"

namespace skyroute {
namespace {

double elapsedMs(std::chrono::steady_clock::time_point since) {
  return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - since).count();
}

Result<MissionOrder> euclideanOrder(const std::vector<Eigen::Vector3d>& points_m, std::string reason) {
  const std::size_t n = points_m.size();
  std::vector<std::vector<double>> cost(n, std::vector<double>(n, 0.0));
  for (std::size_t i = 0; i < n; ++i)
    for (std::size_t j = 0; j < n; ++j) cost[i][j] = (points_m[i] - points_m[j]).norm();
  auto tsp = solveOpenTsp(cost);
  if (!tsp.ok()) return tsp.error();
  MissionOrder out;
  out.order = tsp->order;
  out.method = "euclidean";
  out.fallback_reason = std::move(reason);
  out.cost_m = tsp->cost;
  out.cost_matrix_m = std::move(cost);
  return out;
}

}  // namespace

MissionOrderSearch::MissionOrderSearch() = default;
MissionOrderSearch::~MissionOrderSearch() = default;

Result<MissionOrder> orderMissionPoints(const Heightfield& terrain, const std::vector<Eigen::Vector3d>& points_m,
                                        double min_clearance_m, double ceiling_m, bool fixed,
                                        const MissionOrderOptions& options, const TerminationCondition& stop,
                                        const std::vector<NoFlyZone>& no_fly_zones, double zone_margin_m) {
  const auto started = std::chrono::steady_clock::now();
  if (points_m.size() < 2) return make_error(ErrorCode::kInvalidArgument, "points", "a mission needs a begin and an end");
  MissionOrder out;
  // With at most one mission point there is nothing to choose.
  if (fixed || points_m.size() <= 3) {
    out.order.resize(points_m.size());
    std::iota(out.order.begin(), out.order.end(), 0);
    out.method = "fixed";
    for (std::size_t i = 1; i < points_m.size(); ++i) out.cost_m += (points_m[i] - points_m[i - 1]).norm();
    out.time_ms = elapsedMs(started);
    return out;
  }

  const Eigen::AlignedBox2d& box = terrain.boundsEn();
  const double dem_cell_m = terrain.dem().resolutionM().minCoeff();
  TerrainGridOptions grid_options;
  grid_options.cell_size_m =
      std::max(dem_cell_m, 1.0001 * box.sizes().maxCoeff() / std::max(1, options.max_cells_per_axis));
  double highest_m = -1e300;
  for (const Eigen::Vector3d& p : points_m) highest_m = std::max(highest_m, p.z());
  grid_options.flight_ceiling_m = std::min(ceiling_m, highest_m + options.band_margin_m);
  grid_options.min_clearance_m = min_clearance_m;
  grid_options.no_fly_zones = no_fly_zones;
  grid_options.zone_margin_m = zone_margin_m;
  for (const Eigen::Vector3d& p : points_m) grid_options.keep_free_m.push_back(p.head<2>());
  auto finish = [&](Result<MissionOrder> r) {
    if (r.ok()) r->time_ms = elapsedMs(started);
    return r;
  };
  grid_options.cancel = stop.cancelFlag();  // a large DEM's grid takes a while: stay cancellable
  auto grid = buildTerrainGrid(terrain, grid_options);
  if (!grid.ok() && grid.error().code == ErrorCode::kCancelled) return grid.error();
  if (!grid.ok()) return finish(euclideanOrder(points_m, "order grid: " + grid.error().describe()));

  std::vector<GridCell> cells;
  for (std::size_t i = 0; i < points_m.size(); ++i) {
    auto cell = grid->cellAt(points_m[i].head<2>());
    if (!cell) return finish(euclideanOrder(points_m, "point " + std::to_string(i) + " is off the order grid"));
    cells.push_back(*cell);
  }
  const std::vector<GridCell> missions(cells.begin() + 1, cells.end() - 1);
  MissionOptions mission_options;
  mission_options.moves = options.moves;
  mission_options.fresh_plan_fraction = options.fresh_plan_fraction;
  mission_options.defer_goal_maps = options.defer_goal_maps;
  mission_options.symmetric_pairs = options.symmetric_pairs;
  auto search = std::make_shared<MissionOrderSearch>();
  search->grid = std::make_unique<GridLayer>(std::move(*grid));
  search->cells = cells;
  search->flight_ceiling_m = grid_options.flight_ceiling_m;
  search->band_floor_m = terrain.minHeightM() + min_clearance_m;
  search->zones = no_fly_zones;
  search->zone_margin_m = zone_margin_m;
  auto planner = MissionPlanner::create(*search->grid, cells.front(), missions, cells.back(), mission_options);
  if (!planner.ok()) return finish(euclideanOrder(points_m, "order grid: " + planner.error().describe()));
  auto plan = planner->preplan(stop);
  if (!plan.ok()) {
    if (plan.error().code == ErrorCode::kTimeout || plan.error().code == ErrorCode::kCancelled) return plan.error();
    return finish(euclideanOrder(points_m, "order grid: " + plan.error().describe()));
  }
  out.order = plan->order;
  out.method = "mmdstar";
  const double cell_size_m = search->grid->cellSize();
  out.cost_m = plan->cost * cell_size_m;
  out.cell_size_m = cell_size_m;
  out.expansions = plan->search.expansions;
  out.cost_matrix_m = plan->cost_matrix;
  for (auto& row : out.cost_matrix_m)
    for (double& cost : row) cost *= cell_size_m;  // infinity stays infinity
  search->planner = std::make_unique<MissionPlanner>(std::move(*planner));
  out.search = std::move(search);
  out.time_ms = elapsedMs(started);
  return out;
}

}  // namespace skyroute
