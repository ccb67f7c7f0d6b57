// MapImage: a hillshade of the DEM tinted by height, in the DEM's own pixel grid, for map figures
// (service/map_figure.hpp) and `terrain info --png` (hillshade by GDALDEMProcessing, PNG by CreateCopy).
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "planning/core/result.hpp"
#include "terrain/heightfield.hpp"

namespace skyroute {

struct Rgb {
  std::uint8_t r = 0, g = 0, b = 0;
};

class MapImage {
 public:
  // Hillshade of the DEM in its own pixel grid (one image pixel per DEM cell).
  static Result<MapImage> hillshade(const Dem& dem);
  // The same for the window of cols x rows cells from (col0, row0), clipped to the DEM; pixel
  // (0, 0) is cell (col0, row0).
  static Result<MapImage> hillshade(const Dem& dem, int col0, int row0, int cols, int rows);

  int width() const { return width_; }
  int height() const { return height_; }
  Rgb pixel(int x, int y) const;  // black outside the image

  Status savePng(const std::string& path) const;

 private:
  int width_ = 0;
  int height_ = 0;
  std::vector<std::uint8_t> rgb_;  // interleaved
};

}  // namespace skyroute
