#include "terrain/flyable_regions.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <queue>
#include <utility>

namespace skyroute {
namespace {

constexpr float kNever = std::numeric_limits<float>::infinity();  // a block with no flyable square
constexpr double kDoubtfulBlockCost = 4.0;  // per metre through a block flyable only in part

constexpr int kNeighbourDx[8] = {1, -1, 0, 0, 1, 1, -1, -1};
constexpr int kNeighbourDy[8] = {0, 0, 1, -1, 1, -1, 1, -1};

// Calls visit(k, n) for each of the 8 neighbours n of block `at` inside a width x height grid
// (row-major indices); k indexes kNeighbourDx / kNeighbourDy.
template <class Visit>
void forEachNeighbour(std::size_t at, int width, int height, Visit visit) {
  const int x = static_cast<int>(at % static_cast<std::size_t>(width));
  const int y = static_cast<int>(at / static_cast<std::size_t>(width));
  for (int k = 0; k < 8; ++k) {
    const int nx = x + kNeighbourDx[k], ny = y + kNeighbourDy[k];
    if (nx < 0 || ny < 0 || nx >= width || ny >= height) continue;
    visit(k, static_cast<std::size_t>(ny) * static_cast<std::size_t>(width) + static_cast<std::size_t>(nx));
  }
}

}  // namespace

FlyableRegions FlyableRegions::build(const Heightfield& terrain, double threshold_m, std::size_t max_blocks) {
  FlyableRegions r;
  r.terrain_ = &terrain;
  r.threshold_m_ = threshold_m;
  const int cells_wide = terrain.dem().width();
  const int cells_high = terrain.dem().height();
  r.squares_wide_ = std::max(1, cells_wide - 1);
  r.squares_high_ = std::max(1, cells_high - 1);
  const std::size_t wanted = std::max<std::size_t>(1, max_blocks);
  auto blocks = [&](int pool) {
    return static_cast<std::size_t>((r.squares_wide_ + pool - 1) / pool) *
           static_cast<std::size_t>((r.squares_high_ + pool - 1) / pool);
  };
  int pool = 1;
  while (blocks(pool) > wanted) ++pool;
  r.pool_ = pool;
  r.width_ = (r.squares_wide_ + pool - 1) / pool;
  r.height_ = (r.squares_high_ + pool - 1) / pool;
  const Eigen::Vector2d cell_m = terrain.dem().resolutionM();
  r.block_east_m_ = std::max(1e-6, pool * std::abs(cell_m.x()));
  r.block_north_m_ = std::max(1e-6, pool * std::abs(cell_m.y()));

  // Each square's lowest corner (a square with an unknown corner is unknown everywhere: the
  // bilinear height propagates NaN), folded into its block's minimum.
  r.floor_.assign(static_cast<std::size_t>(r.width_) * r.height_, kNever);
  r.top_.assign(r.floor_.size(), -kNever);
  if (cells_wide >= 2 && cells_high >= 2) {
    // Lowest and highest of each cell and its east neighbour, for this row and the next.
    std::vector<float> pair_min(static_cast<std::size_t>(r.squares_wide_)), pair_max(pair_min.size());
    std::vector<float> next_pair_min(pair_min.size()), next_pair_max(pair_min.size());
    auto row_pairs = [&](int row, std::vector<float>& lo, std::vector<float>& hi) {
      for (int i = 0; i < r.squares_wide_; ++i) {
        const float a = terrain.heightCell(i, row);
        const float b = terrain.heightCell(i + 1, row);
        const bool unknown = std::isnan(a) || std::isnan(b);
        lo[static_cast<std::size_t>(i)] = unknown ? std::numeric_limits<float>::quiet_NaN() : std::min(a, b);
        hi[static_cast<std::size_t>(i)] = unknown ? std::numeric_limits<float>::quiet_NaN() : std::max(a, b);
      }
    };
    row_pairs(0, pair_min, pair_max);
    for (int j = 0; j < r.squares_high_; ++j) {
      row_pairs(j + 1, next_pair_min, next_pair_max);
      float* block_row = &r.floor_[static_cast<std::size_t>(j / pool) * r.width_];
      float* top_row = &r.top_[static_cast<std::size_t>(j / pool) * r.width_];
      for (int i = 0; i < r.squares_wide_; ++i) {
        const std::size_t k = static_cast<std::size_t>(i);
        float& top = top_row[i / pool];
        if (std::isnan(pair_min[k]) || std::isnan(next_pair_min[k])) {
          top = kNever;
          continue;
        }
        float& f = block_row[i / pool];
        f = std::min(f, std::min(pair_min[k], next_pair_min[k]));
        top = std::max(top, std::max(pair_max[k], next_pair_max[k]));
      }
      std::swap(pair_min, next_pair_min);
      std::swap(pair_max, next_pair_max);
    }
  } else if (cells_wide == 1 && cells_high == 1) {
    const float h = terrain.heightCell(0, 0);
    if (!std::isnan(h)) r.floor_[0] = h;
  }

  // Regions: 8-connected flood over the blocks at or below the threshold.
  r.label_.assign(r.floor_.size(), 0);
  std::vector<std::size_t> stack;
  for (std::size_t seed = 0; seed < r.floor_.size(); ++seed) {
    if (r.label_[seed] != 0 || !(r.floor_[seed] <= threshold_m)) continue;
    const std::int32_t region = ++r.regions_;
    r.label_[seed] = region;
    stack.push_back(seed);
    while (!stack.empty()) {
      const std::size_t at = stack.back();
      stack.pop_back();
      forEachNeighbour(at, r.width_, r.height_, [&](int, std::size_t n) {
        if (r.label_[n] != 0 || !(r.floor_[n] <= threshold_m)) return;
        r.label_[n] = region;
        stack.push_back(n);
      });
    }
  }
  return r;
}

std::optional<Eigen::Vector2i> FlyableRegions::blockAt(const Eigen::Vector2d& en_m) const {
  const Eigen::Vector2d px = terrain_->enToPixel(en_m.x(), en_m.y());
  if (!(px.x() >= 0.0 && px.y() >= 0.0 && px.x() <= squares_wide_ && px.y() <= squares_high_)) return std::nullopt;
  // The square holding the point (the last one for a point on the grid's far edge), then its block.
  const int i = std::min(static_cast<int>(px.x()), squares_wide_ - 1);
  const int j = std::min(static_cast<int>(px.y()), squares_high_ - 1);
  return Eigen::Vector2i(i / pool_, j / pool_);
}

bool FlyableRegions::connected(const Eigen::Vector2d& a_en_m, const Eigen::Vector2d& b_en_m) const {
  const auto a = blockAt(a_en_m);
  const auto b = blockAt(b_en_m);
  if (!a || !b) return false;
  const std::int32_t region = regionOf(*a);
  return region != 0 && region == regionOf(*b);
}

bool FlyableRegions::connectedWithin(const Eigen::Vector2d& a_en_m, const Eigen::Vector2d& b_en_m,
                                     const Eigen::AlignedBox2d& box_en_m) const {
  if (!connected(a_en_m, b_en_m)) return false;
  // The box in pixel space: the image of its part inside the DEM's footprint (a box there, so its
  // corners map inside the grid), widened by two cells for the bend of ENU -> pixel along edges.
  const Eigen::AlignedBox2d clipped = box_en_m.intersection(terrain_->boundsEn());
  if (clipped.isEmpty()) return false;
  Eigen::AlignedBox2d px_box;
  for (int c = 0; c < 4; ++c) {
    const Eigen::Vector2d corner = clipped.corner(static_cast<Eigen::AlignedBox2d::CornerType>(c));
    const Eigen::Vector2d px = terrain_->enToPixel(corner.x(), corner.y());
    if (!px.allFinite()) return true;  // cannot tell: say it may be connected
    px_box.extend(px);
  }
  // Blocks whose squares reach into the pixel box.
  const int x0 = std::clamp(static_cast<int>(std::floor(px_box.min().x() - 2.0)) / pool_, 0, width_ - 1);
  const int y0 = std::clamp(static_cast<int>(std::floor(px_box.min().y() - 2.0)) / pool_, 0, height_ - 1);
  const int x1 = std::clamp(static_cast<int>(std::floor(px_box.max().x() + 2.0)) / pool_, 0, width_ - 1);
  const int y1 = std::clamp(static_cast<int>(std::floor(px_box.max().y() + 2.0)) / pool_, 0, height_ - 1);
  const Eigen::Vector2i a = *blockAt(a_en_m);
  const Eigen::Vector2i b = *blockAt(b_en_m);
  auto inside = [&](int x, int y) { return x >= x0 && x <= x1 && y >= y0 && y <= y1; };
  if (!inside(a.x(), a.y()) || !inside(b.x(), b.y())) return false;
  const int w = x1 - x0 + 1;
  std::vector<char> seen(static_cast<std::size_t>(w) * (y1 - y0 + 1), 0);
  auto local = [&](int x, int y) { return static_cast<std::size_t>(y - y0) * w + (x - x0); };
  std::vector<Eigen::Vector2i> stack{a};
  seen[local(a.x(), a.y())] = 1;
  while (!stack.empty()) {
    const Eigen::Vector2i at = stack.back();
    stack.pop_back();
    if (at == b) return true;
    for (int k = 0; k < 8; ++k) {
      const int nx = at.x() + kNeighbourDx[k], ny = at.y() + kNeighbourDy[k];
      if (!inside(nx, ny) || seen[local(nx, ny)]) continue;
      seen[local(nx, ny)] = 1;
      if (!flyable(static_cast<std::size_t>(ny) * width_ + nx)) continue;
      stack.emplace_back(nx, ny);
    }
  }
  return false;
}

std::optional<double> FlyableRegions::lowestConnectingGroundM(const Eigen::Vector2d& a_en_m,
                                                              const Eigen::Vector2d& b_en_m) const {
  const auto a = blockAt(a_en_m);
  const auto b = blockAt(b_en_m);
  if (!a || !b) return std::nullopt;
  const std::size_t start = index(*a), goal = index(*b);
  if (!std::isfinite(floor_[start]) || !std::isfinite(floor_[goal])) return std::nullopt;
  // Priority flood: blocks in the order of the lowest bottleneck that reaches them; each is
  // settled once, so the work is at most the blocks (a few hundred milliseconds on a 1-arc-second
  // tile at most, and it stops at the goal).
  std::vector<float> best(floor_.size(), kNever);
  using Entry = std::pair<float, std::size_t>;
  std::priority_queue<Entry, std::vector<Entry>, std::greater<>> open;
  best[start] = floor_[start];
  open.emplace(best[start], start);
  while (!open.empty()) {
    const auto [value, at] = open.top();
    open.pop();
    if (value > best[at]) continue;
    if (at == goal) return static_cast<double>(value);
    forEachNeighbour(at, width_, height_, [&, value = value](int, std::size_t n) {
      const float through = std::max(value, floor_[n]);
      if (!(through < best[n])) return;  // also skips unknown blocks (+inf)
      best[n] = through;
      open.emplace(through, n);
    });
  }
  return std::nullopt;
}

std::vector<std::size_t> FlyableRegions::wayBlocks(const Eigen::Vector2d& a_en_m, const Eigen::Vector2d& b_en_m) const {
  if (!connected(a_en_m, b_en_m)) return {};
  const Eigen::Vector2i a = *blockAt(a_en_m);
  const Eigen::Vector2i b = *blockAt(b_en_m);
  const std::size_t start = index(a), goal = index(b);
  const double ex = block_east_m_, ny_m = block_north_m_;
  auto heuristic = [&](std::size_t i) {
    const double dx = static_cast<double>(static_cast<int>(i % width_) - b.x()) * ex;
    const double dy = static_cast<double>(static_cast<int>(i / width_) - b.y()) * ny_m;
    return std::hypot(dx, dy);
  };
  constexpr double kInf = std::numeric_limits<double>::infinity();
  std::vector<double> cost(floor_.size(), kInf);
  std::vector<std::int32_t> parent(floor_.size(), -1);
  using Entry = std::pair<double, std::size_t>;
  std::priority_queue<Entry, std::vector<Entry>, std::greater<>> open;
  cost[start] = 0.0;
  open.emplace(heuristic(start), start);
  bool reached = false;
  while (!open.empty()) {
    const auto [f, at] = open.top();
    open.pop();
    if (f > cost[at] + heuristic(at) + 1e-9) continue;
    if (at == goal) {
      reached = true;
      break;
    }
    forEachNeighbour(at, width_, height_, [&, at = at](int k, std::size_t n) {
      if (!flyable(n)) return;
      // Blocks flyable throughout are preferred: a block flyable only in part may hold no way
      // through (its low squares need not touch the next block's), so it costs more to cross.
      const double doubt = top_[n] <= threshold_m_ ? 1.0 : kDoubtfulBlockCost;
      const double g = cost[at] + doubt * std::hypot(kNeighbourDx[k] * ex, kNeighbourDy[k] * ny_m);
      if (!(g < cost[n])) return;
      cost[n] = g;
      parent[n] = static_cast<std::int32_t>(at);
      open.emplace(g + heuristic(n), n);
    });
  }
  std::vector<std::size_t> way;
  if (!reached) return way;
  for (std::int64_t at = static_cast<std::int64_t>(goal); at >= 0; at = parent[static_cast<std::size_t>(at)]) {
    way.push_back(static_cast<std::size_t>(at));
    if (static_cast<std::size_t>(at) == start) break;
  }
  return way;
}

Eigen::Vector2i FlyableRegions::lowestCell(std::size_t block) const {
  const int col0 = static_cast<int>(block % static_cast<std::size_t>(width_)) * pool_;
  const int row0 = static_cast<int>(block / static_cast<std::size_t>(width_)) * pool_;
  const int cols = terrain_->dem().width(), rows = terrain_->dem().height();
  Eigen::Vector2i lowest(col0, row0);
  float lowest_m = std::numeric_limits<float>::infinity();
  for (int row = row0; row <= std::min(row0 + pool_, rows - 1); ++row) {
    for (int col = col0; col <= std::min(col0 + pool_, cols - 1); ++col) {
      const float h = terrain_->heightCell(col, row);
      if (h < lowest_m) {  // false for unknown (NaN) cells
        lowest_m = h;
        lowest = Eigen::Vector2i(col, row);
      }
    }
  }
  return lowest;
}

std::vector<Eigen::Vector3d> FlyableRegions::shortestWay(const Eigen::Vector2d& a_en_m,
                                                         const Eigen::Vector2d& b_en_m) const {
  const std::vector<std::size_t> blocks = wayBlocks(a_en_m, b_en_m);
  std::vector<Eigen::Vector3d> way;
  way.reserve(blocks.size());
  for (auto it = blocks.rbegin(); it != blocks.rend(); ++it) {
    double x = std::min<double>(static_cast<double>(*it % width_) * pool_ + 0.5 * pool_, squares_wide_);
    double y = std::min<double>(static_cast<double>(*it / width_) * pool_ + 0.5 * pool_, squares_high_);
    // A block flyable only in part is passed where it is flyable: at its lowest grid point (the
    // centre may lie under ground above the threshold).
    if (!(top_[*it] <= threshold_m_)) {
      const Eigen::Vector2i low = lowestCell(*it);
      x = low.x();
      y = low.y();
    }
    const Eigen::Vector2d en = terrain_->pixelToEn(x, y);
    if (en.allFinite()) way.emplace_back(en.x(), en.y(), static_cast<double>(floor_[*it]));
  }
  return way;
}

std::vector<Eigen::Vector2d> FlyableRegions::gridWay(const Eigen::Vector2d& a_en_m, const Eigen::Vector2d& b_en_m,
                                                     double max_ground_m) const {
  if (!connected(a_en_m, b_en_m)) return {};
  const int cols = terrain_->dem().width(), rows = terrain_->dem().height();
  auto low = [&](int col, int row) {
    // Not on the grid's outer edge: a point there is on the terrain's border, which the world's
    // checks may count as outside.
    if (col < 1 || row < 1 || col >= cols - 1 || row >= rows - 1) return false;
    return terrain_->heightCell(col, row) <= max_ground_m;  // false for unknown
  };
  const Eigen::Vector2d a_px = terrain_->enToPixel(a_en_m.x(), a_en_m.y());
  const Eigen::Vector2d b_px = terrain_->enToPixel(b_en_m.x(), b_en_m.y());
  if (!a_px.allFinite() || !b_px.allFinite()) return {};
  auto corners = [&](const Eigen::Vector2d& px) {
    const int i = std::clamp(static_cast<int>(px.x()), 0, std::max(0, cols - 2));
    const int j = std::clamp(static_cast<int>(px.y()), 0, std::max(0, rows - 2));
    std::vector<std::size_t> out;
    for (int dj = 0; dj <= 1; ++dj)
      for (int di = 0; di <= 1; ++di)
        if (low(i + di, j + dj)) out.push_back(static_cast<std::size_t>(j + dj) * cols + (i + di));
    return out;
  };
  const std::vector<std::size_t> sources = corners(a_px), targets = corners(b_px);
  if (sources.empty() || targets.empty()) return {};
  // A* over the grid points (as many entries as the DEM has cells: the world holds several such
  // arrays already). The ground between two low points side by side is linear, so at most the
  // higher of them; a diagonal crosses a square, whose bilinear surface is at most its highest
  // corner.
  const Eigen::Vector2d cell_m = terrain_->dem().resolutionM().cwiseAbs();
  auto heuristic = [&](std::size_t at) {
    const double col = static_cast<double>(at % static_cast<std::size_t>(cols));
    const double row = static_cast<double>(at / static_cast<std::size_t>(cols));
    return std::hypot((col - b_px.x()) * cell_m.x(), (row - b_px.y()) * cell_m.y());
  };
  constexpr float kUnreached = std::numeric_limits<float>::infinity();
  const std::size_t cells = static_cast<std::size_t>(cols) * static_cast<std::size_t>(rows);
  std::vector<float> cost(cells, kUnreached);
  std::vector<std::int32_t> parent(cells, -1);
  std::vector<char> goal(cells, 0);
  for (const std::size_t t : targets) goal[t] = 1;
  using Entry = std::pair<double, std::size_t>;
  std::priority_queue<Entry, std::vector<Entry>, std::greater<>> open;
  for (const std::size_t s : sources) {
    cost[s] = 0.0f;
    parent[s] = static_cast<std::int32_t>(s);
    open.emplace(heuristic(s), s);
  }
  std::optional<std::size_t> reached;
  while (!open.empty()) {
    const auto [f, at] = open.top();
    open.pop();
    if (f > cost[at] + heuristic(at) + 1e-3) continue;
    if (goal[at]) {
      reached = at;
      break;
    }
    const int col = static_cast<int>(at % static_cast<std::size_t>(cols));
    const int row = static_cast<int>(at / static_cast<std::size_t>(cols));
    for (int d = 0; d < 8; ++d) {
      const int nc = col + kNeighbourDx[d], nr = row + kNeighbourDy[d];
      if (!low(nc, nr)) continue;
      if (d >= 4 && !(low(nc, row) && low(col, nr))) continue;  // a diagonal: the square's other corners
      const std::size_t n = static_cast<std::size_t>(nr) * cols + nc;
      const float g = cost[at] + static_cast<float>(std::hypot(kNeighbourDx[d] * cell_m.x(), kNeighbourDy[d] * cell_m.y()));
      if (!(g < cost[n])) continue;
      cost[n] = g;
      parent[n] = static_cast<std::int32_t>(at);
      open.emplace(g + heuristic(n), n);
    }
  }
  if (!reached) return {};
  std::vector<Eigen::Vector2i> way_cells;
  for (std::size_t at = *reached;; at = static_cast<std::size_t>(parent[at])) {
    way_cells.emplace_back(static_cast<int>(at % static_cast<std::size_t>(cols)), static_cast<int>(at / static_cast<std::size_t>(cols)));
    if (static_cast<std::size_t>(parent[at]) == at) break;
  }
  std::reverse(way_cells.begin(), way_cells.end());
  std::vector<Eigen::Vector2d> way;
  for (std::size_t i = 0; i < way_cells.size(); ++i) {
    // Keep the ends and every turn.
    if (i > 0 && i + 1 < way_cells.size() && way_cells[i] - way_cells[i - 1] == way_cells[i + 1] - way_cells[i]) continue;
    const Eigen::Vector2d en = terrain_->pixelToEn(way_cells[i].x(), way_cells[i].y());
    if (!en.allFinite()) return {};
    way.push_back(en);
  }
  return way;
}

std::optional<Eigen::AlignedBox2d> FlyableRegions::shortestWayBox(const Eigen::Vector2d& a_en_m,
                                                                  const Eigen::Vector2d& b_en_m) const {
  const std::vector<std::size_t> way = wayBlocks(a_en_m, b_en_m);
  if (way.empty()) return std::nullopt;
  // The way's extent in pixels (a block spans pool squares from its first), then in ENU through
  // the box's corners, with the two points themselves.
  Eigen::AlignedBox2d px_box;
  for (const std::size_t at : way) {
    const double x = static_cast<double>(at % width_) * pool_;
    const double y = static_cast<double>(at / width_) * pool_;
    px_box.extend(Eigen::Vector2d(x, y));
    px_box.extend(Eigen::Vector2d(std::min<double>(x + pool_, squares_wide_), std::min<double>(y + pool_, squares_high_)));
  }
  Eigen::AlignedBox2d en_box;
  en_box.extend(a_en_m);
  en_box.extend(b_en_m);
  for (int c = 0; c < 4; ++c) {
    const Eigen::Vector2d px = px_box.corner(static_cast<Eigen::AlignedBox2d::CornerType>(c));
    const Eigen::Vector2d en = terrain_->pixelToEn(px.x(), px.y());
    if (en.allFinite()) en_box.extend(en);
  }
  return en_box;
}

}  // namespace skyroute
