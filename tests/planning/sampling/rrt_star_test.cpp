// RRT* on synthetic worlds (exact segment checks) and on a real DEM.
// Every path is checked against an independent dense point check; lengths against analytic optima.
#include "planning/sampling/rrt_star.hpp"

#include <atomic>
#include <chrono>
#include <functional>
#include <memory>
#include <ostream>
#include <string>

#include <gtest/gtest.h>

#include "planning/sampling/lospo.hpp"
#include "planning/sampling/world_motion_validator.hpp"
#include "tests/planning/synthetic_worlds.hpp"
#include "tests/planning/terrain_legs.hpp"

namespace skyroute {
namespace {

using testing::BoxWorld;

// Tests written once for every configuration of the 3D planner (OMPL style): each case builds a
// planner from a validator and options.
struct PlannerCase {
  std::string name;
  std::function<RrtStarOptions()> options;
};

// Test listings show the case's name, not its bytes.
void PrintTo(const PlannerCase& c, std::ostream* out) { *out << c.name; }

class EveryRrtStar : public ::testing::TestWithParam<PlannerCase> {
 protected:
  RrtStarOptions options(std::uint64_t seed) const {
    RrtStarOptions o = GetParam().options();
    o.seed = seed;
    return o;
  }
};

RrtStarResult planOk(const MotionValidator& world, const RrtStarOptions& o, const Eigen::Vector3d& s,
                     const Eigen::Vector3d& g, const TerminationCondition& stop) {
  auto r = RrtStar(world, o).plan(s, g, stop);
  EXPECT_TRUE(r.ok()) << (r.ok() ? "" : r.error().describe());
  return r.ok() ? r.value() : RrtStarResult{};
}

TEST_P(EveryRrtStar, FindsAValidPathRoundAWallNoShorterThanTheTautPath) {
  const BoxWorld world = testing::wallWorld();
  const Eigen::Vector3d s(20, 30, 10), g(80, 30, 10);
  const double taut = testing::wallWorldTautLength(s, g);
  for (std::uint64_t seed = 1; seed <= 5; ++seed) {
    const RrtStarResult r = planOk(world, options(seed), s, g, TerminationCondition().withIterationBudget(3000));
    ASSERT_EQ(r.status, PlannerStatus::kSolved) << to_string(r.status);
    ASSERT_GE(r.path_m.size(), 3u);
    EXPECT_EQ(r.path_m.front(), s);
    EXPECT_EQ(r.path_m.back(), g);
    EXPECT_TRUE(world.denseCheck(r.path_m, 0.01)) << "seed " << seed;
    EXPECT_NEAR(r.length_m, polylineLength(r.path_m), 1e-9);
    EXPECT_GE(r.length_m, taut - 1e-6);
    EXPECT_LT(r.length_m, 1.5 * taut) << "seed " << seed;  // RRT* alone, 3000 samples: loose bound
    EXPECT_EQ(r.iterations, 3000u);
    EXPECT_EQ(r.stop_reason, TerminationCondition::Reason::kIterations);
    EXPECT_GT(r.tree_size, 100u);
    EXPECT_GE(r.first_solution_s, 0.0);
    EXPECT_LE(r.first_solution_iteration, r.iterations);
    // LOSPO on top brings it close to the taut path round the edge.
    auto opt = lospo(world, r.path_m, LospoOptions{.spacing_m = 0.5, .max_passes = 4});
    ASSERT_TRUE(opt.ok());
    EXPECT_TRUE(world.denseCheck(opt->path_m, 0.01));
    EXPECT_LE(opt->length_m, r.length_m);
    EXPECT_LT(opt->length_m, 1.02 * taut) << "seed " << seed;
  }
}

TEST_P(EveryRrtStar, PathsThroughASphereFieldAreCollisionFree) {
  for (unsigned field = 1; field <= 4; ++field) {
    const BoxWorld world = testing::sphereField(field, 40);
    const Eigen::Vector3d s(2, 2, 2), g(98, 98, 98);
    const RrtStarResult r = planOk(world, options(field), s, g, TerminationCondition().withIterationBudget(2000));
    ASSERT_EQ(r.status, PlannerStatus::kSolved) << "field " << field;
    EXPECT_TRUE(world.denseCheck(r.path_m, 0.01)) << "field " << field;
    EXPECT_GE(r.length_m, (g - s).norm() - 1e-9);
  }
}

TEST_P(EveryRrtStar, MoreIterationsNeverLengthenTheSolution) {
  // With the same seed a longer budget continues the same run, so the best cost can only drop.
  const BoxWorld world = testing::sphereField(7, 60);
  const Eigen::Vector3d s(2, 2, 2), g(98, 98, 98);
  double previous = std::numeric_limits<double>::infinity();
  for (std::uint64_t budget : {500u, 1500u, 5000u}) {
    const RrtStarResult r = planOk(world, options(3), s, g, TerminationCondition().withIterationBudget(budget));
    ASSERT_EQ(r.status, PlannerStatus::kSolved);
    EXPECT_LE(r.length_m, previous + 1e-9) << "budget " << budget;
    previous = r.length_m;
  }
}

TEST_P(EveryRrtStar, SameSeedGivesBitIdenticalResults) {
  const BoxWorld world = testing::sphereField(3, 50);
  const Eigen::Vector3d s(2, 2, 2), g(98, 98, 98);
  const auto stop = TerminationCondition().withIterationBudget(2500);
  const RrtStarResult a = planOk(world, options(42), s, g, stop);
  const RrtStarResult b = planOk(world, options(42), s, g, stop);
  const RrtStarResult c = planOk(world, options(43), s, g, stop);
  ASSERT_EQ(a.status, PlannerStatus::kSolved);
  ASSERT_EQ(a.path_m.size(), b.path_m.size());
  for (std::size_t i = 0; i < a.path_m.size(); ++i) EXPECT_EQ(a.path_m[i], b.path_m[i]) << i;  // bitwise
  EXPECT_EQ(a.length_m, b.length_m);
  EXPECT_EQ(a.tree_size, b.tree_size);
  EXPECT_EQ(a.motion_checks, b.motion_checks);
  EXPECT_EQ(a.solution_improvements, b.solution_improvements);
  EXPECT_NE(a.length_m, c.length_m);  // another seed explores another tree
}

TEST_P(EveryRrtStar, InvalidStartAndGoalAreReportedBeforeSearching) {
  BoxWorld world = testing::wallWorld();
  const Eigen::Vector3d free_point(20, 30, 10);
  const Eigen::Vector3d in_wall(50, 30, 10);
  const Eigen::Vector3d outside(-5, 30, 10);
  const auto stop = TerminationCondition().withIterationBudget(1000);
  EXPECT_EQ(planOk(world, options(1), in_wall, free_point, stop).status, PlannerStatus::kStartInvalid);
  EXPECT_EQ(planOk(world, options(1), outside, free_point, stop).status, PlannerStatus::kStartInvalid);
  EXPECT_EQ(planOk(world, options(1), free_point, in_wall, stop).status, PlannerStatus::kGoalInvalid);
  const RrtStarResult r = planOk(world, options(1), free_point, outside, stop);
  EXPECT_EQ(r.status, PlannerStatus::kGoalInvalid);
  EXPECT_EQ(r.iterations, 0u);
  EXPECT_TRUE(r.path_m.empty());
  EXPECT_EQ(to_string(PlannerStatus::kGoalInvalid), "goal invalid");
}

// A goal sealed inside a closed shell of six boxes.
BoxWorld sealedGoalWorld() {
  BoxWorld w(Eigen::AlignedBox3d(Eigen::Vector3d(0, 0, 0), Eigen::Vector3d(100, 100, 100)));
  const double lo = 60, hi = 80, t = 1;
  w.addBox({lo - t, lo - t, lo - t}, {hi + t, hi + t, lo});  // floor
  w.addBox({lo - t, lo - t, hi}, {hi + t, hi + t, hi + t});  // lid
  w.addBox({lo - t, lo - t, lo - t}, {lo, hi + t, hi + t});
  w.addBox({hi, lo - t, lo - t}, {hi + t, hi + t, hi + t});
  w.addBox({lo - t, lo - t, lo - t}, {hi + t, lo, hi + t});
  w.addBox({lo - t, hi, lo - t}, {hi + t, hi + t, hi + t});
  return w;
}

TEST_P(EveryRrtStar, UnreachableGoalEndsWithAClearStatusWithinTheBudget) {
  const BoxWorld world = sealedGoalWorld();
  const Eigen::Vector3d s(10, 10, 10), g(70, 70, 70);
  // Deadline: timeout, close to the deadline (generous margin for sanitizer builds).
  const RrtStarResult by_time = planOk(world, options(1), s, g, TerminationCondition::afterMilliseconds(100));
  EXPECT_EQ(by_time.status, PlannerStatus::kTimeout);
  EXPECT_EQ(by_time.stop_reason, TerminationCondition::Reason::kDeadline);
  // The deadline's clock starts when the condition is made, just before the planner's own clock,
  // so the planner's time can fall short of 100 ms by microseconds.
  EXPECT_GE(by_time.time_s, 0.1 - 1e-3);
  EXPECT_LT(by_time.time_s, 1.0);
  EXPECT_TRUE(by_time.path_m.empty());
  // Deadline in the thread's CPU time: the same status, and the thread did spend the budget.
  const auto cpu_before = TerminationCondition::threadCpuNow();
  const RrtStarResult by_cpu = planOk(world, options(1), s, g, TerminationCondition::afterThreadCpuMilliseconds(50));
  const auto cpu_spent = TerminationCondition::threadCpuNow() - cpu_before;
  EXPECT_EQ(by_cpu.status, PlannerStatus::kTimeout);
  EXPECT_EQ(by_cpu.stop_reason, TerminationCondition::Reason::kDeadline);
  EXPECT_GE(cpu_spent, std::chrono::milliseconds(50));
  EXPECT_GT(by_cpu.iterations, 0u);
  // Iteration budget: no path.
  const RrtStarResult by_count = planOk(world, options(1), s, g, TerminationCondition().withIterationBudget(2000));
  EXPECT_EQ(by_count.status, PlannerStatus::kBudgetExhausted);
  EXPECT_EQ(by_count.iterations, 2000u);
  // Node budget: no path, tree capped.
  RrtStarOptions capped = options(1);
  capped.max_nodes = 300;
  const RrtStarResult by_nodes = planOk(world, capped, s, g, TerminationCondition().withIterationBudget(100000));
  EXPECT_EQ(by_nodes.status, PlannerStatus::kBudgetExhausted);
  EXPECT_TRUE(by_nodes.node_budget_reached);
  EXPECT_EQ(by_nodes.tree_size, 300u);
  // Cancel flag.
  auto cancel = std::make_shared<std::atomic<bool>>(true);
  const RrtStarResult cancelled = planOk(world, options(1), s, g, TerminationCondition::afterMilliseconds(10000).withCancelFlag(cancel));
  EXPECT_EQ(cancelled.status, PlannerStatus::kCancelled);
  EXPECT_LT(cancelled.time_s, 1.0);
  // Approximate: ends at the node nearest the goal, outside the shell, on a valid path.
  RrtStarOptions approx = options(1);
  approx.allow_approximate = true;
  const RrtStarResult a = planOk(world, approx, s, g, TerminationCondition().withIterationBudget(2000));
  EXPECT_EQ(a.status, PlannerStatus::kApproximate);
  ASSERT_GE(a.path_m.size(), 2u);
  EXPECT_TRUE(world.denseCheck(a.path_m, 0.01));
  EXPECT_GT(a.distance_to_goal_m, 10.0 - 1e-9);  // the shell keeps every node >= 10 m from its centre
  EXPECT_NEAR(a.distance_to_goal_m, (a.path_m.back() - g).norm(), 1e-9);
}

TEST_P(EveryRrtStar, StraightLineWhenTheGoalIsInSight) {
  const BoxWorld world = testing::wallWorld();
  const Eigen::Vector3d s(10, 90, 5), g(90, 85, 15);
  RrtStarOptions o = options(1);
  o.try_direct_first = false;
  const RrtStarResult r = planOk(world, o, s, g, TerminationCondition().withIterationBudget(3000));
  ASSERT_EQ(r.status, PlannerStatus::kSolved);
  EXPECT_TRUE(world.denseCheck(r.path_m, 0.01));
  EXPECT_LT(r.length_m, 1.05 * (g - s).norm());
  o.try_direct_first = true;
  const RrtStarResult d = planOk(world, o, s, g, TerminationCondition().withIterationBudget(3000));
  ASSERT_EQ(d.status, PlannerStatus::kSolved);
  EXPECT_EQ(d.path_m.size(), 2u);
  EXPECT_DOUBLE_EQ(d.length_m, (g - s).norm());
}

// The near-set and tree-pruning switches (skip_hopeless with the benchmark's goal bias 0.1 and
// rewire factor 2).
std::function<RrtStarOptions()> searchOptions(bool k_nearest, bool prune_tree, bool skip_hopeless) {
  return [=] {
    RrtStarOptions o;
    o.k_nearest = k_nearest;
    o.prune_tree = prune_tree;
    o.skip_hopeless_checks = skip_hopeless;
    if (skip_hopeless) {
      o.goal_bias = 0.1;
      o.rewire_factor = 2.0;
    }
    return o;
  };
}

INSTANTIATE_TEST_SUITE_P(
    Configurations, EveryRrtStar,
    ::testing::Values(PlannerCase{"informed", [] { return RrtStarOptions{}; }},
                      PlannerCase{"uniform", [] {
                                    RrtStarOptions o;
                                    o.informed_sampling = false;
                                    return o;
                                  }},
                      PlannerCase{"short_steps", [] {
                                    RrtStarOptions o;
                                    o.max_step_m = 8.0;
                                    o.goal_bias = 0.1;
                                    return o;
                                  }},
                      PlannerCase{"k_nearest", searchOptions(true, false, false)},
                      PlannerCase{"pruned", searchOptions(false, true, false)},
                      PlannerCase{"pruned_k_nearest", searchOptions(true, true, false)},
                      PlannerCase{"skip_hopeless", searchOptions(false, false, true)}),
    [](const ::testing::TestParamInfo<PlannerCase>& info) { return info.param.name; });

TEST(RrtStar, BadArgumentsAreErrorsNamingTheField) {
  const BoxWorld world = testing::wallWorld();
  const Eigen::Vector3d ok(20, 30, 10);
  const Eigen::Vector3d nan(std::nan(""), 1, 1);
  const auto stop = TerminationCondition().withIterationBudget(10);
  auto r = RrtStar(world).plan(nan, ok, stop);
  ASSERT_FALSE(r.ok());
  EXPECT_EQ(r.error().code, ErrorCode::kInvalidArgument);
  EXPECT_EQ(r.error().field, "start");
  r = RrtStar(world).plan(ok, nan, stop);
  ASSERT_FALSE(r.ok());
  EXPECT_EQ(r.error().field, "goal");
  RrtStarOptions o;
  o.goal_bias = 1.0;
  r = RrtStar(world, o).plan(ok, ok, stop);
  ASSERT_FALSE(r.ok());
  EXPECT_EQ(r.error().field, "goal_bias");
  o = RrtStarOptions{};
  o.rewire_factor = 0.5;
  r = RrtStar(world, o).plan(ok, ok, stop);
  ASSERT_FALSE(r.ok());
  EXPECT_EQ(r.error().field, "rewire_factor");
  o = RrtStarOptions{};
  o.max_step_m = -1;
  r = RrtStar(world, o).plan(ok, ok, stop);
  ASSERT_FALSE(r.ok());
  EXPECT_EQ(r.error().field, "max_step_m");
  o = RrtStarOptions{};
  o.guide_m = {ok};
  o.guide_bias = 1.0;
  r = RrtStar(world, o).plan(ok, ok, stop);
  ASSERT_FALSE(r.ok());
  EXPECT_EQ(r.error().field, "guide_bias");
  o.guide_bias = 0.5;
  o.guide_radius_m = -1.0;
  r = RrtStar(world, o).plan(ok, ok, stop);
  ASSERT_FALSE(r.ok());
  EXPECT_EQ(r.error().field, "guide_radius_m");
  o.guide_radius_m = 1.0;
  o.guide_m = {ok, nan};
  r = RrtStar(world, o).plan(ok, ok, stop);
  ASSERT_FALSE(r.ok());
  EXPECT_EQ(r.error().field, "guide_m");
  const BoxWorld flat(Eigen::AlignedBox3d(Eigen::Vector3d(0, 0, 0), Eigen::Vector3d(10, 10, 0)));
  r = RrtStar(flat).plan(Eigen::Vector3d(1, 1, 0), Eigen::Vector3d(2, 2, 0), stop);
  ASSERT_FALSE(r.ok());
  EXPECT_EQ(r.error().field, "sampling bounds");
}

// Guided samples (a coarse way round the wall's end) still give a valid path, reproducible from
// the seed, and a guide with no bias draws exactly as no guide at all.
TEST(RrtStar, GuidedSamplesKeepPathsValidAndReproducible) {
  const BoxWorld world = testing::wallWorld();
  const Eigen::Vector3d s(20, 30, 10), g(80, 30, 10);
  RrtStarOptions o;
  o.seed = 9;
  o.guide_m = {{30, 60, 5}, {40, 85, 5}, {50, 90, 5}, {60, 85, 5}, {70, 60, 5}};
  o.guide_bias = 0.5;
  o.guide_radius_m = 5.0;
  const auto stop = TerminationCondition().withIterationBudget(1500);
  auto a = RrtStar(world, o).plan(s, g, stop);
  auto b = RrtStar(world, o).plan(s, g, stop);
  ASSERT_TRUE(a.ok() && b.ok());
  ASSERT_TRUE(a->solved());
  EXPECT_TRUE(world.denseCheck(a->path_m, 0.05));
  EXPECT_GE(a->length_m, testing::wallWorldTautLength(s, g) - 1e-6);
  EXPECT_EQ(a->path_m, b->path_m);
  RrtStarOptions unbiased = o;
  unbiased.guide_bias = 0.0;
  RrtStarOptions plain = o;
  plain.guide_m.clear();
  auto c = RrtStar(world, unbiased).plan(s, g, stop);
  auto d = RrtStar(world, plain).plan(s, g, stop);
  ASSERT_TRUE(c.ok() && d.ok());
  EXPECT_EQ(c->path_m, d->path_m);
  EXPECT_EQ(c->tree_size, d->tree_size);
}

TEST(RrtStar, RewireRadiusFollowsKaramanFrazzoli) {
  // d = 3: gamma* = 2 (4/3)^(1/3) (V / (4 pi / 3))^(1/3), radius = factor gamma* (log n / n)^(1/3).
  const double volume = 1000.0;
  const double unit_ball = 4.0 / 3.0 * 3.14159265358979323846;
  const double gamma = 2.0 * std::cbrt(4.0 / 3.0) * std::cbrt(volume / unit_ball);
  for (std::size_t n : {10u, 100u, 10000u}) {
    const double expected = 1.1 * gamma * std::cbrt(std::log(double(n)) / double(n));
    EXPECT_NEAR(rrtStarRewireRadius(n, 3, volume, 1.1), expected, 1e-12 * expected);
  }
  // The radius shrinks as the tree grows.
  EXPECT_GT(rrtStarRewireRadius(100, 3, volume, 1.1), rrtStarRewireRadius(1000, 3, volume, 1.1));
}

// Real terrain: plan low over the White Mountains under a ceiling; every 2 m along the path (and
// after LOSPO) the raw heightfield must be at least the clearance below, and the ceiling above.
class RrtStarOnTerrain : public testing::WhiteMountains {};

TEST_F(RrtStarOnTerrain, PathsOverARealDemKeepTheClearance) {
  const int planned = forEachPlannedLeg(3, [&](const testing::TerrainLeg& leg, const WorldMotionValidator&,
                                               const RrtStarResult& r, const LospoResult& shortened) {
    EXPECT_LE(shortened.length_m, r.length_m);
    expectClearOfTerrain(r.path_m, leg.attempt);
    expectClearOfTerrain(shortened.path_m, leg.attempt);
  });
  EXPECT_EQ(planned, 3);
}

}  // namespace
}  // namespace skyroute
