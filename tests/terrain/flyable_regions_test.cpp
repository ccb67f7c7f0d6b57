// FlyableRegions against synthetic terrains: a ridge with a pass and a closed one, unknown
// terrain, the lowest connecting ground against a brute-force search over thresholds, and the
// soundness of "not connected" against the world's own exact segment checks on hilly terrain with
// pooled blocks (a valid straight flight between two points must never be called impossible).
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <limits>
#include <numeric>
#include <set>
#include <vector>

#include <gtest/gtest.h>

#include "terrain/flyable_regions.hpp"
#include "terrain/terrain_generator.hpp"
#include "tests/ridge_terrain.hpp"

namespace skyroute {
namespace {

using testing::RidgeSpec;

Eigen::Vector2d cellEn(const Heightfield& hf, double col, double row) { return hf.pixelToEn(col, row); }

// Hilly generated terrain, kHillySize cells each way of 30 m.
constexpr int kHillySize = 120;
std::vector<float> hillyHeights(std::uint64_t seed) {
  TerrainGeneratorOptions g;
  g.width = kHillySize;
  g.height = kHillySize;
  g.cell_size_m = 30.0;
  g.seed = seed;
  return generateTerrainHeights(g);
}

// Seeded uniform numbers in [lo, hi) (a 64-bit LCG: the same sequence on every platform).
class Uniform {
 public:
  explicit Uniform(std::uint64_t seed) : state_(seed) {}
  double operator()(double lo, double hi) {
    state_ = state_ * 6364136223846793005ULL + 1442695040888963407ULL;
    return lo + (hi - lo) * static_cast<double>(state_ >> 11) * 0x1.0p-53;
  }

