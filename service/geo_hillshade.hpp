// A hillshade of a DEM as PNG bytes on a WGS84 latitude/longitude grid, with its bounds, so a
// viewer (the ground station's web map) maps latitude and longitude to pixels linearly. The DEM is
// warped to EPSG:4326 by GDAL (GDALWarp, bilinear) and shaded as MapImage::hillshade shades it.
#pragma once

#include <string>

#include "terrain/dem.hpp"
#include "planning/core/result.hpp"

namespace skyroute {

struct GeoPng {
  std::string png;  // the PNG file's bytes
  int width_px = 0;
  int height_px = 0;
  // Outer edges of the image (pixel corners, not centres), degrees.
  double west_deg = 0.0;
  double south_deg = 0.0;
  double east_deg = 0.0;
  double north_deg = 0.0;
};

Result<GeoPng> hillshadePngWgs84(const Dem& dem);

}  // namespace skyroute
