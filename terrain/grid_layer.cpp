#include "terrain/grid_layer.hpp"

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <stdexcept>

namespace skyroute {

GridLayer::GridLayer(int width, int height, double cell_size_m, const Eigen::Vector2d& origin_m)
    : width_(std::max(0, width)),
      height_(std::max(0, height)),
      cell_size_m_(cell_size_m),
      origin_m_(origin_m),
      static_blocked_(cellCount(), 0),
      obstacle_count_(cellCount(), 0),
      blocked_(cellCount(), 0) {}

GridLayer GridLayer::fromRows(const std::vector<std::string>& rows) {
  GridLayer g(rows.empty() ? 0 : static_cast<int>(rows.front().size()), static_cast<int>(rows.size()));
  std::vector<GridCell> blocked;
  for (int y = 0; y < static_cast<int>(rows.size()); ++y) {
    for (int x = 0; x < static_cast<int>(rows[y].size()) && x < g.width(); ++x) {
      if (rows[y][x] == '#') blocked.push_back({x, y});
    }
  }
  g.setStaticBlocked(blocked, true);
  return g;
}

GridLayer GridLayer::cropped(GridCell lo, int width, int height) const {
  GridLayer out(width, height, cell_size_m_, origin_m_ + cell_size_m_ * Eigen::Vector2d(lo.x, lo.y));
  std::vector<GridCell> cells;
  for (int y = 0; y < height; ++y) {
    for (int x = 0; x < width; ++x) {
      if (blocked(GridCell{lo.x + x, lo.y + y})) cells.push_back(GridCell{x, y});
    }
  }
  out.setStaticBlocked(cells, true);
  return out;
}

std::size_t GridLayer::blockedCount() const {
  return static_cast<std::size_t>(std::count(blocked_.begin(), blocked_.end(), std::uint8_t{1}));
}

void GridLayer::refresh(std::size_t i, std::vector<GridCell>& changed) {
  const std::uint8_t now = (static_blocked_[i] != 0 || obstacle_count_[i] > 0) ? 1 : 0;
  if (now != blocked_[i]) {
    blocked_[i] = now;
    changed.push_back(cellOf(i));
  }
}

template <class Change>
std::vector<GridCell> GridLayer::changeCells(std::span<const GridCell> cells, Change&& change) {
  std::vector<GridCell> changed;
  for (const GridCell& c : cells) {
    if (!inside(c)) continue;
    const std::size_t i = index(c);
    change(i);
    refresh(i, changed);
  }
  if (!changed.empty()) ++version_;
  return changed;
}

std::vector<GridCell> GridLayer::setStaticBlocked(std::span<const GridCell> cells, bool blocked) {
  return changeCells(cells, [&](std::size_t i) { static_blocked_[i] = blocked ? 1 : 0; });
}

std::vector<GridCell> GridLayer::addObstacleCover(std::span<const GridCell> cells) {
  return changeCells(cells, [&](std::size_t i) {
    if (obstacle_count_[i] < UINT16_MAX) ++obstacle_count_[i];
  });
}

std::vector<GridCell> GridLayer::removeObstacleCover(std::span<const GridCell> cells) {
  return changeCells(cells, [&](std::size_t i) {
    if (obstacle_count_[i] > 0) --obstacle_count_[i];
  });
}

Eigen::Vector2d GridLayer::cellCenter(GridCell c) const {
  return origin_m_ + cell_size_m_ * Eigen::Vector2d(c.x, c.y);
}

std::optional<GridCell> GridLayer::cellAt(const Eigen::Vector2d& east_north_m) const {
  const Eigen::Vector2d g = (east_north_m - origin_m_) / cell_size_m_;
  if (!std::isfinite(g.x()) || !std::isfinite(g.y())) return std::nullopt;
  const GridCell c{static_cast<int>(std::floor(g.x() + 0.5)), static_cast<int>(std::floor(g.y() + 0.5))};
  if (!inside(c)) return std::nullopt;
  return c;
}

namespace {

// Walks the cells the segment between cell centres a and b touches, calling visit(cell) for each
// in order (corner side cells before the diagonal step); stops early when visit returns false.
template <class Visit>
bool walkSegmentCells(GridCell a, GridCell b, Visit&& visit) {
  if (!visit(a)) return false;
  const int dx = std::abs(b.x - a.x);
  const int dy = std::abs(b.y - a.y);
  const int sx = b.x > a.x ? 1 : -1;
  const int sy = b.y > a.y ? 1 : -1;
  // Cells are unit squares around integer centres. The segment crosses the k-th vertical cell
  // boundary at parameter (2k+1)/(2dx) and the m-th horizontal one at (2m+1)/(2dy); comparing
  // (2k+1)*dy with (2m+1)*dx in integers orders the crossings exactly, ties being corners.
  int x = a.x;
  int y = a.y;
  long long k = 0;
  long long m = 0;
  while (k < dx || m < dy) {
    const long long tv = (k < dx) ? (2 * k + 1) * static_cast<long long>(dy) : -1;
    const long long th = (m < dy) ? (2 * m + 1) * static_cast<long long>(dx) : -1;
    if (m >= dy || (k < dx && tv < th)) {
      x += sx;
      ++k;
    } else if (k >= dx || th < tv) {
      y += sy;
      ++m;
    } else {  // exactly through a corner: the segment touches both side cells
      if (!visit(GridCell{x + sx, y}) || !visit(GridCell{x, y + sy})) return false;
      x += sx;
      y += sy;
      ++k;
      ++m;
    }
    if (!visit(GridCell{x, y})) return false;
  }
  return true;
}

}  // namespace

bool GridLayer::lineOfSight(GridCell a, GridCell b) const {
  return walkSegmentCells(a, b, [this](GridCell c) { return passable(c); });
}

std::vector<GridCell> GridLayer::segmentCells(GridCell a, GridCell b) {
  std::vector<GridCell> cells;
  walkSegmentCells(a, b, [&cells](GridCell c) {
    cells.push_back(c);
    return true;
  });
  return cells;
}

}  // namespace skyroute
