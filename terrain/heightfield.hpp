// Heightfield: terrain height at any ENU (east, north), by bilinear interpolation in the DEM's own
// grid (no resampling of the heights). ENU -> DEM pixel goes through exact OSR transforms at the
// nodes of a lattice and bilinear interpolation between them (error checked in tests to be far
// below a millimetre of ground position), so a height lookup costs nanoseconds, not a PROJ call.
// Heights are in the frame's up axis (metres AMSL with the default anchor altitude of 0).
#pragma once

#include <memory>
#include <optional>
#include <vector>

#include <Eigen/Core>
#include <Eigen/Geometry>

#include "terrain/dem.hpp"
#include "terrain/local_frame.hpp"

namespace skyroute {

class Heightfield {
 public:
  // frame: the local frame; when absent, one anchored at the DEM's centre at altitude 0.
  static Result<std::shared_ptr<const Heightfield>> build(std::shared_ptr<const Dem> dem,
                                                          std::optional<LocalFrame> frame = std::nullopt);

  // A copy whose every cell is the maximum over a disk of radius_m around it: checking a point
  // against it keeps a sphere of that radius off steep slopes beside the point.
  std::shared_ptr<const Heightfield> dilated(double radius_m) const;

  const Dem& dem() const { return *dem_; }
  const LocalFrame& frame() const { return frame_; }

  // Terrain height (up, metres) at (east, north); NaN outside the DEM or where the DEM is unknown.
  double heightAt(double east_m, double north_m) const;
  std::optional<double> height(const Eigen::Vector2d& en_m) const;
  // Height of p above the ground; nothing outside the DEM or over unknown cells.
  std::optional<double> heightAboveGround(const Eigen::Vector3d& p_m) const;
  bool inside(double east_m, double north_m) const;

  // Lowest (p.z - ground) along the straight segment a -> b, exact for the bilinear surface: the
  // segment is cut at every cell edge it crosses and the quadratic in each piece is minimised.
  // NaN when the segment leaves the DEM or crosses an unknown cell.
  double minHeightAboveGround(const Eigen::Vector3d& a_m, const Eigen::Vector3d& b_m) const;

  // Axis-aligned ENU rectangle inside the DEM's footprint (every point in it has a height unless
  // the DEM has unknown cells there).
  const Eigen::AlignedBox2d& boundsEn() const { return bounds_en_; }
  double minHeightM() const { return min_height_m_; }
  double maxHeightM() const { return max_height_m_; }

  // Fractional DEM pixel coordinates (cell centres at integers) of an ENU point.
  Eigen::Vector2d enToPixel(double east_m, double north_m) const;
  // Same through the exact OSR chain, for tests of the lattice.
  Eigen::Vector2d enToPixelExact(double east_m, double north_m) const;
  Eigen::Vector2d pixelToEn(double col, double row) const;  // exact
  std::size_t memoryBytes() const;
  // Height of cell (col, row): the DEM's, or its dilation's; NaN unknown. No bounds check.
  float heightCell(int col, int row) const { return heights_[static_cast<std::size_t>(row) * width_ + col]; }

 private:
  Heightfield() = default;
  double bilinear(double px, double py) const;

  struct CrsTransforms;  // DEM CRS <-> WGS84, behind a mutex
  std::shared_ptr<CrsTransforms> crs_;
  std::shared_ptr<const Dem> dem_;
  LocalFrame frame_;
  int width_ = 0;
  int height_ = 0;
  std::vector<float> heights_;  // the DEM's cells (or their dilation), NaN unknown
  double min_height_m_ = 0.0;
  double max_height_m_ = 0.0;
  // Lattice ENU -> pixel: nodes every lattice_step_m_ over lattice_box_.
  Eigen::Vector2d lattice_origin_m_ = Eigen::Vector2d::Zero();
  double lattice_step_m_ = 1.0;
  int lattice_nx_ = 0;
  int lattice_ny_ = 0;
  std::vector<Eigen::Vector2d> lattice_pixels_;
  Eigen::AlignedBox2d bounds_en_;
};

}  // namespace skyroute
