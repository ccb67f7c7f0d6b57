// The order stage's cost matrix: what the visiting order was chosen from, in metres, for each
// method (MMD*L on the flight band, the straight-line fallback, a fixed order).
#include <gtest/gtest.h>

#include <cmath>

#include "service/mission_order.hpp"
#include "terrain/heightfield.hpp"
#include "tests/terrain_data.hpp"
#include "tests/test_data.hpp"

namespace skyroute {
namespace {

class MissionOrderMatrix : public ::testing::Test {
 protected:
  static void SetUpTestSuite() { terrain_ = testing::defaultTerrainHeightfield(); }
  void SetUp() override { ASSERT_TRUE(terrain_) << "data/default_terrain.tif did not load"; }

  Eigen::Vector3d above(double east_m, double north_m, double agl_m) const {
    return {east_m, north_m, terrain_->heightAt(east_m, north_m) + agl_m};
  }
  // The order's cost summed from the matrix along the order.
  static double costAlong(const MissionOrder& o) {
    double sum = 0.0;
    for (std::size_t k = 0; k + 1 < o.order.size(); ++k) sum += o.cost_matrix_m[o.order[k]][o.order[k + 1]];
    return sum;
  }

  static inline std::shared_ptr<const Heightfield> terrain_;
};

TEST_F(MissionOrderMatrix, MmdStarMatrixHoldsPathCostsTheOrderAddsUp) {
  const std::vector<Eigen::Vector3d> points{above(-4000, -4000, 200), above(3000, 2500, 200), above(-2500, 3000, 200),
                                            above(2500, -3000, 200), above(4000, 4000, 200)};
  auto o = orderMissionPoints(*terrain_, points, 30.0, 5000.0, false);
  ASSERT_TRUE(o.ok()) << o.error().describe();
  ASSERT_EQ(o->method, "mmdstar") << o->fallback_reason;
  ASSERT_EQ(o->cost_matrix_m.size(), points.size());
  for (const auto& row : o->cost_matrix_m) ASSERT_EQ(row.size(), points.size());
  EXPECT_NEAR(costAlong(*o), o->cost_m, 1e-6 * o->cost_m);
  // A grid path is never shorter than the straight line between the cells' centres, give or take
  // the cells the points lie in; and MMD*L plans no path into the begin point.
  for (std::size_t i = 0; i < points.size(); ++i) {
    EXPECT_FALSE(std::isfinite(o->cost_matrix_m[i][0])) << i;
    for (std::size_t j = 1; j < points.size(); ++j) {
      const double v = o->cost_matrix_m[i][j];
      if (i == j || !std::isfinite(v)) continue;
      EXPECT_GE(v, (points[i] - points[j]).head<2>().norm() - 2.0 * o->cell_size_m) << i << " -> " << j;
    }
  }
}

TEST_F(MissionOrderMatrix, EuclideanFallbackMatrixHoldsStraightLines) {
  // Two points in one grid cell: MMD*L cannot tell them apart, the order falls back.
  const std::vector<Eigen::Vector3d> points{above(-4000, -4000, 200), above(1000, 1000, 200), above(1001, 1001, 200),
                                            above(4000, 4000, 200)};
  auto o = orderMissionPoints(*terrain_, points, 30.0, 5000.0, false);
  ASSERT_TRUE(o.ok()) << o.error().describe();
  ASSERT_EQ(o->method, "euclidean");
  EXPECT_FALSE(o->fallback_reason.empty());
  ASSERT_EQ(o->cost_matrix_m.size(), points.size());
  for (std::size_t i = 0; i < points.size(); ++i)
    for (std::size_t j = 0; j < points.size(); ++j)
      EXPECT_DOUBLE_EQ(o->cost_matrix_m[i][j], (points[i] - points[j]).norm());
  EXPECT_NEAR(costAlong(*o), o->cost_m, 1e-6);
}

TEST_F(MissionOrderMatrix, FixedOrderComparesNothing) {
  const std::vector<Eigen::Vector3d> points{above(-4000, -4000, 200), above(3000, 2500, 200), above(-2500, 3000, 200),
                                            above(4000, 4000, 200)};
  auto o = orderMissionPoints(*terrain_, points, 30.0, 5000.0, true);
  ASSERT_TRUE(o.ok());
  EXPECT_EQ(o->method, "fixed");
  EXPECT_TRUE(o->cost_matrix_m.empty());
  EXPECT_EQ(o->order, (std::vector<int>{0, 1, 2, 3}));
}

}  // namespace
}  // namespace skyroute
