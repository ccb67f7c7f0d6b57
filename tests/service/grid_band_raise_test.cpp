// The grid planners' flight band rises when terrain above it parts a leg's ends: a leg of the
// embedded terrain whose band (200 m above its higher end) is cut by a ridge is flown over the
// ridge on a higher band instead of coming back "no path"; every piece of the lifted path is
// clear of the terrain, and a leg the first band already serves keeps that band.
#include <gtest/gtest.h>

#include <algorithm>

#include "service/grid_leg_planner.hpp"
#include "tests/service/default_world_fixture.hpp"

namespace skyroute {
namespace {

class GridBandRaiseTest : public testing::DefaultWorldTest {};

double highest(const std::vector<Eigen::Vector3d>& path) {
  double top = -1e9;
  for (const Eigen::Vector3d& p : path) top = std::max(top, p.z());
  return top;
}

TEST_F(GridBandRaiseTest, ARidgeAboveTheBandRaisesItInsteadOfNoPath) {
  auto world = world_->worldFor(30.0, 5000.0);
  ASSERT_TRUE(world.ok());
  const Eigen::Vector3d a = enu(2574.7, 2211.1, 60).enu_m;
  const Eigen::Vector3d b = enu(-3373.6, 5250.8, 60).enu_m;
  ASSERT_FALSE((*world)->isSegmentValid(a, b)) << "the test needs a blocked straight leg";
  const GridLegOptions options;
  const double first_top_m = std::max(a.z(), b.z()) + options.band_margin_m;
  for (const GridGlobalPlanner planner : {GridGlobalPlanner::kHabPp, GridGlobalPlanner::kHabPpRrt}) {
    auto route = planGridRoutePaths(*world, {a, b}, planner, options, 1);
    ASSERT_TRUE(route.ok()) << route.error().describe();
    ASSERT_EQ(route->legs.size(), 1u);
    const std::vector<Eigen::Vector3d>& path = route->legs[0].path_m;
    EXPECT_GT(highest(path), first_top_m + 1.0) << "flown on the first band, which the ridge cuts";
    EXPECT_EQ(path.front(), a);
    EXPECT_EQ(path.back(), b);
    for (std::size_t k = 1; k < path.size(); ++k) EXPECT_TRUE((*world)->isSegmentValid(path[k - 1], path[k])) << k;
  }
  // A leg the first band serves keeps it: its cruise altitude is that band's top.
  const Eigen::Vector3d c = enu(-5000, -2000, 60).enu_m;
  const Eigen::Vector3d d = enu(0, -5500, 150).enu_m;
  ASSERT_FALSE((*world)->isSegmentValid(c, d));
  auto served = planGridRoutePaths(*world, {c, d}, GridGlobalPlanner::kHabPp, options, 1);
  ASSERT_TRUE(served.ok()) << served.error().describe();
  EXPECT_NEAR(highest(served->legs[0].path_m), std::max(c.z(), d.z()) + options.band_margin_m, 1e-6);
}

}  // namespace
}  // namespace skyroute
