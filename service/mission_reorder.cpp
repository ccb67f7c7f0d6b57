#include "service/mission_reorder.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <iterator>

#include "planning/mission/mission_planner.hpp"
#include "terrain/grid_from_terrain.hpp"

namespace skyroute {
namespace {

double msSince(std::chrono::steady_clock::time_point t) {
  return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t).count();
}

// Radius of the vertical column round an obstacle's shape (the shapes are axis-aligned), and the
// half height of the shape.
double horizontalRadius(const Obstacle& o) {
  switch (o.shape) {
    case ObstacleShape::kSphere: return o.size_m.x();
    case ObstacleShape::kEllipsoid: return std::max(o.size_m.x(), o.size_m.y());
    case ObstacleShape::kBox: return std::hypot(o.size_m.x(), o.size_m.y());
    case ObstacleShape::kCylinder: return o.size_m.x();
  }
  return o.boundingRadius();
}

double halfHeight(const Obstacle& o) {
  return o.shape == ObstacleShape::kSphere ? o.size_m.x() : o.size_m.z();
}

double distanceToSegment(const Eigen::Vector2d& p, const Eigen::Vector2d& a, const Eigen::Vector2d& b) {
  const Eigen::Vector2d ab = b - a;
  const double length2 = ab.squaredNorm();
  const double t = length2 > 0.0 ? std::clamp((p - a).dot(ab) / length2, 0.0, 1.0) : 0.0;
  return (p - (a + t * ab)).norm();
}

// The same zone as published (a zone replaced under its name with a new shape is another).
bool sameZone(const NoFlyZone& a, const NoFlyZone& b) {
  return a.name == b.name && a.ring_m == b.ring_m && a.floor_m == b.floor_m && a.ceiling_m == b.ceiling_m &&
         a.valid_from_s == b.valid_from_s && a.valid_until_s == b.valid_until_s;
}

std::vector<GridCell> cellsOf(const GridLayer& grid, std::span<const std::uint32_t> indices) {
  std::vector<GridCell> cells;
  cells.reserve(indices.size());
  for (std::uint32_t i : indices) cells.push_back(grid.cellOf(i));
  return cells;
}

}  // namespace

std::string orderText(std::span<const int> order) {
  std::string out;
  for (int p : order) out += (out.empty() ? "" : ",") + std::to_string(p);
  return out;
}

std::unique_ptr<MissionReorder> MissionReorder::create(std::shared_ptr<MissionOrderSearch> search,
                                                       const MissionReorderOptions& options, double vehicle_radius_m) {
  if (!options.enabled || !search || !search->grid || !search->planner) return nullptr;
  return std::unique_ptr<MissionReorder>(new MissionReorder(std::move(search), options, vehicle_radius_m));
}

MissionReorder::MissionReorder(std::shared_ptr<MissionOrderSearch> search, const MissionReorderOptions& options,
                               double vehicle_radius_m)
    : search_(std::move(search)), options_(options), vehicle_radius_m_(vehicle_radius_m) {
  OpenTspOptions tsp;
  tsp.max_exact_points = kExactPoints;
  tsp.compare_heuristic = false;  // the gap is a benchmark's question, not the cycle's
  search_->planner->setTspOptions(tsp);
  search_->planner->setThreads(options_.repair_threads);
}

