// A GridLayer seen through the MotionValidator interface, so the 3D sampling planners (RRT*,
// LOSPO) can run on the 2D grid at the flight band: the HAB-PP benchmark's "RRT* with LOSPO" next
// to the grid planners. Only the benchmarks use it, so it lives in bench/support.
//
// Points are ENU metres in the grid's frame (GridLayer::cellCenter: cell (x, y) has its centre at
// origin + cell_size * (x, y)); with the default frame of a Moving AI map these are cell
// coordinates. The planners need a box of positive volume, so the grid is lifted to a slab
// [band_min_m, band_max_m] in z in which height does not matter: a state is valid when it lies in
// the slab over a free cell, a motion when it stays in the slab and the closed square of every cell
// its (x, y) shadow touches is free. For segments between cell centres that is exactly
// GridLayer::lineOfSight (corner passes need both side cells free). Callers that want a 2D path
// set z = 0 (or any height in the slab) on the result; projecting a valid path keeps it valid.
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>

#include "planning/core/motion_validator.hpp"
#include "terrain/grid_layer.hpp"

namespace skyroute {

class GridMotionValidator : public MotionValidator {
 public:
  // The grid must outlive the validator and not change while a planner uses it (reads only, so
  // concurrent planners are safe). band_max_m must exceed band_min_m.
  explicit GridMotionValidator(const GridLayer& grid, double band_min_m = -0.5, double band_max_m = 0.5);

  bool isStateValid(const Eigen::Vector3d& p_m) const override;
  bool isMotionValid(const Eigen::Vector3d& a_m, const Eigen::Vector3d& b_m) const override;
  // The hull of the cell centres times the band: every sample lies over the grid.
  Eigen::AlignedBox3d samplingBounds() const override;

  // Metres <-> continuous cell coordinates (cell centres at integers).
  Eigen::Vector2d toCell(const Eigen::Vector3d& p_m) const;
  Eigen::Vector3d toMetres(double cell_x, double cell_y, double z_m = 0.0) const;

  const GridLayer& grid() const { return *grid_; }

 private:
  bool inBand(double z_m) const { return z_m >= band_min_m_ && z_m <= band_max_m_; }

  const GridLayer* grid_;
  double band_min_m_;
  double band_max_m_;
};

}  // namespace skyroute
