// refinePath (the stage after LOSPO): never lengthens, never invalidates (independent dense checks
// on synthetic worlds and on the real terrain), converges to the analytic taut length round a wall
// edge and a sphere, respects the termination condition, and is deterministic.
#include "planning/path_refinement.hpp"

#include <atomic>
#include <cmath>
#include <memory>
#include <vector>

#include <gtest/gtest.h>

#include "planning/lospo.hpp"
#include "planning/rrt_star.hpp"
#include "planning/world_motion_validator.hpp"
#include "terrain/terrain_world.hpp"
#include "tests/planning/synthetic_worlds.hpp"
#include "tests/test_data.hpp"

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

TEST(PathRefinement, NeverLengthensNorInvalidatesRrtStarAndLospoPaths) {
  double lospo_total = 0.0, refined_total = 0.0;
  for (unsigned field = 1; field <= 6; ++field) {
    const BoxWorld world = testing::sphereField(field, 50);
    const Eigen::Vector3d s(2, 2, 2), g(98, 98, 98);
    RrtStarOptions o;
    o.seed = field;
    o.max_step_m = 10.0;
    auto plan = RrtStar(world, o).plan(s, g, TerminationCondition().withIterationBudget(1500));
    ASSERT_TRUE(plan.ok());
    ASSERT_TRUE(plan->solved()) << "field " << field;
    auto shortened = lospo(world, plan->path_m, LospoOptions{.spacing_m = 5.0});
    ASSERT_TRUE(shortened.ok());
    for (const auto* input : {&plan->path_m, &shortened->path_m}) {
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
    auto refined = refinePath(world, shortened->path_m);
    ASSERT_TRUE(refined.ok());
    lospo_total += shortened->length_m;
    refined_total += refined->length_m;
  }
  // The refinement finds length LOSPO leaves (little here: LOSPO at 5 m spacing in open fields).
  EXPECT_LT(refined_total, lospo_total - 0.01);
}

TEST(PathRefinement, SameInputAndSeedGiveTheSamePath) {
  const BoxWorld world = testing::sphereField(3, 50);
  RrtStarOptions o;
  o.seed = 7;
  auto plan = RrtStar(world, o).plan(Eigen::Vector3d(2, 2, 2), Eigen::Vector3d(98, 98, 98),
                                     TerminationCondition().withIterationBudget(1500));
  ASSERT_TRUE(plan.ok() && plan->solved());
  auto a = refinePath(world, plan->path_m);
  auto b = refinePath(world, plan->path_m);
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

// Real terrain: RRT* + LOSPO + refinement low over the White Mountains; every 2 m along the
// refined path the raw heightfield is at least the clearance below and the ceiling above, and the
// refinement shortens what LOSPO left.
TEST(PathRefinementOnTerrain, RefinedPathsKeepTheClearance) {
  SKYROUTE_REQUIRE_SHARED(dem_path, "dem/N44W072.hgt");
  CollisionWorldOptions wo;
  wo.ceiling_m = 900.0;
  wo.build_octree = false;
  auto world = loadTerrainWorld(dem_path, wo);
  ASSERT_TRUE(world.ok()) << world.error().describe();
  const Heightfield& hf = *world->heightfield;
  const Eigen::AlignedBox2d en = hf.boundsEn();
  std::uint64_t state = 4242;
  auto next = [&state]() {
    state = state * 6364136223846793005ULL + 1442695040888963407ULL;
    return static_cast<double>(state >> 11) * 0x1.0p-53;
  };
  const WorldMotionValidator whole(world->collision);
  int planned = 0;
  double lospo_total = 0.0, refined_total = 0.0;
  for (int attempt = 0; attempt < 2000 && planned < 3; ++attempt) {
    const Eigen::Vector2d s2 = en.min() + (en.sizes().array() * Eigen::Array2d(0.1 + 0.8 * next(), 0.1 + 0.8 * next())).matrix();
    const double d = 3000 + 3000 * next(), a = 6.283185307179586 * next();
    const Eigen::Vector2d g2 = s2 + d * Eigen::Vector2d(std::cos(a), std::sin(a));
    if (!en.contains(g2)) continue;
    const Eigen::Vector3d s(s2.x(), s2.y(), hf.heightAt(s2.x(), s2.y()) + wo.min_clearance_m + 30.0);
    const Eigen::Vector3d g(g2.x(), g2.y(), hf.heightAt(g2.x(), g2.y()) + wo.min_clearance_m + 30.0);
    if (!whole.isStateValid(s) || !whole.isStateValid(g) || whole.isMotionValid(s, g)) continue;
    const WorldMotionValidator v(world->collision, WorldMotionValidator::corridor(s, g, 0.5 * d));
    RrtStarOptions o;
    o.seed = static_cast<std::uint64_t>(attempt);
    auto r = RrtStar(v, o).plan(s, g, TerminationCondition().withIterationBudget(3000));
    ASSERT_TRUE(r.ok());
    if (!r->solved()) continue;
    ++planned;
    auto opt = lospo(v, r->path_m, LospoOptions{.spacing_m = 100.0, .max_vertices = 60, .max_passes = 2});
    ASSERT_TRUE(opt.ok());
    auto refined = refinePath(v, opt->path_m);
    ASSERT_TRUE(refined.ok()) << refined.error().describe();
    EXPECT_LE(refined->length_m, opt->length_m);
    lospo_total += opt->length_m;
    refined_total += refined->length_m;
    double lowest_agl = 1e9, highest = -1e9;
    const auto& path = refined->path_m;
    for (std::size_t i = 0; i + 1 < path.size(); ++i) {
      const int n = std::max(1, static_cast<int>(std::ceil((path[i + 1] - path[i]).norm() / 2.0)));
      for (int k = 0; k <= n; ++k) {
        const Eigen::Vector3d p = path[i] + (path[i + 1] - path[i]) * (double(k) / n);
        const double ground = hf.heightAt(p.x(), p.y());
        ASSERT_TRUE(std::isfinite(ground));
        lowest_agl = std::min(lowest_agl, p.z() - ground);
        highest = std::max(highest, p.z());
      }
    }
    EXPECT_GE(lowest_agl, wo.min_clearance_m - 1e-6) << "attempt " << attempt;
    EXPECT_LE(highest, wo.ceiling_m + 1e-9);
  }
  EXPECT_EQ(planned, 3);
  EXPECT_LT(refined_total, lospo_total);
}

}  // namespace
}  // namespace skyroute
