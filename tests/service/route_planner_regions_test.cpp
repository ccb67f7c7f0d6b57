// The route planner's legs where the terrain decides: a leg whose only way round a ridge lies
// beyond its sampling corridor is found (the corridor grows), a leg across a ridge that is above
// the ceiling everywhere is refused at once as not connected (with the lowest ceiling that could
// connect it), a leg whose RRT* finds nothing in its budget flies the regions' grid way under the
// ceiling, and a leg the corridor can hold is planned exactly as RRT* in that corridor plans it.
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <string>

#include <gtest/gtest.h>

#include "service/route_planner.hpp"
#include "tests/ridge_terrain.hpp"

namespace skyroute {
namespace {

using testing::RidgeSpec;

constexpr double kClearanceM = 30.0;
constexpr double kCeilingM = 330.0;

// 100 x 100 cells of 30 m; the ridge over columns 48-52 is 1000 m high except at the pass.
RidgeSpec ridge(int pass_first_row, int pass_last_row, double pass_m) {
  RidgeSpec s;
  s.size = 100;
  s.ridge_first_col = 48;
  s.ridge_last_col = 52;
  s.pass_first_row = pass_first_row;
  s.pass_last_row = pass_last_row;
  s.pass_m = pass_m;
  return s;
}

Eigen::Vector3d above(const Heightfield& hf, double col, double row, double agl_m) {
  const Eigen::Vector2d en = hf.pixelToEn(col, row);
  return {en.x(), en.y(), hf.heightAt(en.x(), en.y()) + agl_m};
}

RouteOptions iterationBudget(double corridor_margin_m, std::uint64_t leg_iterations = 4000) {
  RouteOptions o;
  o.seed = 3;
  o.leg_budget_ms = 0.0;  // reproducible: the iteration budget alone
  o.leg_max_iterations = leg_iterations;
  o.corridor_margin_m = corridor_margin_m;
  return o;
}

// Every 2 m along the path: under the ceiling and at least the clearance above the raw ground,
// read from the heightfield (not through the planner's motion checks).
int denseViolations(const Heightfield& hf, const std::vector<Eigen::Vector3d>& path) {
  int bad = 0;
  for (std::size_t i = 0; i + 1 < path.size(); ++i) {
    const int steps = std::max(1, static_cast<int>(std::ceil((path[i + 1] - path[i]).norm() / 2.0)));
    for (int k = 0; k <= steps; ++k) {
      const Eigen::Vector3d p = path[i] + (path[i + 1] - path[i]) * (static_cast<double>(k) / steps);
      const auto agl = hf.heightAboveGround(p);
      if (!agl || *agl < kClearanceM - 1e-6 || p.z() > kCeilingM + 1e-9) ++bad;
    }
  }
  return bad;
}

TEST(RoutePlannerRegions, ALegWhosePassLiesBeyondTheCorridorIsFound) {
  const auto w = testing::ridgeWorld(ridge(85, 92, 200.0), kCeilingM);
  ASSERT_TRUE(w.world);
  const Heightfield& hf = *w.terrain;
  // West to east along row 10, 60 m up; the corridor (300 m, ten cells) ends 75 rows north of the pass.
  const Eigen::Vector3d a = above(hf, 15, 10, 60), b = above(hf, 85, 10, 60);
  auto route = planRoutePaths(w.world, {a, b}, iterationBudget(300.0));
  ASSERT_TRUE(route.ok()) << route.error().describe();
  ASSERT_EQ(route->legs.size(), 1u);
  const std::vector<Eigen::Vector3d>& path = route->legs[0].path_m;
  EXPECT_EQ(denseViolations(hf, route->legs[0].rrt.path_m), 0);
  EXPECT_EQ(denseViolations(hf, path), 0);
  EXPECT_TRUE(path.front().isApprox(a) && path.back().isApprox(b));
  // It goes through the pass: south of the pass's northern edge somewhere, and at least the
  // way down to it and back (the straight line is 2.1 km).
  const double pass_north_m = hf.pixelToEn(50, 85).y();
  double southmost = a.y();
  for (const auto& p : path) southmost = std::min(southmost, p.y());
  EXPECT_LT(southmost, pass_north_m);
  EXPECT_GT(route->legs[0].lospo_length_m, 2.0 * (a.y() - pass_north_m));
}

// RRT* with far too few samples for the way round finds nothing; the leg still flies: the
// flyable regions' grid way under the ceiling, checked piece by piece, then straightened by LOSPO.
TEST(RoutePlannerRegions, ALegRrtStarCannotSolveInItsBudgetFliesTheGridWayUnderTheCeiling) {
  const auto w = testing::ridgeWorld(ridge(85, 92, 200.0), kCeilingM);
  ASSERT_TRUE(w.world);
  const Heightfield& hf = *w.terrain;
  const Eigen::Vector3d a = above(hf, 15, 10, 60), b = above(hf, 85, 10, 60);
  auto route = planRoutePaths(w.world, {a, b}, iterationBudget(300.0, 20));
  ASSERT_TRUE(route.ok()) << route.error().describe();
  ASSERT_EQ(route->legs.size(), 1u);
  const RouteLeg& leg = route->legs[0];
  EXPECT_TRUE(leg.rrt.solved());
  EXPECT_EQ(denseViolations(hf, leg.rrt.path_m), 0);
  EXPECT_EQ(denseViolations(hf, leg.path_m), 0);
  EXPECT_TRUE(leg.path_m.front().isApprox(a) && leg.path_m.back().isApprox(b));
  const double pass_north_m = hf.pixelToEn(50, 85).y();
  double southmost = a.y();
  for (const auto& p : leg.path_m) southmost = std::min(southmost, p.y());
  EXPECT_LT(southmost, pass_north_m);
  // LOSPO straightened the staircase: shorter than the grid way it started from.
  EXPECT_LT(leg.lospo_length_m, leg.rrt.length_m);
}

TEST(RoutePlannerRegions, ARidgeAboveTheCeilingEverywhereIsNotConnected) {
  const auto w = testing::ridgeWorld(ridge(85, 92, 500.0), kCeilingM);
  ASSERT_TRUE(w.world);
  const Heightfield& hf = *w.terrain;
  const Eigen::Vector3d a = above(hf, 15, 10, 60), b = above(hf, 85, 10, 60);
  auto route = planRoutePaths(w.world, {a, b}, iterationBudget(300.0, 20000));
  ASSERT_FALSE(route.ok());
  EXPECT_EQ(route.error().code, ErrorCode::kUnreachable) << route.error().describe();
  EXPECT_EQ(route.error().field, "legs[0]");
  const std::string& message = route.error().message;
  EXPECT_EQ(message.rfind("no path: start and goal are not connected below the ceiling", 0), 0u) << message;
  // The pass is 500 m high: 530 m with the clearance.
  EXPECT_NE(message.find("the lowest ceiling that could connect them is 530 m"), std::string::npos) << message;
  // And with a ceiling above that (room to fly over the pass) the leg is planned.
  const auto higher = testing::ridgeWorld(ridge(85, 92, 500.0), 600.0);
  ASSERT_TRUE(higher.world);
  auto over_the_pass = planRoutePaths(higher.world, {a, b}, iterationBudget(300.0));
  EXPECT_TRUE(over_the_pass.ok()) << over_the_pass.error().describe();
}

TEST(RoutePlannerRegions, ALegTheCorridorHoldsIsPlannedExactlyAsInTheCorridor) {
  // The pass is on the leg's own row: the corridor holds the way over it.
  const auto w = testing::ridgeWorld(ridge(5, 15, 200.0), kCeilingM);
  ASSERT_TRUE(w.world);
  const Heightfield& hf = *w.terrain;
  const Eigen::Vector3d a = above(hf, 15, 10, 60), b = above(hf, 85, 12, 60);
  ASSERT_FALSE(w.world->isSegmentValid(a, b));
  const RouteOptions options = iterationBudget(300.0);
  auto route = planRoutePaths(w.world, {a, b}, options);
  ASSERT_TRUE(route.ok()) << route.error().describe();
  const WorldMotionValidator corridor(w.world, WorldMotionValidator::corridor(a, b, options.corridor_margin_m));
  RrtStarOptions rrt = options.rrt;
  rrt.seed = options.seed;
  auto alone = RrtStar(corridor, rrt).plan(a, b, TerminationCondition().withIterationBudget(options.leg_max_iterations));
  ASSERT_TRUE(alone.ok() && alone->solved());
  ASSERT_EQ(route->legs[0].rrt.path_m.size(), alone->path_m.size());
  for (std::size_t k = 0; k < alone->path_m.size(); ++k) EXPECT_EQ(route->legs[0].rrt.path_m[k], alone->path_m[k]);
  EXPECT_EQ(route->legs[0].rrt.iterations, alone->iterations);
}

}  // namespace
}  // namespace skyroute