std::vector<std::uint32_t> MissionReorder::coverOf(const GridLayer& grid, std::span<const Obstacle> obstacles,
                                                   double now_s, double sweep_s, double vehicle_radius_m,
                                                   double flight_ceiling_m, std::span<const GridCell> free_cells) {
  std::vector<std::uint32_t> cover;
  const double cell = grid.cellSize();
  for (const Obstacle& o : obstacles) {
    const auto [from, to] = o.trackDuring(now_s, now_s + std::max(0.0, sweep_s));
    if (!from.allFinite() || !to.allFinite()) continue;
    if (std::min(from.z(), to.z()) - halfHeight(o) > flight_ceiling_m) continue;  // above the band
    const Eigen::Vector2d a = from.head<2>();
    const Eigen::Vector2d b = to.head<2>();
    const double reach = horizontalRadius(o) + vehicle_radius_m + 0.5 * std::sqrt(2.0) * cell;
    if (!std::isfinite(reach)) continue;
    // The cells whose centres lie in the capsule's bounding box, clipped to the grid.
    const Eigen::Vector2d lo = (a.cwiseMin(b) - grid.origin()).array() / cell - reach / cell;
    const Eigen::Vector2d hi = (a.cwiseMax(b) - grid.origin()).array() / cell + reach / cell;
    const int x0 = std::max(0, static_cast<int>(std::ceil(std::max(lo.x(), -1.0))));
    const int y0 = std::max(0, static_cast<int>(std::ceil(std::max(lo.y(), -1.0))));
    const int x1 = std::min(grid.width() - 1, static_cast<int>(std::floor(std::min(hi.x(), double(grid.width())))));
    const int y1 = std::min(grid.height() - 1, static_cast<int>(std::floor(std::min(hi.y(), double(grid.height())))));
    for (int y = y0; y <= y1; ++y) {
      for (int x = x0; x <= x1; ++x) {
        const GridCell c{x, y};
        if (distanceToSegment(grid.cellCenter(c), a, b) <= reach) cover.push_back(static_cast<std::uint32_t>(grid.index(c)));
      }
    }
  }
  std::sort(cover.begin(), cover.end());
  cover.erase(std::unique(cover.begin(), cover.end()), cover.end());
  std::erase_if(cover, [&](std::uint32_t i) {
    return std::any_of(free_cells.begin(), free_cells.end(), [&](const GridCell& c) { return grid.index(c) == i; });
  });
  return cover;
}

std::optional<GridCell> MissionReorder::vehicleCell(const Eigen::Vector3d& vehicle_m) const {
  const GridLayer& grid = *search_->grid;
  const std::optional<GridCell> at = grid.cellAt(vehicle_m.head<2>());
  if (!at) return std::nullopt;
  if (grid.passable(*at)) return at;
  // The cover is conservative by half a cell and more: the nearest passable cell stands in.
  std::optional<GridCell> best;
  double best_d = 0.0;
  for (int dy = -2; dy <= 2; ++dy) {
    for (int dx = -2; dx <= 2; ++dx) {
      const GridCell c{at->x + dx, at->y + dy};
      const double d = std::hypot(dx, dy);
      if (grid.passable(c) && (!best || d < best_d)) {
        best = c;
        best_d = d;
      }
    }
  }
  return best;
}

std::vector<std::uint32_t> MissionReorder::zoneCover(const MissionOrderSearch& search, std::span<const NoFlyZone> zones,
                                                     double now_s, double sweep_s) {
  std::vector<std::uint32_t> cover;
  const GridLayer& grid = *search.grid;
  const double margin = search.zone_margin_m;
  for (const NoFlyZone& zone : zones) {
    if (!zone.activeDuring(now_s, now_s + std::max(0.0, sweep_s))) continue;
    if (zone.floor_m - margin > search.flight_ceiling_m || zone.ceiling_m + margin < search.band_floor_m) continue;
    if (std::any_of(search.zones.begin(), search.zones.end(), [&](const NoFlyZone& z) { return sameZone(z, zone); }))
      continue;  // blocked in the grid already
    for (const GridCell& c : noFlyZoneCells(grid, zone, margin)) cover.push_back(static_cast<std::uint32_t>(grid.index(c)));
  }
  std::sort(cover.begin(), cover.end());
  cover.erase(std::unique(cover.begin(), cover.end()), cover.end());
  std::erase_if(cover, [&](std::uint32_t i) {
    return std::any_of(search.cells.begin(), search.cells.end(), [&](const GridCell& c) { return grid.index(c) == i; });
  });
  return cover;
}

