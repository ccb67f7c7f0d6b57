// The sweep-line simplicity check (terrain/ring_simplicity.hpp) against the quadratic check the
// no-fly zones used before it (every pair of edges), on many seeded random rings: small integer
// grids (repeated vertices, touching, collinear overlaps everywhere), star-shaped rings with one
// vertex moved, and nearly-degenerate rings far from the origin (vertices one grid step off a
// line). Both use the same exact predicates, so they must agree on every ring; each defect the
// sweep names is checked to be one.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <optional>
#include <random>
#include <vector>

#include <gtest/gtest.h>

#include "terrain/ring_simplicity.hpp"
#include "tests/terrain/ring_by_every_pair.hpp"

namespace skyroute {
namespace {

using Ring = std::vector<RingGridPoint>;
using testing::simpleByEveryPair;

// The defect the sweep names is one: the same point twice, a fold, or two edges that are not
// consecutive and meet.
void expectRealDefect(const Ring& ring, const RingDefect& d) {
  const std::size_t n = ring.size();
  ASSERT_LT(d.first, d.second);
  ASSERT_LT(d.second, n);
  switch (d.kind) {
    case RingDefect::Kind::kRepeatedVertex:
      EXPECT_EQ(ring[d.first], ring[d.second]);
      break;
    case RingDefect::Kind::kFoldingEdges: {
      EXPECT_TRUE(d.second == d.first + 1 || (d.first == 0 && d.second == n - 1));
      const std::size_t i = d.second == d.first + 1 ? d.first : d.second;  // the edge whose end is shared
      const RingGridPoint &a = ring[i], &b = ring[(i + 1) % n], &c = ring[(i + 2) % n];
      EXPECT_EQ(ringOrientation(a, b, c), 0);
      break;
    }
    case RingDefect::Kind::kCrossingEdges:
      EXPECT_FALSE(d.second == d.first + 1 || (d.first == 0 && d.second == n - 1)) << d.first << " " << d.second;
      EXPECT_TRUE(ringSegmentsMeet(ring[d.first], ring[(d.first + 1) % n], ring[d.second], ring[(d.second + 1) % n]));
      break;
  }
}

// Runs both checks; the count of rings each verdict got, so a test can show it exercised both.
struct Verdicts {
  int simple = 0;
  int defective = 0;
};

void compare(const Ring& ring, Verdicts& verdicts) {
  const std::optional<RingDefect> defect = findRingDefect(ring);
  const bool reference = simpleByEveryPair(ring);
  if (!defect.has_value() != reference) {
    std::string text;
    for (const RingGridPoint& p : ring) text += "(" + std::to_string(p.x) + "," + std::to_string(p.y) + ") ";
    FAIL() << "sweep says " << (defect ? "defective" : "simple") << ", every pair says "
           << (reference ? "simple" : "defective") << ": " << text;
  }
  if (defect) {
    expectRealDefect(ring, *defect);
    ++verdicts.defective;
  } else {
    ++verdicts.simple;
  }
}

// A ring round the origin: n vertices at increasing angles (simple by construction).
Ring starRing(std::mt19937_64& rng, std::size_t n, double radius) {
  std::uniform_real_distribution<double> angle(0.0, 2.0 * M_PI), r(0.2 * radius, radius);
  std::vector<double> angles(n);
  for (double& a : angles) a = angle(rng);
  std::sort(angles.begin(), angles.end());
  Ring ring;
  for (double a : angles) {
    const double rr = r(rng);
    ring.push_back(RingGridPoint{std::llround(rr * std::cos(a)), std::llround(rr * std::sin(a))});
  }
  return ring;
}

TEST(RingSimplicity, AgreesWithEveryPairOnSmallGrids) {
  // Few places for many vertices: repeated vertices, a vertex on another edge, edges on one line.
  std::mt19937_64 rng(20260425);
  Verdicts verdicts;
  for (int grid : {2, 3, 4, 6, 10}) {
    std::uniform_int_distribution<std::int64_t> coordinate(0, grid);
    for (int trial = 0; trial < 40000; ++trial) {
      const std::size_t n = 3 + static_cast<std::size_t>(trial % 10);
      Ring ring(n);
      for (RingGridPoint& p : ring) p = RingGridPoint{coordinate(rng), coordinate(rng)};
      compare(ring, verdicts);
      if (HasFatalFailure()) return;
    }
  }
  EXPECT_GT(verdicts.simple, 5000);
  EXPECT_GT(verdicts.defective, 5000);
}

TEST(RingSimplicity, AgreesWithEveryPairOnStarsWithOneVertexMoved) {
  std::mt19937_64 rng(7);
  Verdicts verdicts;
  for (int trial = 0; trial < 4000; ++trial) {
    const std::size_t n = 3 + static_cast<std::size_t>(trial % 120);
    Ring ring = starRing(rng, n, 1000.0);
    compare(ring, verdicts);
    // Moved anywhere, or onto another vertex, or onto the middle of another edge (touching).
    std::uniform_int_distribution<std::size_t> pick(0, n - 1);
    const std::size_t k = pick(rng), other = pick(rng);
    Ring moved = ring;
    switch (trial % 3) {
      case 0:
        moved[k] = RingGridPoint{std::uniform_int_distribution<std::int64_t>(-1000, 1000)(rng),
                                 std::uniform_int_distribution<std::int64_t>(-1000, 1000)(rng)};
        break;
      case 1:
        moved[k] = ring[other];
        break;
      default: {
        const RingGridPoint& a = ring[other];
        const RingGridPoint& b = ring[(other + 1) % n];
        if ((a.x + b.x) % 2 == 0 && (a.y + b.y) % 2 == 0) moved[k] = RingGridPoint{(a.x + b.x) / 2, (a.y + b.y) / 2};
        break;
      }
    }
    compare(moved, verdicts);
    if (HasFatalFailure()) return;
  }
  EXPECT_GT(verdicts.simple, 1000);
  EXPECT_GT(verdicts.defective, 1000);
}

TEST(RingSimplicity, AgreesWithEveryPairOnNearlyDegenerateRingsFarAway) {
  // Vertices along a long line 1e7 m (1e13 grid steps) from the origin, each 0, 1 or 2 steps off
  // it: orientations of nearly collinear points, which only exact arithmetic gets right.
  std::mt19937_64 rng(3);
  Verdicts verdicts;
  const std::int64_t far = 10'000'000'000'000;
  for (int trial = 0; trial < 20000; ++trial) {
    const std::size_t n = 3 + static_cast<std::size_t>(trial % 9);
    std::uniform_int_distribution<std::int64_t> along(0, 6), off(-2, 2);
    const std::int64_t dx = 1'000'003, dy = 999'983;  // the line's direction
    Ring ring(n);
    for (RingGridPoint& p : ring) {
      const std::int64_t t = along(rng);
      p = RingGridPoint{far + t * dx + off(rng), far + t * dy + off(rng)};
    }
    compare(ring, verdicts);
    if (HasFatalFailure()) return;
  }
  EXPECT_GT(verdicts.simple, 500);
  EXPECT_GT(verdicts.defective, 500);
}

TEST(RingSimplicity, NamesEachKindOfDefect) {
  const Ring square{{0, 0}, {10, 0}, {10, 10}, {0, 10}};
  EXPECT_FALSE(findRingDefect(square));
  const Ring bow{{0, 0}, {10, 10}, {10, 0}, {0, 10}};
  auto d = findRingDefect(bow);
  ASSERT_TRUE(d);
  EXPECT_EQ(d->kind, RingDefect::Kind::kCrossingEdges);
  EXPECT_EQ(d->first, 0u);
  EXPECT_EQ(d->second, 2u);
  const Ring repeated{{0, 0}, {10, 0}, {5, 5}, {10, 10}, {0, 10}, {5, 5}};
  d = findRingDefect(repeated);
  ASSERT_TRUE(d);
  EXPECT_EQ(d->kind, RingDefect::Kind::kRepeatedVertex);
  EXPECT_EQ(d->first, 2u);
  EXPECT_EQ(d->second, 5u);
  const Ring folded{{0, 0}, {10, 0}, {5, 0}, {5, 10}};
  d = findRingDefect(folded);
  ASSERT_TRUE(d);
  EXPECT_EQ(d->kind, RingDefect::Kind::kFoldingEdges);
  const Ring touching{{0, 0}, {10, 0}, {10, 10}, {5, 0}, {0, 10}};  // vertex 3 on edge 0
  d = findRingDefect(touching);
  ASSERT_TRUE(d);
  EXPECT_EQ(d->kind, RingDefect::Kind::kCrossingEdges);
  // Collinear vertices that go on in one direction are allowed.
  const Ring straight_on{{0, 0}, {5, 0}, {10, 0}, {10, 10}, {0, 10}};
  EXPECT_FALSE(findRingDefect(straight_on));
  const Ring vertical_edges{{0, 0}, {0, 5}, {0, 10}, {-10, 10}, {-10, 0}};
  EXPECT_FALSE(findRingDefect(vertical_edges));
}

TEST(RingSimplicity, GridRefusesWhatIsNotOnEarth) {
  const std::vector<Eigen::Vector2d> ok{{0.0, 0.0}, {1.5e-6, 0.0}, {0.0, -2e7}};
  const auto grid = ringOnGrid(ok);
  ASSERT_TRUE(grid);
  EXPECT_EQ((*grid)[1].x, 2);  // 1.5 µm rounds to 2 steps
  EXPECT_EQ((*grid)[2].y, -20'000'000'000'000);
  EXPECT_FALSE(ringOnGrid(std::vector<Eigen::Vector2d>{{0.0, 0.0}, {2e8, 0.0}, {0.0, 1.0}}));
  EXPECT_FALSE(ringOnGrid(std::vector<Eigen::Vector2d>{{0.0, 0.0}, {NAN, 0.0}, {0.0, 1.0}}));
}

TEST(RingSimplicity, TenThousandVerticesTakeAFewMilliseconds) {
  // The bound of a zone's ring: a star of 10,000 vertices, simple, and the same with its last
  // vertex moved out beyond the far side (its edges cross the ring there). Measured and printed,
  // not held to a deadline.
  std::mt19937_64 rng(11);
  Ring ring = starRing(rng, 10000, 1e9);
  const auto start = std::chrono::steady_clock::now();
  EXPECT_FALSE(findRingDefect(ring));
  ring.back() = RingGridPoint{-2'000'000'000, 0};
  EXPECT_TRUE(findRingDefect(ring));
  const double took_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  RecordProperty("two_checks_of_10000_vertices_ms", std::to_string(took_s * 1e3));
  std::printf("two checks of 10,000 vertices: %.1f ms\n", took_s * 1e3);
}

}  // namespace
}  // namespace skyroute
