// refinePath (the benchmarks' stage after LOSPO): never lengthens, never invalidates (independent
// dense checks on synthetic worlds and on a real DEM), converges to the analytic taut length round
// a wall edge and a sphere, respects the termination condition, and is deterministic.
#include "bench/support/path_refinement.hpp"

#include <atomic>
#include <cmath>
#include <memory>
#include <vector>

#include <gtest/gtest.h>

#include "planning/sampling/lospo.hpp"
#include "planning/sampling/rrt_star.hpp"
#include "tests/planning/synthetic_worlds.hpp"
#include "tests/planning/terrain_legs.hpp"

namespace skyroute {
namespace {

using testing::BoxWorld;

// LOSPO on a coarse spacing leaves the corners at its inserted vertices, off the wall's edges; the
// refinement moves them onto the edges: the 2D taut length round the two corners.
TEST(PathRefinement, DetourRoundAWallConvergesToTheTautLength) {
  const BoxWorld world = testing::wallWorld();
  const Eigen::Vector3d s(20, 30, 10), g(80, 30, 10);
  const double taut = testing::wallWorldTautLength(s, g);
  const std::vector<Eigen::Vector3d> detour{s, {15, 70, 3}, {30, 95, 18}, {70, 97, 2}, {90, 60, 15}, g};
  auto coarse = lospo(world, detour, LospoOptions{.spacing_m = 15.0});
  ASSERT_TRUE(coarse.ok());
  ASSERT_GT(coarse->length_m, taut + 0.5);  // LOSPO alone is visibly slack at this spacing
  PathRefinementOptions o;
  o.min_round_gain_m = 0.0;
  o.max_rounds = 300;
  auto r = refinePath(world, coarse->path_m, o);
  ASSERT_TRUE(r.ok()) << r.error().describe();
  EXPECT_TRUE(world.denseCheck(r->path_m, 0.005));
  EXPECT_GE(r->length_m, taut - 1e-9);
  // Within 5 cm (4e-4) of the taut length, where LOSPO alone is 7 m off: the corners settle within
  // a few min_step_m (5 cm) of the wall's edges.
  EXPECT_LT(r->length_m, taut + 0.05) << "taut " << taut << " lospo " << coarse->length_m;
  EXPECT_NEAR(r->length_m, polylineLength(r->path_m), 1e-9);
  EXPECT_DOUBLE_EQ(r->input_length_m, coarse->length_m);
  EXPECT_EQ(r->path_m.front(), s);
  EXPECT_EQ(r->path_m.back(), g);
  EXPECT_FALSE(r->stopped_early);
}

// Round a sphere (a smooth obstacle, as a ridge's clearance surface): the taut path is two tangents
// and an arc of a great circle; a polygon outside the sphere is longer, approaching it as the
// corners are cut.
TEST(PathRefinement, PathRoundASphereApproachesTheTangentArcLength) {
  BoxWorld world(Eigen::AlignedBox3d(Eigen::Vector3d(0, 0, 0), Eigen::Vector3d(100, 100, 100)));
  const Eigen::Vector3d c(50, 50, 50);
  const double radius = 20.0;
  world.addSphere(c, radius);
  const Eigen::Vector3d s(10, 50, 50), g(90, 50, 50);
  const double d = 40.0;  // start and goal distance from the centre, on opposite sides
  const double taut = 2.0 * std::sqrt(d * d - radius * radius) + radius * (M_PI - 2.0 * std::acos(radius / d));
  // A box-shaped detour over the top in the plane y = 50.
  const std::vector<Eigen::Vector3d> detour{s, {20, 50, 85}, {80, 50, 85}, g};
  ASSERT_TRUE(world.denseCheck(detour, 0.01));
  PathRefinementOptions o;
  o.min_step_m = 0.01;
  o.max_rounds = 200;
  auto r = refinePath(world, detour, o);
  ASSERT_TRUE(r.ok());
  EXPECT_TRUE(world.denseCheck(r->path_m, 0.005));
  EXPECT_GE(r->length_m, taut - 1e-9);
  EXPECT_LT(r->length_m, taut * 1.001) << "taut " << taut << " input " << polylineLength(detour);
  EXPECT_GT(r->cut, 0);
  // With a minimum segment length the corners are cut less finely: still valid and shorter, and
  // the cuts make no segment shorter than asked.
  o.min_segment_m = 4.0;
  auto coarse = refinePath(world, detour, o);
  ASSERT_TRUE(coarse.ok());
  EXPECT_TRUE(world.denseCheck(coarse->path_m, 0.005));
  EXPECT_LT(coarse->length_m, taut * 1.01);
  EXPECT_GE(coarse->length_m, r->length_m);
  EXPECT_LT(coarse->path_m.size(), r->path_m.size());
  for (std::size_t i = 1; i < coarse->path_m.size(); ++i) {
    EXPECT_GE((coarse->path_m[i] - coarse->path_m[i - 1]).norm(), 4.0 - 1e-9) << "segment " << i;
  }
}

// An RRT* path through sphere field `field` and LOSPO's result on it.
std::pair<std::vector<Eigen::Vector3d>, std::vector<Eigen::Vector3d>> fieldPaths(const BoxWorld& world, unsigned field) {
  auto plan = RrtStar(world, RrtStarOptions{.seed = field, .max_step_m = 10.0})
                  .plan(Eigen::Vector3d(2, 2, 2), Eigen::Vector3d(98, 98, 98), TerminationCondition().withIterationBudget(1500));
  if (!plan.ok() || !plan->solved()) return {};
  auto shortened = lospo(world, plan->path_m, LospoOptions{.spacing_m = 5.0});
  return {plan->path_m, shortened.ok() ? shortened->path_m : plan->path_m};
}

TEST(PathRefinement, NeverLengthensNorInvalidatesRrtStarAndLospoPaths) {
  double lospo_total = 0.0, refined_total = 0.0;
  const Eigen::Vector3d s(2, 2, 2), g(98, 98, 98);
  for (unsigned field = 1; field <= 6; ++field) {
    const BoxWorld world = testing::sphereField(field, 50);
    const auto [raw, shortened] = fieldPaths(world, field);
    ASSERT_FALSE(raw.empty()) << "field " << field;
    for (const auto* input : {&raw, &shortened}) {
      PathRefinementOptions ro;
      ro.seed = field;
      auto r = refinePath(world, *input, ro);
      ASSERT_TRUE(r.ok());
      EXPECT_LE(r->length_m, polylineLength(*input)) << "field " << field;
      EXPECT_NEAR(r->length_m, polylineLength(r->path_m), 1e-9);
      EXPECT_TRUE(world.denseCheck(r->path_m, 0.005)) << "field " << field;
      for (std::size_t i = 1; i < r->path_m.size(); ++i) EXPECT_TRUE(world.isMotionValid(r->path_m[i - 1], r->path_m[i]));
      EXPECT_EQ(r->path_m.front(), s);
      EXPECT_EQ(r->path_m.back(), g);
      EXPECT_LE(static_cast<int>(r->path_m.size()), std::max<int>(ro.max_vertices, static_cast<int>(input->size())));
    }
    auto refined = refinePath(world, shortened);
    ASSERT_TRUE(refined.ok());
    lospo_total += polylineLength(shortened);
    refined_total += refined->length_m;
  }
  // The refinement finds length LOSPO leaves (little here: LOSPO at 5 m spacing in open fields).
  EXPECT_LT(refined_total, lospo_total - 0.01);
}

TEST(PathRefinement, SameInputAndSeedGiveTheSamePath) {
  const BoxWorld world = testing::sphereField(3, 50);
  const auto raw = fieldPaths(world, 7).first;
  ASSERT_FALSE(raw.empty());
  auto a = refinePath(world, raw);
  auto b = refinePath(world, raw);
  ASSERT_TRUE(a.ok() && b.ok());
  EXPECT_EQ(a->path_m, b->path_m);
  EXPECT_EQ(a->motion_checks, b->motion_checks);
  EXPECT_GT(a->shortcuts + a->relaxed + a->cut + a->collapsed, 0);
}

TEST(PathRefinement, StopsAtTheTerminationConditionWithAValidPath) {
  const BoxWorld world = testing::wallWorld();
  const std::vector<Eigen::Vector3d> detour{{20, 30, 10}, {30, 95, 18}, {70, 97, 2}, {80, 30, 10}};
  auto cancel = std::make_shared<std::atomic<bool>>(true);
  auto r = refinePath(world, detour, {}, TerminationCondition().withCancelFlag(cancel));
  ASSERT_TRUE(r.ok());
  EXPECT_TRUE(r->stopped_early);
  EXPECT_EQ(r->path_m, detour);  // cancelled before the first change
  // An iteration-free deadline in the past: same.
  auto late = refinePath(world, detour, {}, TerminationCondition::afterMilliseconds(-1.0));
  ASSERT_TRUE(late.ok());
  EXPECT_TRUE(late->stopped_early);
  EXPECT_EQ(late->path_m, detour);
}

TEST(PathRefinement, BadInputIsAnErrorNamingTheField) {
  const BoxWorld world = testing::wallWorld();
  EXPECT_EQ(refinePath(world, {Eigen::Vector3d(1, 1, 1)}).error().field, "path");
  auto through = refinePath(world, {Eigen::Vector3d(20, 30, 10), Eigen::Vector3d(80, 30, 10)});
  ASSERT_FALSE(through.ok());
  EXPECT_EQ(through.error().field, "path");
  const std::vector<Eigen::Vector3d> ok{Eigen::Vector3d(20, 30, 10), Eigen::Vector3d(20, 40, 10)};
  EXPECT_EQ(refinePath(world, ok, PathRefinementOptions{.min_step_m = 0.0}).error().field, "min_step_m");
  EXPECT_EQ(refinePath(world, ok, PathRefinementOptions{.max_rounds = -1}).error().field, "max_rounds");
  EXPECT_EQ(refinePath(world, ok, PathRefinementOptions{.shortcut_attempts = -1}).error().field, "shortcut_attempts");
  EXPECT_EQ(refinePath(world, {Eigen::Vector3d(20, 30, 10), Eigen::Vector3d(NAN, 40, 10)}).error().field, "path");
}

// Real terrain: RRT* and LOSPO low over the White Mountains under a ceiling, then the refinement;
// every 2 m along the refined path the raw heightfield must be at least the clearance below, and
// the ceiling above. The refinement never lengthens and shortens in total.
class PathRefinementOnTerrain : public testing::WhiteMountains {};

TEST_F(PathRefinementOnTerrain, RefinedPathsOverARealDemKeepTheClearance) {
  double lospo_total = 0.0, refined_total = 0.0;
  const int planned = forEachPlannedLeg(3, [&](const testing::TerrainLeg& leg, const WorldMotionValidator& v,
                                               const RrtStarResult&, const LospoResult& shortened) {
    auto refined = refinePath(v, shortened.path_m);
    ASSERT_TRUE(refined.ok()) << refined.error().describe();
    EXPECT_LE(refined->length_m, shortened.length_m);
    lospo_total += shortened.length_m;
    refined_total += refined->length_m;
    expectClearOfTerrain(refined->path_m, leg.attempt);
  });
  EXPECT_EQ(planned, 3);
  EXPECT_LT(refined_total, lospo_total);
}

}  // namespace
}  // namespace skyroute
