// Dem: one band of elevations read through GDAL, in metres, in the raster's own grid and CRS.
// Voids (nodata) are filled by interpolation when small; cells of large voids stay unknown (NaN)
// and are never flyable.
#pragma once

#include <array>
#include <chrono>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "planning/core/result.hpp"

namespace skyroute {

struct DemLoadOptions {
  int band = 0;                     // 1-based band; 0 = the only band (several bands is an error)
  int max_filled_void_cells = 64;   // a void (4-connected nodata region) up to this size is filled
  double min_plausible_height_m = -500.0;   // below the Dead Sea shore with margin
  double max_plausible_height_m = 9000.0;   // above Everest with margin
  // Larger rasters are refused before any cell is read: loading and the heightfield take about 20
  // bytes a cell, and a few hundred bytes of header can declare billions of cells.
  std::int64_t max_cells = 100'000'000;
};

class Dem {
 public:
  // Errors (each names the file): kFileNotFound, kNotARaster, kNoCrs, kBandAmbiguous,
  // kInvalidArgument (band out of range, more cells than max_cells), kAllNodata, kAbsurdHeights.
  static Result<std::shared_ptr<const Dem>> load(const std::string& path, const DemLoadOptions& options = {});
  // For tests and the generator: a DEM from memory. heights_m row-major, row 0 at the top.
  static Result<std::shared_ptr<const Dem>> fromArray(int width, int height, std::vector<float> heights_m,
                                                      const std::array<double, 6>& geo_transform,
                                                      const std::string& crs_wkt, const std::string& name);

  const std::string& path() const { return path_; }
  int width() const { return width_; }
  int height() const { return height_; }
  const std::string& crsWkt() const { return crs_wkt_; }
  const std::string& crsName() const { return crs_name_; }
  bool isGeographic() const { return geographic_; }
  // GDAL convention: x = gt[0] + col*gt[1] + row*gt[2] at the pixel's top-left corner.
  const std::array<double, 6>& geoTransform() const { return geo_transform_; }

  // Height in metres of cell (col, row); NaN where unknown. No bounds check in release builds.
  float cell(int col, int row) const { return heights_m_[static_cast<std::size_t>(row) * width_ + col]; }
  const std::vector<float>& cells() const { return heights_m_; }

  // CRS coordinates of a fractional pixel position (cell centres at col + 0.5, row + 0.5).
  Eigen::Vector2d pixelToCrs(double col, double row) const;
  Eigen::Vector2d crsToPixel(double x, double y) const;

  double minHeightM() const { return min_height_m_; }
  double maxHeightM() const { return max_height_m_; }
  int filledVoidCells() const { return filled_void_cells_; }
  int unknownCells() const { return unknown_cells_; }
  // Mean ground size of a cell (x, y) in metres, measured at the centre of the raster.
  const Eigen::Vector2d& resolutionM() const { return resolution_m_; }
  std::size_t memoryBytes() const { return heights_m_.size() * sizeof(float); }
  double loadSeconds() const { return load_seconds_; }

 private:
  static Result<std::shared_ptr<const Dem>> finish(std::shared_ptr<Dem> dem, const DemLoadOptions& options,
                                                   std::chrono::steady_clock::time_point started);

  std::string path_;
  int width_ = 0;
  int height_ = 0;
  std::string crs_wkt_;
  std::string crs_name_;
  bool geographic_ = false;
  std::array<double, 6> geo_transform_{};
  std::array<double, 6> inverse_transform_{};
  std::vector<float> heights_m_;
  double min_height_m_ = 0.0;
  double max_height_m_ = 0.0;
  int filled_void_cells_ = 0;
  int unknown_cells_ = 0;
  Eigen::Vector2d resolution_m_ = Eigen::Vector2d::Zero();
  double load_seconds_ = 0.0;
};

}  // namespace skyroute
