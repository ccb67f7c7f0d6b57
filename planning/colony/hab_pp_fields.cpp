// HAB-PP's view of the grid for one plan: the modified visibility field and the sight windows
// (GridFields), what an ant may step to (sightRadius, candidates), and how it chooses among them
// by eq. (1) (angleFactor, rouletteSelect).
#include "planning/colony/hab_pp.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include "planning/grid/grid_search.hpp"

namespace skyroute::habpp {

std::vector<GridCell> segmentCells(GridCell a, GridCell b) { return GridLayer::segmentCells(a, b); }

GridFields::GridFields(const GridLayer& grid, GridCell goal, const HabPpParameters& params)
    : grid_(&grid), goal_(goal), visibility_(grid.cellCount(), 0.0) {
  const int w = grid.width();
  const int h = grid.height();
  blocked_prefix_.assign(static_cast<std::size_t>(w + 1) * (h + 1), 0);
  for (int y = 0; y < h; ++y) {
    for (int x = 0; x < w; ++x) {
      const std::size_t i = static_cast<std::size_t>(y + 1) * (w + 1) + (x + 1);
      blocked_prefix_[i] = (grid.blocked(GridCell{x, y}) ? 1 : 0) + blocked_prefix_[i - 1] +
                           blocked_prefix_[i - (w + 1)] - blocked_prefix_[i - (w + 1) - 1];
    }
  }
  double far = 1.0;
  std::vector<double> to_goal;
  if (params.geodesic_visibility) {
    to_goal = dijkstraCostField(grid, goal);
    for (double d : to_goal) {
      if (std::isfinite(d)) far = std::max(far, d);
    }
  } else {
    for (GridCell corner : {GridCell{0, 0}, GridCell{w - 1, 0}, GridCell{0, h - 1}, GridCell{w - 1, h - 1}}) {
      far = std::max(far, std::hypot(double(corner.x - goal.x), double(corner.y - goal.y)));
    }
  }
  const int reach = static_cast<int>(std::ceil(params.d0_cells));
  for (int y = 0; y < h; ++y) {
    for (int x = 0; x < w; ++x) {
      const GridCell c{x, y};
      const double to_goal_cells = params.geodesic_visibility ? std::min(to_goal[grid.index(c)], far)
                                                              : std::hypot(double(x - goal.x), double(y - goal.y));
      const double closeness = 1.0 - to_goal_cells / far;
      // Distance to the nearest blocked cell centre, exact up to d_0 (only that range matters).
      double nearest = params.d0_cells;
      for (int oy = -reach; oy <= reach; ++oy) {
        for (int ox = -reach; ox <= reach; ++ox) {
          const GridCell o{x + ox, y + oy};
          if (grid.inside(o) && grid.blocked(o)) nearest = std::min(nearest, std::hypot(double(ox), double(oy)));
        }
      }
      const double clearance = nearest / params.d0_cells;
      visibility_[grid.index(c)] = std::max(1e-3, params.k_mix * closeness + (1.0 - params.k_mix) * clearance);
    }
  }
}

bool GridFields::windowFree(GridCell c, int r) const {
  const int w = grid_->width();
  const int x0 = c.x - r, y0 = c.y - r, x1 = c.x + r + 1, y1 = c.y + r + 1;
  if (x0 < 0 || y0 < 0 || x1 > w || y1 > grid_->height()) return false;
  auto at = [&](int x, int y) { return blocked_prefix_[static_cast<std::size_t>(y) * (w + 1) + x]; };
  return at(x1, y1) - at(x0, y1) - at(x1, y0) + at(x0, y0) == 0;
}

namespace {
// The points of the border of the window of radius r around at, in candidates()' order.
template <class Visit>
void forBorder(GridCell at, int r, Visit&& visit) {
  for (int dx = -r; dx <= r; ++dx) {
    visit(GridCell{at.x + dx, at.y - r});
    visit(GridCell{at.x + dx, at.y + r});
  }
  for (int dy = -r + 1; dy <= r - 1; ++dy) {
    visit(GridCell{at.x - r, at.y + dy});
    visit(GridCell{at.x + r, at.y + dy});
  }
}
}  // namespace

std::uint32_t GridFields::borderSight(GridCell c, int r) const {
  const std::size_t slot = grid_->index(c) * (kMaxCachedRadius - 1) + static_cast<std::size_t>(r - 2);
  const std::uint8_t bit = static_cast<std::uint8_t>(1u << (r - 2));
  if (border_sight_.empty()) {
    border_sight_.assign(grid_->cellCount() * (kMaxCachedRadius - 1), 0);
    border_known_.assign(grid_->cellCount(), 0);
  }
  std::uint8_t& known = border_known_[grid_->index(c)];
  if ((known & bit) == 0) {
    std::uint32_t mask = 0;
    int k = 0;
    forBorder(c, r, [&](GridCell q) {
      if (grid_->passable(q) && grid_->lineOfSight(c, q)) mask |= 1u << k;
      ++k;
    });
    border_sight_[slot] = mask;
    known |= bit;
  }
  return border_sight_[slot];
}

int sightRadius(const GridFields& fields, GridCell at, int base_radius, bool expanding, int max_radius) {
  int r = base_radius;
  if (!expanding) return r;
  while (r < max_radius && fields.windowFree(at, r + 1)) ++r;
  return r;
}

std::vector<GridCell> candidates(const GridFields& fields, GridCell at, int radius,
                                 const std::vector<std::uint8_t>& visited) {
  std::vector<GridCell> out;
  candidates(fields, at, radius, visited, out);
  return out;
}

void candidates(const GridFields& fields, GridCell at, int radius, const std::vector<std::uint8_t>& visited,
                std::vector<GridCell>& out) {
  const GridLayer& grid = fields.grid();
  const GridCell goal = fields.goal();
  out.clear();
  if (std::max(std::abs(goal.x - at.x), std::abs(goal.y - at.y)) <= radius && grid.lineOfSight(at, goal)) {
    out.push_back(goal);
    return;
  }
  for (int r = radius; r >= 1; --r) {
    // A free window makes every border point visible (the segment stays inside the free square).
    const bool window_free = fields.windowFree(at, r);
    // Radius 1 (the simple ants, most of the colony): the segment to a side neighbour touches only
    // the two cells, to a diagonal one also the two cells beside the corner, so lineOfSight
    // reduces to those tests.
    // Radii 2 to 4 read the cached border mask (GridFields::borderSight).
    const bool cached = !window_free && r >= 2 && r <= GridFields::kMaxCachedRadius;
    const std::uint32_t mask = cached ? fields.borderSight(at, r) : 0;
    int k = 0;
    auto visible = [&](GridCell c) {
      if (window_free) return true;
      if (cached) return ((mask >> k) & 1u) != 0;
      if (r > 1) return grid.lineOfSight(at, c);
      return c.x == at.x || c.y == at.y ||
             (grid.passable(GridCell{c.x, at.y}) && grid.passable(GridCell{at.x, c.y}));
    };
    forBorder(at, r, [&](GridCell c) {
      if (!grid.blocked(c) && visited[grid.index(c)] == 0 && visible(c)) out.push_back(c);
      ++k;
    });
    if (!out.empty()) return;
  }
}

double angleFactor(double heading_x, double heading_y, GridCell at, GridCell to, double floor) {
  const double sx = to.x - at.x;
  const double sy = to.y - at.y;
  const double hn = std::sqrt(heading_x * heading_x + heading_y * heading_y);
  const double sn = std::sqrt(sx * sx + sy * sy);
  if (hn == 0.0 || sn == 0.0) return 1.0;
  const double cos_theta = (heading_x * sx + heading_y * sy) / (hn * sn);
  return std::max(floor, 0.5 * (1.0 + cos_theta));
}

std::size_t rouletteSelect(const std::vector<double>& weights, Rng& rng) {
  double sum = 0.0;
  for (double w : weights) sum += w;
  const double r = std::uniform_real_distribution<double>(0.0, sum)(rng);
  double acc = 0.0;
  for (std::size_t i = 0; i < weights.size(); ++i) {
    acc += weights[i];
    if (r < acc) return i;
  }
  // Rounding can leave r == sum: the last index with a positive weight.
  for (std::size_t i = weights.size(); i-- > 0;) {
    if (weights[i] > 0.0) return i;
  }
  return weights.size() - 1;
}

}  // namespace skyroute::habpp
