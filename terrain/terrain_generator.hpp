// The seeded generator of the embedded default terrain (data/default_terrain.tif): ridged fractal
// noise plus a long ridge with passes and a valley, so a planner must climb or go around.
// `skyroute terrain generate` writes it as a GeoTIFF with a real CRS.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

namespace skyroute {

struct TerrainGeneratorOptions {
  std::uint32_t seed = 2026;
  int width = 320;                 // cells
  int height = 320;                // cells
  double cell_size_m = 40.0;
  double base_height_m = 150.0;
  double relief_m = 650.0;         // highest ridges rise about this much above the base
  int epsg = 32633;                // WGS 84 / UTM zone 33N
  double origin_easting_m = 500000.0;   // top-left corner of the raster
  double origin_northing_m = 5205000.0;
};

// Heights in metres, row-major, row 0 at the north edge.
std::vector<float> generateTerrainHeights(const TerrainGeneratorOptions& options);

}  // namespace skyroute
