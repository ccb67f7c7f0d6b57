// planGridRoutePaths on the embedded terrain: a route whose legs must cross the main ridge goes
// through HAB-PP on the flight band and comes back lifted to 3D. Checked: every segment of every
// leg is clear by the collision world's own check, the legs join the route points, and the band
// vertex next to a leg end is lowered towards max_end_slope (never steeper than without easing,
// and at most the slope where the terrain lets it).
#include "service/grid_leg_planner.hpp"

#include <gtest/gtest.h>

#include "service/world_model.hpp"
#include "tests/test_data.hpp"

namespace skyroute {
namespace {

// Rise over horizontal run of a - b; infinity for a vertical step.
double slope(const Eigen::Vector3d& a, const Eigen::Vector3d& b) {
  const double run_m = (b - a).head<2>().norm();
  return run_m < 1e-6 ? std::numeric_limits<double>::infinity() : std::abs(b.z() - a.z()) / run_m;
}

class GridLegPlannerTest : public ::testing::Test {
 protected:
  void SetUp() override {
    heightfield_ = testing::defaultTerrainHeightfield();
    ASSERT_TRUE(heightfield_) << "data/default_terrain.tif did not load";
    auto model = WorldModel::create(heightfield_, WorldModelOptions{}, "default_terrain");
    ASSERT_TRUE(model.ok());
    auto world = (*model)->worldFor(30.0, 5000.0);
    ASSERT_TRUE(world.ok());
    world_ = *world;
  }
  Eigen::Vector3d at(double e, double n, double agl_m) const {
    return Eigen::Vector3d(e, n, heightfield_->heightAt(e, n) + agl_m);
  }
  std::shared_ptr<const Heightfield> heightfield_;
  std::shared_ptr<const CollisionWorld> world_;
};

TEST_F(GridLegPlannerTest, LiftedLegsAreClearAndTheirEndsAreEased) {
  // The engine test's route: both legs cross the ridge low, so both go through HAB-PP.
  const std::vector<Eigen::Vector3d> points{at(-5000, -2000, 60), at(0, -5500, 60), at(5000, 2000, 60)};
  GridLegOptions steep;
  steep.max_end_slope = 0.0;  // never lowered
  const GridLegOptions eased;
  ASSERT_GT(eased.max_end_slope, 0.0);
  auto plain = planGridRoutePaths(world_, points, GridGlobalPlanner::kHabPp, steep, 11);
  auto lowered = planGridRoutePaths(world_, points, GridGlobalPlanner::kHabPp, eased, 11);
  ASSERT_TRUE(plain.ok()) << plain.error().describe();
  ASSERT_TRUE(lowered.ok()) << lowered.error().describe();
  ASSERT_EQ(lowered->legs.size(), 2u);
  int eased_ends = 0;
  for (std::size_t i = 0; i < lowered->legs.size(); ++i) {
    SCOPED_TRACE("leg " + std::to_string(i));
    const std::vector<Eigen::Vector3d>& p = lowered->legs[i].path_m;
    const std::vector<Eigen::Vector3d>& q = plain->legs[i].path_m;
    ASSERT_GE(p.size(), 2u);
    EXPECT_LT((p.front() - points[i]).norm(), 1e-9);
    EXPECT_LT((p.back() - points[i + 1]).norm(), 1e-9);
    for (std::size_t k = 1; k < p.size(); ++k) EXPECT_TRUE(world_->isSegmentValid(p[k - 1], p[k])) << "segment " << k;
    // Same colony, same seed: the same vertices in plan, only altitudes differ.
    ASSERT_EQ(p.size(), q.size());
    for (std::size_t k = 0; k < p.size(); ++k) EXPECT_LT((p[k] - q[k]).head<2>().norm(), 1e-9);
    if (p.size() < 3) continue;
    for (auto [end, next] : {std::pair<std::size_t, std::size_t>{0, 1}, {p.size() - 1, p.size() - 2}}) {
      EXPECT_LE(p[next].z(), q[next].z() + 1e-9);
      EXPECT_GE(p[next].z(), std::min(p[end].z(), q[next].z()) - 1e-9);
      if (p[next].z() < q[next].z() - 1.0) {
        ++eased_ends;
        EXPECT_LE(slope(p[end], p[next]), slope(q[end], q[next]));
      }
    }
  }
  EXPECT_GT(eased_ends, 0) << "some leg end had a steep climb or descent to ease";
}

}  // namespace
}  // namespace skyroute
