#include "bench/support/grid_motion_validator.hpp"

#include <algorithm>
#include <cmath>

namespace skyroute {

namespace {

// A point closer than this (in cells) to a cell's closed square counts as touching it, so rounding
// in the metre <-> cell conversion can only make a check stricter, never let a corner slip through.
// Segments between cell centres pass at least 1 / (2 * length) cells from any corner they miss,
// far more than this, so for them the rule equals GridLayer::lineOfSight.
constexpr double kTouchCells = 1e-9;

int firstCellTouching(double lo) { return static_cast<int>(std::ceil(lo - 0.5 - kTouchCells)); }
int lastCellTouching(double hi) { return static_cast<int>(std::floor(hi + 0.5 + kTouchCells)); }

}  // namespace

GridMotionValidator::GridMotionValidator(const GridLayer& grid, double band_min_m, double band_max_m)
    : grid_(&grid), band_min_m_(band_min_m), band_max_m_(band_max_m) {}

Eigen::Vector2d GridMotionValidator::toCell(const Eigen::Vector3d& p_m) const {
  return (p_m.head<2>() - grid_->origin()) / grid_->cellSize();
}

Eigen::Vector3d GridMotionValidator::toMetres(double cell_x, double cell_y, double z_m) const {
  const Eigen::Vector2d en = grid_->origin() + grid_->cellSize() * Eigen::Vector2d(cell_x, cell_y);
  return {en.x(), en.y(), z_m};
}

bool GridMotionValidator::isStateValid(const Eigen::Vector3d& p_m) const {
  if (!p_m.allFinite() || !inBand(p_m.z())) return false;
  const Eigen::Vector2d c = toCell(p_m);
  // A point on a cell border touches the cells on both sides; all must be free.
  for (int y = firstCellTouching(c.y()); y <= lastCellTouching(c.y()); ++y) {
    for (int x = firstCellTouching(c.x()); x <= lastCellTouching(c.x()); ++x) {
      if (grid_->blocked(GridCell{x, y})) return false;
    }
  }
  return true;
}

bool GridMotionValidator::isMotionValid(const Eigen::Vector3d& a_m, const Eigen::Vector3d& b_m) const {
  if (!isStateValid(a_m) || !isStateValid(b_m)) return false;  // the band is convex: ends suffice in z
  const Eigen::Vector2d a = toCell(a_m);
  const Eigen::Vector2d b = toCell(b_m);
  const double x_lo = std::min(a.x(), b.x());
  const double x_hi = std::max(a.x(), b.x());
  const double dx = b.x() - a.x();
  // Column by column: the part of the segment over the column's closed x-range spans a y-range;
  // every cell of the column whose closed square meets that range is touched.
  for (int cx = firstCellTouching(x_lo); cx <= lastCellTouching(x_hi); ++cx) {
    double lo = std::max(x_lo, cx - 0.5);
    double hi = std::min(x_hi, cx + 0.5);
    if (lo > hi) lo = hi = (lo > x_hi ? x_hi : x_lo);  // a column only grazed within kTouchCells
    double y0 = std::min(a.y(), b.y());
    double y1 = std::max(a.y(), b.y());
    if (std::abs(dx) > 0.0) {
      const double ya = a.y() + (b.y() - a.y()) * ((lo - a.x()) / dx);
      const double yb = a.y() + (b.y() - a.y()) * ((hi - a.x()) / dx);
      y0 = std::min(ya, yb);
      y1 = std::max(ya, yb);
    }
    for (int cy = firstCellTouching(y0); cy <= lastCellTouching(y1); ++cy) {
      if (grid_->blocked(GridCell{cx, cy})) return false;
    }
  }
  return true;
}

Eigen::AlignedBox3d GridMotionValidator::samplingBounds() const {
  const Eigen::Vector3d lo = toMetres(0.0, 0.0, band_min_m_);
  const Eigen::Vector3d hi = toMetres(grid_->width() - 1.0, grid_->height() - 1.0, band_max_m_);
  return Eigen::AlignedBox3d(lo.cwiseMin(hi), lo.cwiseMax(hi));
}

}  // namespace skyroute
