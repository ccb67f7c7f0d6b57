// A fixed wing's path angles in the legs' motion check: WorldMotionValidator::limitPathAngles
// refuses motions climbing or descending more steeply than the limits, and RRT* + LOSPO on the
// embedded terrain with them find a climbing leg whose every piece keeps within them (checked
// here from the path's vertices), where the straight climb is too steep.
#include <cmath>
#include <numbers>

#include <gtest/gtest.h>

#include "planning/sampling/lospo.hpp"
#include "planning/sampling/rrt_star.hpp"
#include "planning/sampling/world_motion_validator.hpp"
#include "terrain/terrain_world.hpp"
#include "tests/test_data.hpp"

namespace skyroute {
namespace {

constexpr double kDeg = std::numbers::pi / 180.0;

class PathAngleTest : public ::testing::Test {
 protected:
  void SetUp() override {
    CollisionWorldOptions options;
    options.build_octree = false;
    auto world = loadTerrainWorld(testing::projectDataPath("default_terrain.tif"), options);
    ASSERT_TRUE(world.ok()) << world.error().describe();
    world_ = std::move(world).value();
  }
  // A point `agl_m` above the ground at east/north metres from the centre.
  Eigen::Vector3d above(double e, double n, double agl_m) const {
    return {e, n, world_.heightfield->heightAt(e, n) + agl_m};
  }
  TerrainWorld world_;
};

// Slope of a -> b above the horizontal, degrees (negative descending).
double pathAngleDeg(const Eigen::Vector3d& a, const Eigen::Vector3d& b) {
  return std::atan2(b.z() - a.z(), (b - a).head<2>().norm()) / kDeg;
}

TEST_F(PathAngleTest, SteeperMotionsThanTheLimitsAreInvalid) {
  WorldMotionValidator v(world_.collision);
  const Eigen::Vector3d a = above(-3000, -3000, 400);
  auto at = [&](double angle_deg) -> Eigen::Vector3d {
    return a + Eigen::Vector3d(200, 0, 200 * std::tan(angle_deg * kDeg));
  };
  EXPECT_TRUE(v.isMotionValid(a, at(30)));
  v.limitPathAngles(15.0, 10.0);
  EXPECT_FALSE(v.isMotionValid(a, at(30)));
  EXPECT_FALSE(v.isMotionValid(a, at(16)));
  EXPECT_TRUE(v.isMotionValid(a, at(14)));
  EXPECT_TRUE(v.isMotionValid(a, at(-9)));
  EXPECT_FALSE(v.isMotionValid(a, at(-11)));
  EXPECT_FALSE(v.isMotionValid(a, a + Eigen::Vector3d(0, 0, 10)));  // straight up
}

TEST_F(PathAngleTest, RrtStarAndLospoKeepEveryPieceWithinTheLimits) {
  // 800 m up over 2 km: a 22 degree straight climb, twice the 11 degree limit.
  const Eigen::Vector3d start = above(-2000, -4000, 100);
  const Eigen::Vector3d goal(0, -4000, start.z() + 800);
  WorldMotionValidator v(world_.collision, WorldMotionValidator::corridor(start, goal, 4000));
  v.limitPathAngles(11.0, 11.0);
  ASSERT_TRUE(v.isStateValid(start));
  ASSERT_TRUE(v.isStateValid(goal));
  ASSERT_GT(pathAngleDeg(start, goal), 20.0);
  ASSERT_FALSE(v.isMotionValid(start, goal));
  RrtStarOptions o;
  o.seed = 7;
  auto r = RrtStar(v, o).plan(start, goal, TerminationCondition().withIterationBudget(6000));
  ASSERT_TRUE(r.ok());
  ASSERT_TRUE(r->solved()) << "no path in 6000 iterations";
  auto shortened = lospo(v, r->path_m, LospoOptions{.spacing_m = 50.0});
  ASSERT_TRUE(shortened.ok());
  for (const auto* path : {&r->path_m, &shortened->path_m}) {
    ASSERT_GE(path->size(), 3u);  // the straight climb is refused: it winds up
    for (std::size_t k = 0; k + 1 < path->size(); ++k) {
      const double angle = pathAngleDeg((*path)[k], (*path)[k + 1]);
      EXPECT_LE(std::abs(angle), 11.0 + 1e-9) << "piece " << k;
    }
  }
}

}  // namespace
}  // namespace skyroute