 private:
  std::uint64_t state_;
};

TEST(FlyableRegions, ARidgeWithAPassIsConnectedOnlyThroughThePass) {
  RidgeSpec spec;
  spec.pass_first_row = 40;
  spec.pass_last_row = 47;
  spec.pass_m = 200.0;
  const auto w = testing::ridgeWorld(spec, 330.0);  // threshold 300: the pass is flyable, the ridge not
  ASSERT_TRUE(w.world);
  const FlyableRegions& regions = w.world->flyableRegions();
  EXPECT_EQ(regions.pool(), 1);
  EXPECT_DOUBLE_EQ(regions.thresholdM(), 300.0);
  EXPECT_EQ(regions.regionCount(), 1);
  const Eigen::Vector2d west = cellEn(*w.terrain, 10, 10), east = cellEn(*w.terrain, 50, 10);
  EXPECT_TRUE(regions.connected(west, east));
  EXPECT_TRUE(regions.connected(east, west));
  // A box over the northern rows only leaves out the pass.
  Eigen::AlignedBox2d north;
  north.extend(cellEn(*w.terrain, 0, 0));
  north.extend(cellEn(*w.terrain, 59, 25));
  EXPECT_FALSE(regions.connectedWithin(west, east, north));
  Eigen::AlignedBox2d all = north;
  all.extend(cellEn(*w.terrain, 59, 59));
  EXPECT_TRUE(regions.connectedWithin(west, east, all));
  // The shortest way goes through the pass: its box reaches the pass rows but not the south edge.
  const auto way = regions.shortestWayBox(west, east);
  ASSERT_TRUE(way);
  EXPECT_TRUE(way->contains(cellEn(*w.terrain, 30, 40)));
  EXPECT_FALSE(way->contains(cellEn(*w.terrain, 30, 55)));
  EXPECT_TRUE(way->contains(west) && way->contains(east));
}

TEST(FlyableRegions, AClosedRidgeSeparatesAndNamesThePassHeight) {
  RidgeSpec spec;
  spec.pass_first_row = 40;
  spec.pass_last_row = 47;
  spec.pass_m = 500.0;
  const auto w = testing::ridgeWorld(spec, 330.0);
  ASSERT_TRUE(w.world);
  const FlyableRegions& regions = w.world->flyableRegions();
  EXPECT_EQ(regions.regionCount(), 2);
  const Eigen::Vector2d west = cellEn(*w.terrain, 10, 10), east = cellEn(*w.terrain, 50, 10);
  EXPECT_FALSE(regions.connected(west, east));
  EXPECT_FALSE(regions.shortestWayBox(west, east));
  EXPECT_TRUE(regions.connected(west, cellEn(*w.terrain, 5, 58)));
  const auto lowest = regions.lowestConnectingGroundM(west, east);
  ASSERT_TRUE(lowest);
  EXPECT_DOUBLE_EQ(*lowest, 500.0);
  // The same world's labelling is made once.
  EXPECT_EQ(&w.world->flyableRegions(), &regions);
}

TEST(FlyableRegions, UnknownTerrainBlocksAtAnyHeight) {
  RidgeSpec spec;
  spec.void_ridge = true;
  const auto closed = testing::ridgeWorld(spec, 1e9);  // no ceiling at all
  ASSERT_TRUE(closed.world);
  const Eigen::Vector2d west = cellEn(*closed.terrain, 10, 10), east = cellEn(*closed.terrain, 50, 10);
  EXPECT_FALSE(closed.world->flyableRegions().connected(west, east));
  EXPECT_FALSE(closed.world->flyableRegions().lowestConnectingGroundM(west, east));
  spec.pass_first_row = 50;
  spec.pass_last_row = 53;
  const auto open = testing::ridgeWorld(spec, 1e9);
  ASSERT_TRUE(open.world);
  EXPECT_TRUE(open.world->flyableRegions().connected(west, east));
  // Outside the grid is never flyable.
  EXPECT_FALSE(open.world->flyableRegions().connected(west, Eigen::Vector2d(1e7, 1e7)));
}

// Brute force on the squares of the DEM (pool 1): a square is as low as its lowest corner and
// none with an unknown one; for each candidate threshold in increasing order, flood the squares at
// or below it from a's square and see whether b's is reached.
std::optional<double> bruteForceLowestGround(const Heightfield& hf, int w, int h, Eigen::Vector2i a, Eigen::Vector2i b) {
  const int sw = w - 1, sh = h - 1;
  std::vector<double> square(static_cast<std::size_t>(sw) * sh, std::numeric_limits<double>::infinity());
  std::set<double> candidates;
  for (int j = 0; j < sh; ++j) {
    for (int i = 0; i < sw; ++i) {
      const double c[4] = {hf.heightCell(i, j), hf.heightCell(i + 1, j), hf.heightCell(i, j + 1), hf.heightCell(i + 1, j + 1)};
      bool unknown = false;
      for (double v : c) unknown = unknown || std::isnan(v);
      if (unknown) continue;
      square[static_cast<std::size_t>(j) * sw + i] = *std::min_element(c, c + 4);
      candidates.insert(square[static_cast<std::size_t>(j) * sw + i]);
    }
  }
  for (double t : candidates) {
    std::vector<char> seen(square.size(), 0);
    std::vector<Eigen::Vector2i> todo;
    if (!(square[static_cast<std::size_t>(a.y()) * sw + a.x()] <= t)) continue;
    todo.push_back(a);
    seen[static_cast<std::size_t>(a.y()) * sw + a.x()] = 1;
    while (!todo.empty()) {
      const Eigen::Vector2i p = todo.back();
      todo.pop_back();
      if (p == b) return t;
      for (int dy = -1; dy <= 1; ++dy) {
        for (int dx = -1; dx <= 1; ++dx) {
          const Eigen::Vector2i q(p.x() + dx, p.y() + dy);
          if (q.x() < 0 || q.y() < 0 || q.x() >= sw || q.y() >= sh) continue;
          const std::size_t k = static_cast<std::size_t>(q.y()) * sw + q.x();
          if (seen[k] || !(square[k] <= t)) continue;
          seen[k] = 1;
          todo.push_back(q);
        }
      }
    }
  }
  return std::nullopt;
}

TEST(FlyableRegions, LowestConnectingGroundMatchesABruteForceSearch) {
  const int n = 40;
  TerrainGeneratorOptions g;
  g.width = n;
  g.height = n;
  g.cell_size_m = 30.0;
  g.seed = 11;
  std::vector<float> heights = generateTerrainHeights(g);
  // A few unknown cells so the search also has to go round them.
  for (int k = 0; k < 30; ++k) heights[static_cast<std::size_t>((k * 37) % (n * n))] = std::numeric_limits<float>::quiet_NaN();
  const auto w = testing::syntheticWorld(n, heights, 1e9);
  ASSERT_TRUE(w.world);
  const FlyableRegions regions = FlyableRegions::build(*w.terrain, 0.0);
  ASSERT_EQ(regions.pool(), 1);
  std::uint64_t state = 5;
  auto next = [&state](int m) {
    state = state * 6364136223846793005ULL + 1442695040888963407ULL;
    return static_cast<int>((state >> 33) % static_cast<std::uint64_t>(m));
  };
  int compared = 0;
  for (int k = 0; k < 12; ++k) {
    const Eigen::Vector2i a(next(n - 1), next(n - 1)), b(next(n - 1), next(n - 1));
    // The centre of each square, in ENU.
    const Eigen::Vector2d a_en = w.terrain->pixelToEn(a.x() + 0.5, a.y() + 0.5);
    const Eigen::Vector2d b_en = w.terrain->pixelToEn(b.x() + 0.5, b.y() + 0.5);
    ASSERT_EQ(regions.blockAt(a_en), std::optional<Eigen::Vector2i>(a));
    const auto expected = bruteForceLowestGround(*w.terrain, n, n, a, b);
    const auto got = regions.lowestConnectingGroundM(a_en, b_en);
    ASSERT_EQ(expected.has_value(), got.has_value()) << "pair " << k;
    if (expected) {
      EXPECT_FLOAT_EQ(static_cast<float>(*got), static_cast<float>(*expected)) << "pair " << k;
      ++compared;
    }
  }
  EXPECT_GE(compared, 8);
}

TEST(FlyableRegions, NotConnectedIsNeverSaidOfAValidFlightEvenWithPooledBlocks) {
  const int n = kHillySize;
  const std::vector<float> heights = hillyHeights(3);
  const float lowest = *std::min_element(heights.begin(), heights.end());
  const float highest = *std::max_element(heights.begin(), heights.end());
  const double ceiling = lowest + 30.0 + 0.45 * (highest - lowest);  // valleys separated by ridges
  const auto w = testing::syntheticWorld(n, heights, ceiling);
  ASSERT_TRUE(w.world);
  for (std::size_t max_blocks : {std::size_t{1} << 20, std::size_t{400}, std::size_t{60}}) {
    const FlyableRegions regions = FlyableRegions::build(*w.terrain, ceiling - 30.0, max_blocks);
    const Eigen::AlignedBox2d en = w.terrain->boundsEn();
    Uniform u(17);
    auto validPoint = [&]() -> std::optional<Eigen::Vector3d> {
      for (int k = 0; k < 1000; ++k) {
        const Eigen::Vector2d p(u(en.min().x(), en.max().x()), u(en.min().y(), en.max().y()));
        const double ground = w.terrain->heightAt(p.x(), p.y());
        const Eigen::Vector3d q(p.x(), p.y(), u(ground + 30.0, ceiling));
        if (w.world->isPointValid(q)) return q;
      }
      return std::nullopt;
    };
    int valid_flights = 0, separated = 0;
    for (int k = 0; k < 3000; ++k) {
      const auto a = validPoint(), b = validPoint();
      ASSERT_TRUE(a && b);
      if (w.world->isSegmentValid(*a, *b)) {
        ++valid_flights;
        ASSERT_TRUE(regions.connected(a->head<2>(), b->head<2>())) << "max_blocks " << max_blocks;
        const Eigen::AlignedBox2d own_box(a->head<2>().cwiseMin(b->head<2>()), a->head<2>().cwiseMax(b->head<2>()));
        ASSERT_TRUE(regions.connectedWithin(a->head<2>(), b->head<2>(), own_box));
      } else if (!regions.connected(a->head<2>(), b->head<2>())) {
        ++separated;
        // Not connected below this ceiling, so the bottleneck lies above the threshold.
        const auto lowest_ground = regions.lowestConnectingGroundM(a->head<2>(), b->head<2>());
        ASSERT_TRUE(lowest_ground);
        EXPECT_GT(*lowest_ground, ceiling - 30.0);
      }
    }
    EXPECT_GT(valid_flights, 100) << "max_blocks " << max_blocks;
    if (max_blocks > 1000) {
      EXPECT_GT(separated, 100) << "the ceiling should split the valleys";
    }
  }
}

// The grid way is clear by construction: on hilly terrain with pooled blocks, every point along
// every piece of it has ground at most the threshold (read from the heightfield every 2 m), and
// it runs from a corner of the first point's grid square to a corner of the second's.
TEST(FlyableRegions, TheGridWayKeepsTheGroundUnderItAtMostTheThreshold) {
  const int n = kHillySize;
  const std::vector<float> heights = hillyHeights(5);
  const float lowest = *std::min_element(heights.begin(), heights.end());
  const float highest = *std::max_element(heights.begin(), heights.end());
  const double threshold = lowest + 0.7 * (highest - lowest);
  const auto w = testing::syntheticWorld(n, heights, threshold + 30.0);
  ASSERT_TRUE(w.world);
  const Heightfield& hf = *w.terrain;
  int ways = 0;
  for (std::size_t max_blocks : {std::size_t{1} << 20, std::size_t{400}}) {
    const FlyableRegions regions = FlyableRegions::build(hf, threshold, max_blocks);
    Uniform u(29);
    for (int k = 0; k < 200; ++k) {
      const Eigen::Vector2d a = cellEn(hf, u(1, n - 2), u(1, n - 2)), b = cellEn(hf, u(1, n - 2), u(1, n - 2));
      if (!(hf.heightAt(a.x(), a.y()) <= threshold && hf.heightAt(b.x(), b.y()) <= threshold)) continue;
      if (!regions.connected(a, b)) continue;
      const std::vector<Eigen::Vector2d> way = regions.gridWay(a, b, threshold);
      if (way.empty()) continue;  // the blocks may connect where no grid way does
      ++ways;
      EXPECT_LT((way.front() - a).norm(), 2 * 30.0 * 1.5);
      EXPECT_LT((way.back() - b).norm(), 2 * 30.0 * 1.5);
      for (std::size_t i = 0; i + 1 < way.size(); ++i) {
        const double length = (way[i + 1] - way[i]).norm();
        const int steps = std::max(1, static_cast<int>(std::ceil(length / 2.0)));
        for (int s = 0; s <= steps; ++s) {
          const Eigen::Vector2d p = way[i] + (way[i + 1] - way[i]) * (static_cast<double>(s) / steps);
          ASSERT_LE(hf.heightAt(p.x(), p.y()), threshold + 1e-3) << "piece " << i << " of way " << ways;
        }
      }
    }
  }
  std::printf("%d grid ways checked\n", ways);
  EXPECT_GT(ways, 40);
}

}  // namespace
}  // namespace skyroute
