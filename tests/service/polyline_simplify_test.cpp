// Douglas-Peucker with kept vertices: the corridor holds both ways on random seeded 3D walks, kept
// vertices survive, and bad input names the field.
#include "service/polyline_simplify.hpp"

#include <algorithm>
#include <cmath>
#include <random>

#include <gtest/gtest.h>

namespace skyroute {
namespace {

std::vector<Eigen::Vector3d> randomWalk(std::uint32_t seed, std::size_t n) {
  std::mt19937 rng(seed);
  std::normal_distribution<double> turn(0.0, 0.15), climb(0.0, 0.5);
  std::vector<Eigen::Vector3d> points{Eigen::Vector3d(0, 0, 500)};
  double heading = 0.0;
  for (std::size_t i = 1; i < n; ++i) {
    heading += turn(rng);
    points.push_back(points.back() + Eigen::Vector3d(4.0 * std::cos(heading), 4.0 * std::sin(heading), climb(rng)));
  }
  return points;
}

double distanceToPolyline(const Eigen::Vector3d& p, const std::vector<Eigen::Vector3d>& line) {
  double best = (p - line.front()).norm();
  for (std::size_t i = 0; i + 1 < line.size(); ++i) best = std::min(best, distanceToSegment(p, line[i], line[i + 1]));
  return best;
}

TEST(PolylineSimplify, CorridorHoldsBothWaysAndKeptVerticesStay) {
  for (std::uint32_t seed = 1; seed <= 20; ++seed) {
    const auto points = randomWalk(seed, 400);
    const std::vector<std::size_t> keep = {37, 200, 201, 333};
    for (double tolerance : {0.5, 3.0, 15.0}) {
      auto kept = simplifyPolyline(points, tolerance, keep);
      ASSERT_TRUE(kept.ok()) << kept.error().describe();
      ASSERT_GE(kept->size(), 2u + keep.size());
      EXPECT_EQ(kept->front(), 0u);
      EXPECT_EQ(kept->back(), points.size() - 1);
      for (std::size_t k : keep) EXPECT_TRUE(std::binary_search(kept->begin(), kept->end(), k)) << k;
      std::vector<Eigen::Vector3d> route;
      for (std::size_t i : *kept) route.push_back(points[i]);
      // Every vertex of the walk lies within the tolerance of its replacing segment...
      for (std::size_t s = 0; s + 1 < kept->size(); ++s)
        for (std::size_t i = (*kept)[s]; i <= (*kept)[s + 1]; ++i)
          EXPECT_LE(distanceToSegment(points[i], points[(*kept)[s]], points[(*kept)[s + 1]]), tolerance + 1e-9);
      // ...and every point of the straight route within the tolerance of the walk.
      for (std::size_t s = 0; s + 1 < route.size(); ++s)
        for (int j = 0; j <= 50; ++j) {
          const Eigen::Vector3d q = route[s] + (route[s + 1] - route[s]) * (j / 50.0);
          EXPECT_LE(distanceToPolyline(q, points), tolerance + 1e-9) << "seed " << seed;
        }
      if (tolerance == 15.0) {
        EXPECT_LT(kept->size(), points.size() / 4) << "seed " << seed;
      }
    }
  }
}

TEST(PolylineSimplify, StraightLineKeepsItsEnds) {
  std::vector<Eigen::Vector3d> line;
  for (int i = 0; i < 10; ++i) line.emplace_back(i * 10.0, i * 5.0, 100.0 + i);
  auto kept = simplifyPolyline(line, 0.01);
  ASSERT_TRUE(kept.ok());
  EXPECT_EQ(*kept, (std::vector<std::size_t>{0, 9}));
  auto two = simplifyPolyline({line[0], line[1]}, 1.0);
  ASSERT_TRUE(two.ok());
  EXPECT_EQ(two->size(), 2u);
}

TEST(PolylineSimplify, BadInputNamesTheField) {
  const std::vector<Eigen::Vector3d> line = {{0, 0, 0}, {1, 0, 0}, {2, 1, 0}};
  auto zero = simplifyPolyline(line, 0.0);
  ASSERT_FALSE(zero.ok());
  EXPECT_EQ(zero.error().field, "tolerance_m");
  auto past = simplifyPolyline(line, 1.0, {3});
  ASSERT_FALSE(past.ok());
  EXPECT_EQ(past.error().field, "keep[0]");
  auto nan = simplifyPolyline({{0, 0, 0}, {std::nan(""), 0, 0}, {2, 0, 0}}, 1.0);
  ASSERT_FALSE(nan.ok());
  EXPECT_EQ(nan.error().field, "points[1]");
}

}  // namespace
}  // namespace skyroute
