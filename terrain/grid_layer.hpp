// GridLayer: a 2D 8-connected occupancy grid at the flight band, the world of the grid searches
// (D* Lite, MMD*L, GMTPA, HAB-PP). Built from the terrain (grid_from_terrain.hpp) or loaded from a
// Moving AI map (movingai.hpp).
//
// Blocking has two sources kept apart so that removing an obstacle restores exactly what the
// terrain says: the static layer (terrain or map walls) and a per-cell count of obstacles covering
// the cell. Every update returns the cells whose blocked state actually changed, which is what an
// incremental search (D* Lite) needs to repair its costs.
#pragma once

#include <cmath>
#include <cstdint>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include <Eigen/Core>

namespace skyroute {

struct GridCell {
  int x = 0;  // column (east, or the Moving AI x)
  int y = 0;  // row (north, or the Moving AI y)
  friend bool operator==(const GridCell&, const GridCell&) = default;
};

// Euclidean distance between the centres of a and b, in cell edges (polylineLength of
// planning/core/polyline.hpp finds it for paths of cells).
inline double segmentLength(GridCell a, GridCell b) {
  return std::hypot(static_cast<double>(b.x - a.x), static_cast<double>(b.y - a.y));
}

class GridLayer {
 public:
  GridLayer() = default;
  // cell_size_m: edge of a cell; origin_m: ENU (east, north) of the centre of cell (0, 0).
  GridLayer(int width, int height, double cell_size_m = 1.0,
            const Eigen::Vector2d& origin_m = Eigen::Vector2d::Zero());
  // A small grid drawn as text, row y = 0 first: '#' is blocked, anything else free (for tests,
  // examples and benchmarks). Rows shorter than the first are padded with free cells.
  static GridLayer fromRows(const std::vector<std::string>& rows);
  // The width x height cells from `lo` as a grid of their own (cell lo becomes (0, 0), the origin
  // moves with it), each blocked where this grid blocks it (static or obstacle layer) and cells
  // beyond this grid blocked: a search on the crop can only use cells of the box.
  GridLayer cropped(GridCell lo, int width, int height) const;

  int width() const { return width_; }
  int height() const { return height_; }
  double cellSize() const { return cell_size_m_; }
  const Eigen::Vector2d& origin() const { return origin_m_; }
  std::size_t cellCount() const { return static_cast<std::size_t>(width_) * height_; }

  bool inside(GridCell c) const { return c.x >= 0 && c.y >= 0 && c.x < width_ && c.y < height_; }
  std::size_t index(GridCell c) const { return static_cast<std::size_t>(c.y) * width_ + c.x; }
  GridCell cellOf(std::size_t index) const {
    return GridCell{static_cast<int>(index % width_), static_cast<int>(index / width_)};
  }
  // Outside cells count as blocked, so searches need no separate bounds test.
  bool blocked(GridCell c) const { return !inside(c) || blocked_[index(c)] != 0; }
  bool passable(GridCell c) const { return !blocked(c); }
  bool staticBlocked(GridCell c) const { return !inside(c) || static_blocked_[index(c)] != 0; }
  int obstacleCount(GridCell c) const { return inside(c) ? obstacle_count_[index(c)] : 0; }
  std::size_t blockedCount() const;

  // Static layer (terrain, map walls). Returns the cells whose blocked state changed.
  std::vector<GridCell> setStaticBlocked(std::span<const GridCell> cells, bool blocked);
  // Obstacle layer: each call adds or removes one cover of the given cells.
  std::vector<GridCell> addObstacleCover(std::span<const GridCell> cells);
  std::vector<GridCell> removeObstacleCover(std::span<const GridCell> cells);

  // Grows with every change of any cell's blocked state.
  std::uint64_t version() const { return version_; }

  // Cell <-> ENU metres. cellAt returns nothing outside the grid.
  Eigen::Vector2d cellCenter(GridCell c) const;
  std::optional<GridCell> cellAt(const Eigen::Vector2d& east_north_m) const;

  // Any-angle line of sight between cell centres: every cell the segment passes through is
  // passable, and where it passes exactly through a cell corner both cells beside the corner must
  // be passable too (the same rule as "no corner cutting" for diagonal moves).
  bool lineOfSight(GridCell a, GridCell b) const;
  // Every cell the segment between the centres of a and b touches, in order from a, including both
  // side cells where it passes exactly through a corner (the cells lineOfSight requires free).
  static std::vector<GridCell> segmentCells(GridCell a, GridCell b);

 private:
  void refresh(std::size_t i, std::vector<GridCell>& changed);
  // Applies change(i) to each cell of `cells` inside the grid, then refreshes its blocked state;
  // returns the cells whose blocked state changed (one version step when any did).
  template <class Change>
  std::vector<GridCell> changeCells(std::span<const GridCell> cells, Change&& change);

  int width_ = 0;
  int height_ = 0;
  double cell_size_m_ = 1.0;
  Eigen::Vector2d origin_m_ = Eigen::Vector2d::Zero();
  std::vector<std::uint8_t> static_blocked_;
  std::vector<std::uint16_t> obstacle_count_;
  std::vector<std::uint8_t> blocked_;
  std::uint64_t version_ = 0;
};

}  // namespace skyroute
