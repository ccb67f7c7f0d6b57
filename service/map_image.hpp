// MapImage: a hillshade of the DEM that paths and markers are drawn on, saved as PNG through GDAL
// (hillshade by GDALDEMProcessing, drawing in memory, PNG by CreateCopy).
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
  // A blank canvas (e.g. for grid maps); `background` fills it.
  static MapImage blank(int width, int height, Rgb background);

  int width() const { return width_; }
  int height() const { return height_; }
  void setPixel(int x, int y, Rgb c);
  // Pixel coordinates with cell centres at integers.
  void drawLine(const Eigen::Vector2d& from_px, const Eigen::Vector2d& to_px, Rgb c, int thickness = 1);
  void drawDisc(const Eigen::Vector2d& center_px, double radius_px, Rgb c);
  // An ENU polyline through the heightfield's pixel mapping.
  void drawPathEn(const Heightfield& terrain, const std::vector<Eigen::Vector3d>& path_m, Rgb c, int thickness = 2);
  // Appends a panel of `panel_height` rows under the map with a line chart of `values` (e.g. an
  // altitude profile) against `reference` (e.g. the ground under it), both in the same units.
  void appendProfile(const std::vector<double>& values, const std::vector<double>& reference, int panel_height);

  Status savePng(const std::string& path) const;

 private:
  int width_ = 0;
  int height_ = 0;
  std::vector<std::uint8_t> rgb_;  // interleaved
};

}  // namespace skyroute
