// The grid's move rules, written once for every search on a GridLayer.
// 8-connected (A*, Dijkstra, D* Lite, MMD*L, Theta*, HAB-PP's fields): a straight move costs 1, a
// diagonal move `diagonal_cost` (sqrt(2) by default, the Moving AI convention; 1.4 in the MMD*L
// paper), and a diagonal move needs both orthogonal neighbours passable (no corner cutting), so
// every move is symmetric: c(a, b) = c(b, a). With these rules optimal costs match the Moving AI
// .scen files. 4-connected (the fleet's steps, seed 002): kFourMoves.
#pragma once

#include <array>
#include <cmath>
#include <cstdint>
#include <limits>
#include <numbers>
#include <span>
#include <vector>

#include "terrain/grid_layer.hpp"

namespace skyroute {

inline constexpr double kInfiniteCost = std::numeric_limits<double>::infinity();

struct GridMoves {
  enum class Heuristic {
    kOctile,     // exact distance on an empty grid: straight + diagonal_cost * diagonal steps
    kChebyshev,  // max(|dx|, |dy|), the paper's choice (eq. 4): cheaper, weaker
  };
  double diagonal_cost = std::numbers::sqrt2;
  Heuristic heuristic = Heuristic::kOctile;
  // false (the project's rule, above): a diagonal move needs both orthogonal neighbours free.
  // true: only its two ends must be free, as in the seed's simulation (section IV), where c(s, s')
  // is infinite only when s or s' is an obstacle.
  bool corner_cutting = false;

  // The paper's rules: diagonal 1.4, Chebyshev heuristic.
  static GridMoves paper() { return GridMoves{1.4, Heuristic::kChebyshev}; }

  // Admissible and consistent for these moves (diagonal_cost >= 1).
  double estimate(GridCell a, GridCell b) const {
    const int dx = std::abs(a.x - b.x);
    const int dy = std::abs(a.y - b.y);
    const int lo = dx < dy ? dx : dy;
    const int hi = dx < dy ? dy : dx;
    if (heuristic == Heuristic::kChebyshev) return hi;
    return (hi - lo) + diagonal_cost * lo;
  }
};

struct GridOffset {
  int dx = 0;
  int dy = 0;
};
// The 8 moves: the 4 straight ones first.
inline constexpr std::array<GridOffset, 8> kGridOffsets{{
    {1, 0}, {-1, 0}, {0, 1}, {0, -1}, {1, 1}, {1, -1}, {-1, 1}, {-1, -1}}};

// The 4-connected steps of the fleet planner (seed 002, eq. 6: one step to a side neighbour, or
// wait), in a fixed order (east, north, west, south): every tie of the step searches is broken by
// this order, so results are deterministic.
inline constexpr GridCell kFourMoves[4] = {{1, 0}, {0, 1}, {-1, 0}, {0, -1}};

// Cost of the move from `a` by `d` (one of kGridOffsets); infinity when either end is blocked or
// outside, or when a diagonal move would cut a blocked corner.
inline double moveCost(const GridLayer& grid, GridCell a, GridOffset d, const GridMoves& moves) {
  const GridCell b{a.x + d.dx, a.y + d.dy};
  if (grid.blocked(a) || grid.blocked(b)) return kInfiniteCost;
  if (d.dx != 0 && d.dy != 0) {
    if (!moves.corner_cutting && (grid.blocked(GridCell{a.x + d.dx, a.y}) || grid.blocked(GridCell{a.x, a.y + d.dy}))) return kInfiniteCost;
    return moves.diagonal_cost;
  }
  return 1.0;
}

// Calls f(neighbour, cost) for every allowed move out of `a`.
template <class F>
void forEachMove(const GridLayer& grid, GridCell a, const GridMoves& moves, F&& f) {
  for (const GridOffset& d : kGridOffsets) {
    const double c = moveCost(grid, a, d, moves);
    if (c < kInfiniteCost) f(GridCell{a.x + d.dx, a.y + d.dy}, c);
  }
}

// The allowed moves of every cell as a bit mask (bit k: kGridOffsets[k]), for the incremental
// searches: their inner loops then walk neighbours by flat index, with no bounds or corner tests.
// It follows the grid through the changed cells the searches are told about (update), and rebuilds
// itself when the grid changed behind its back (sync, by GridLayer::version).
class GridMoveTable {
 public:
  GridMoveTable(const GridLayer& grid, const GridMoves& moves);

  const GridLayer& grid() const { return *grid_; }
  const GridMoves& moves() const { return moves_; }
  std::uint8_t mask(std::size_t i) const { return mask_[i]; }
  // Index offset and cost of move k.
  std::ptrdiff_t delta(int k) const { return delta_[k]; }
  double cost(int k) const { return cost_[k]; }

  // Refreshes the masks of the 3x3 neighbourhood of every changed cell (a move's cost depends only
  // on cells in its start's 3x3 block), once per grid version however many searches ask.
  void update(std::span<const GridCell> changed);
  // Full rebuild when the grid's version moved without an update().
  void sync() {
    if (version_ != grid_->version()) rebuild();
  }

 private:
  void rebuild();
  void refresh(GridCell c);

  const GridLayer* grid_;
  GridMoves moves_;
  std::vector<std::uint8_t> mask_;
  std::array<std::ptrdiff_t, 8> delta_{};
  std::array<double, 8> cost_{};
  std::uint64_t version_ = 0;
};

}  // namespace skyroute