ReorderCheck MissionReorder::check(std::span<const Obstacle> obstacles, std::span<const NoFlyZone> zones, double now_s,
                                   std::span<const int> reached, const Eigen::Vector3d& vehicle_m,
                                   std::span<const int> remaining, const TerminationCondition& stop) {
  const auto started = std::chrono::steady_clock::now();
  ReorderCheck out;
  out.old_order.push_back(reached.empty() ? 0 : reached.back());
  out.old_order.insert(out.old_order.end(), remaining.begin(), remaining.end());

  GridLayer& grid = *search_->grid;
  std::vector<std::uint32_t> cover = coverOf(grid, obstacles, now_s, options_.sweep_s, vehicle_radius_m_,
                                             search_->flight_ceiling_m, search_->cells);
  if (!zones.empty()) {
    const std::vector<std::uint32_t> zoned = zoneCover(*search_, zones, now_s, options_.sweep_s);
    std::vector<std::uint32_t> both;
    std::set_union(cover.begin(), cover.end(), zoned.begin(), zoned.end(), std::back_inserter(both));
    cover = std::move(both);
  }
  out.covered_cells = cover.size();
  std::vector<std::uint32_t> gone;
  std::vector<std::uint32_t> added;
  std::set_difference(covered_.begin(), covered_.end(), cover.begin(), cover.end(), std::back_inserter(gone));
  std::set_difference(cover.begin(), cover.end(), covered_.begin(), covered_.end(), std::back_inserter(added));
  covered_ = std::move(cover);
  std::vector<GridCell> changed = grid.removeObstacleCover(cellsOf(grid, gone));
  const std::vector<GridCell> blocked = grid.addObstacleCover(cellsOf(grid, added));
  changed.insert(changed.end(), blocked.begin(), blocked.end());
  out.changed_cells = changed.size();
  if (changed.empty()) {
    out.time_ms = msSince(started);
    return out;  // no cost changed: the order in force is still the best
  }

  // The searches follow the flight: reached points stop being goals, the vehicle's start moves
  // to where the new route would take over.
  MissionPlanner& planner = *search_->planner;
  for (int p : reached) planner.arriveAt(p);
  const MissionSearch& searches = planner.search();
  const std::optional<GridCell> vehicle = vehicleCell(vehicle_m);
  const GridCell start = vehicle.value_or(searches.points()[static_cast<std::size_t>(searches.vehiclePoint())]);
  pending_.insert(pending_.end(), changed.begin(), changed.end());
  // A point the obstacles cut off has no order at all, and repairing the searches towards it
  // would raise every cost of its map and search the whole grid from it: one sweep of the grid
  // (far cheaper) tells, and the repair waits, its cells kept, until the point is reachable again.
  const std::vector<std::uint8_t> reach = reachableCells(grid, start, searches.moves());
  for (int p : searches.remainingGoals()) {
    const GridCell c = searches.points()[static_cast<std::size_t>(p)];
    if (reach[grid.index(c)] != 0) continue;
    const std::string name = p == searches.endPoint() ? "end" : "points[" + std::to_string(p - 1) + "]";
    out.failure = make_error(ErrorCode::kUnreachable, name,
                             name + " is cut off by the obstacles on the order grid: the order stays until it is "
                                    "reachable again");
    out.time_ms = msSince(started);
    return out;
  }
  planner.placeVehicle(start);
  const SearchStats before = searches.stats();
  // The repair runs whatever happens next: the searches must see every change.
  const std::vector<GridCell> repair = std::move(pending_);
  pending_.clear();
  Result<MissionOrderPlan> plan = planner.replan(repair, stop);
  out.repaired = true;
  const SearchStats& after = searches.stats();
  out.search.expansions = after.expansions - before.expansions;
  out.search.queue_pushes = after.queue_pushes - before.queue_pushes;
  out.search.queue_pops = after.queue_pops - before.queue_pops;
  out.time_ms = msSince(started);
  if (!plan.ok()) {
    out.failure = plan.error();
    return out;
  }
  out.search.time_ms = plan->search.time_ms;
  out.tsp_time_ms = plan->tsp_time_ms;
  if (!vehicle) {
    out.failure = make_error(ErrorCode::kOccupied, "vehicle",
                             "the vehicle's position is inside an obstacle's cover on the order grid");
    return out;
  }
  const std::vector<int> left = searches.remainingMissions();
  std::vector<int> flown(remaining.begin(), remaining.end());
  if (!flown.empty()) flown.pop_back();  // the end
  std::sort(flown.begin(), flown.end());
  if (out.old_order.front() != searches.vehiclePoint() || flown != left || remaining.empty() ||
      remaining.back() != searches.endPoint()) {
    out.failure = make_error(ErrorCode::kInternal, "order",
                             "the points left to fly (" + orderText(out.old_order) + ") are not those the searches keep");
    return out;
  }
  const double cell_m = grid.cellSize();
  double old_cost = 0.0;
  for (std::size_t k = 1; k < out.old_order.size(); ++k)
    old_cost += plan->cost_matrix[static_cast<std::size_t>(out.old_order[k - 1])][static_cast<std::size_t>(out.old_order[k])];
  out.old_cost_m = old_cost * cell_m;
  out.new_cost_m = plan->cost * cell_m;
  // Only a real saving changes the order: equal orders are not swapped back and forth.
  out.new_order = plan->cost < old_cost - options_.min_gain_cells ? plan->order : out.old_order;
  out.time_ms = msSince(started);
  return out;
}

}  // namespace skyroute
