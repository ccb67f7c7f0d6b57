// Derives the 2D GridLayer at a flight band from the terrain: a cell is blocked where the terrain
// anywhere in the cell, plus the clearance, rises above the band's ceiling, or where the DEM is
// unknown or absent. Cell (0, 0) is at the south-west corner of the heightfield's ENU bounds;
// x grows east, y grows north.
#pragma once

#include <atomic>
#include <vector>

#include "planning/core/result.hpp"
#include "terrain/grid_layer.hpp"
#include "terrain/heightfield.hpp"
#include "terrain/no_fly_zone.hpp"

namespace skyroute {

struct TerrainGridOptions {
  double cell_size_m = 90.0;
  double flight_ceiling_m = 1500.0;  // top of the flight band (up axis, metres AMSL by default)
  double min_clearance_m = 30.0;     // required height above ground
  int max_cells_per_axis = 4000;     // refuse absurd grids rather than exhaust memory
  // Set from another thread to stop a long build (checked every row): kCancelled. Not owned.
  const std::atomic<bool>* cancel = nullptr;
  // No-fly zones reaching into the band (floor under its ceiling, ceiling over the lowest ground
  // plus clearance) block every cell their polygon, grown by zone_margin_m, touches, whatever
  // their time window: a grid search has no clock. Cells holding a keep_free_m point (a route's
  // ends, checked clear of the zones by the caller) are left to the terrain.
  std::vector<NoFlyZone> no_fly_zones;
  double zone_margin_m = 0.0;
  std::vector<Eigen::Vector2d> keep_free_m;
};

// The cells of `grid` whose square the zone's polygon, grown by margin_m, touches (its footprint,
// whatever its floor, ceiling and time window).
std::vector<GridCell> noFlyZoneCells(const GridLayer& grid, const NoFlyZone& zone, double margin_m);

// Errors: kInvalidArgument naming the option (cell size <= 0, grid too large); kCancelled.
Result<GridLayer> buildTerrainGrid(const Heightfield& terrain, const TerrainGridOptions& options);

}  // namespace skyroute
