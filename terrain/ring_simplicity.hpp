// Whether a polygon's ring is simple, in O(n log n): no two of its edges meet, except consecutive
// edges at the one vertex they share. A sweep line over the edges (Shamos and Hoey): the edges the
// line crosses are kept in their order along it, and only edges that become neighbours in that
// order are tested against each other, since the first meeting point of two edges is reached
// while they are neighbours. Before the sweep, a sort finds repeated vertices and one pass finds
// consecutive edges that fold back onto each other, so the sweep meets only distinct vertices.
//
// Every test is exact: the check works on the vertices rounded to a grid of kRingGridM (1 µm) as
// integers, with orientations computed in 128-bit integers. Touching, collinear overlaps and
// nearly-degenerate rings get the same verdict however the edges are ordered, and no rounding can
// let the sweep lose its order. The zone check (no_fly_zone.hpp) uses it on rings in metres.
#pragma once

#include <compare>
#include <cstddef>
#include <cstdint>
#include <optional>
#include <span>
#include <vector>

#include <Eigen/Core>

namespace skyroute {

// The grid the ring is checked on, and how far from the frame's origin a vertex may lie: a local
// frame reaches half the Earth's circumference (2e7 m), and 1e8 m on a 1 µm grid keeps every
// product of the orientation test (at most 8e28) well inside 128 bits.
inline constexpr double kRingGridM = 1e-6;
inline constexpr double kRingMaxCoordinateM = 1e8;

struct RingGridPoint {
  std::int64_t x = 0;
  std::int64_t y = 0;
  auto operator<=>(const RingGridPoint&) const = default;  // lexicographic: x, then y
};

struct RingDefect {
  enum class Kind {
    kRepeatedVertex,  // vertices `first` and `second` are the same point
    kFoldingEdges,    // consecutive edges `first` and `second` overlap (the ring folds back)
    kCrossingEdges,   // edges `first` and `second`, not consecutive, meet (cross, touch or overlap)
  };
  Kind kind = Kind::kCrossingEdges;
  std::size_t first = 0;   // vertex or edge index; edge i runs from vertex i to vertex i + 1 (mod n)
  std::size_t second = 0;  // first < second
};

// +1 when r lies left of the line p -> q, -1 right of it, 0 on it. Exact.
int ringOrientation(const RingGridPoint& p, const RingGridPoint& q, const RingGridPoint& r);
// The closed segments a1-a2 and b1-b2 share a point. Exact.
bool ringSegmentsMeet(const RingGridPoint& a1, const RingGridPoint& a2, const RingGridPoint& b1,
                      const RingGridPoint& b2);

// The ring on the grid: nullopt when a coordinate is not finite or lies beyond kRingMaxCoordinateM.
std::optional<std::vector<RingGridPoint>> ringOnGrid(std::span<const Eigen::Vector2d> ring_m);

// A defect of the ring (open: its last vertex is not its first again; at least 3 vertices), or
// nullopt when it is simple. O(n log n) time, O(n) memory. Which defect is named when there are
// several is the first the sweep meets.
std::optional<RingDefect> findRingDefect(std::span<const RingGridPoint> ring);

}  // namespace skyroute
