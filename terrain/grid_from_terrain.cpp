#include "terrain/grid_from_terrain.hpp"

#include <algorithm>
#include <cmath>

namespace skyroute {
namespace {

// The cells the band's no-fly zones cover, except those holding a point to keep free.
std::vector<GridCell> zoneCells(const GridLayer& grid, const Heightfield& terrain, const TerrainGridOptions& options) {
  std::vector<GridCell> cells;
  const double margin = options.zone_margin_m;
  for (const NoFlyZone& zone : options.no_fly_zones) {
    if (zone.floor_m - margin > options.flight_ceiling_m) continue;
    if (zone.ceiling_m + margin < terrain.minHeightM() + options.min_clearance_m) continue;
    const std::vector<GridCell> footprint = noFlyZoneCells(grid, zone, margin);
    cells.insert(cells.end(), footprint.begin(), footprint.end());
  }
  for (const Eigen::Vector2d& p : options.keep_free_m) {
    const auto free = grid.cellAt(p);
    if (free) cells.erase(std::remove(cells.begin(), cells.end(), *free), cells.end());
  }
  return cells;
}

}  // namespace

std::vector<GridCell> noFlyZoneCells(const GridLayer& grid, const NoFlyZone& zone, double margin_m) {
  std::vector<GridCell> cells;
  const Eigen::AlignedBox2d box = zone.boundsEn();
  const Eigen::Vector2d lo_m = box.min() - Eigen::Vector2d::Constant(margin_m + grid.cellSize());
  const Eigen::Vector2d hi_m = box.max() + Eigen::Vector2d::Constant(margin_m + grid.cellSize());
  const Eigen::Vector2d lo = ((lo_m - grid.origin()) / grid.cellSize()).array().floor();
  const Eigen::Vector2d hi = ((hi_m - grid.origin()) / grid.cellSize()).array().ceil();
  if (!lo.allFinite() || !hi.allFinite()) return cells;
  for (int y = std::max(0, static_cast<int>(std::max(lo.y(), -1.0))); y <= std::min(grid.height() - 1, static_cast<int>(std::min(hi.y(), double(grid.height())))); ++y) {
    for (int x = std::max(0, static_cast<int>(std::max(lo.x(), -1.0))); x <= std::min(grid.width() - 1, static_cast<int>(std::min(hi.x(), double(grid.width())))); ++x) {
      const GridCell c{x, y};
      if (zone.touchesSquare(grid.cellCenter(c), grid.cellSize(), margin_m)) cells.push_back(c);
    }
  }
  return cells;
}

Result<GridLayer> buildTerrainGrid(const Heightfield& terrain, const TerrainGridOptions& options) {
  if (!(options.cell_size_m > 0.0) || !std::isfinite(options.cell_size_m)) {
    return make_error(ErrorCode::kInvalidArgument, "cell_size_m", "must be positive and finite");
  }
  if (!std::isfinite(options.flight_ceiling_m)) {
    return make_error(ErrorCode::kInvalidArgument, "flight_ceiling_m", "must be finite");
  }
  if (!(options.min_clearance_m >= 0.0)) {
    return make_error(ErrorCode::kInvalidArgument, "min_clearance_m", "must be zero or positive");
  }
  const Eigen::AlignedBox2d& box = terrain.boundsEn();
  const int width = static_cast<int>(std::floor(box.sizes().x() / options.cell_size_m));
  const int height = static_cast<int>(std::floor(box.sizes().y() / options.cell_size_m));
  if (width < 1 || height < 1) {
    return make_error(ErrorCode::kInvalidArgument, "cell_size_m", "is larger than the terrain");
  }
  if (width > options.max_cells_per_axis || height > options.max_cells_per_axis) {
    return make_error(ErrorCode::kInvalidArgument, "cell_size_m",
                      "gives a " + std::to_string(width) + " x " + std::to_string(height) +
                          " grid, more than max_cells_per_axis = " + std::to_string(options.max_cells_per_axis));
  }
  const Eigen::Vector2d origin = box.min() + Eigen::Vector2d::Constant(0.5 * options.cell_size_m);
  GridLayer grid(width, height, options.cell_size_m, origin);

  // Sample each cell at least every half DEM cell so a narrow peak inside it is not missed.
  const double dem_res = terrain.dem().resolutionM().minCoeff();
  const int samples = std::clamp(static_cast<int>(std::ceil(options.cell_size_m / (0.5 * dem_res))) + 1, 2, 64);
  const double limit = options.flight_ceiling_m - options.min_clearance_m;
  std::vector<GridCell> blocked;
  for (int y = 0; y < height; ++y) {
    if (options.cancel && options.cancel->load(std::memory_order_relaxed)) {
      return make_error(ErrorCode::kCancelled, "grid", "building the terrain grid was cancelled");
    }
    for (int x = 0; x < width; ++x) {
      const Eigen::Vector2d c = grid.cellCenter(GridCell{x, y});
      bool is_blocked = false;
      for (int j = 0; j < samples && !is_blocked; ++j) {
        for (int i = 0; i < samples && !is_blocked; ++i) {
          const double e = c.x() + options.cell_size_m * (static_cast<double>(i) / (samples - 1) - 0.5);
          const double n = c.y() + options.cell_size_m * (static_cast<double>(j) / (samples - 1) - 0.5);
          const double h = terrain.heightAt(e, n);
          is_blocked = !(h <= limit);  // NaN (unknown) blocks too
        }
      }
      if (is_blocked) blocked.push_back(GridCell{x, y});
    }
  }
  grid.setStaticBlocked(blocked, true);
  grid.setStaticBlocked(zoneCells(grid, terrain, options), true);
  return grid;
}

}  // namespace skyroute
