// The one polyline length (planning/core/polyline.hpp) for 3D points in metres; grid cells use the
// same template through their segmentLength (tests/planning/grid/any_angle_search_test.cpp).
#include "planning/core/polyline.hpp"

#include <cmath>
#include <vector>

#include <gtest/gtest.h>

namespace skyroute {
namespace {

TEST(PolylineLength, SumsTheSegmentsInOrder) {
  EXPECT_EQ(polylineLength(std::vector<Eigen::Vector3d>{}), 0.0);
  EXPECT_EQ(polylineLength(std::vector<Eigen::Vector3d>{Eigen::Vector3d(1, 2, 3)}), 0.0);
  const std::vector<Eigen::Vector3d> path{{0, 0, 0}, {3, 4, 0}, {3, 4, 12}, {0, 0, 0}};
  EXPECT_DOUBLE_EQ(polylineLength(path), 5.0 + 12.0 + 13.0);
  // Left to right, exactly as a running sum of (b - a).norm().
  double running = 0.0;
  for (std::size_t i = 1; i < path.size(); ++i) running += (path[i] - path[i - 1]).norm();
  EXPECT_EQ(polylineLength(path), running);
}

}  // namespace
}  // namespace skyroute
