// LOSPO (seed 003 section 2-3): never lengthens, never invalidates, approaches the taut path, and
// searches as the seed says (farthest visible vertex, testing from the goal backwards).
#include "planning/sampling/lospo.hpp"

#include <mutex>
#include <utility>
#include <vector>

#include <gtest/gtest.h>

#include "planning/sampling/rrt_star.hpp"
#include "tests/planning/synthetic_worlds.hpp"

namespace skyroute {
namespace {

using testing::BoxWorld;

TEST(Lospo, ZigzagInOpenSpaceBecomesTheStraightSegment) {
  const BoxWorld world(Eigen::AlignedBox3d(Eigen::Vector3d(0, 0, 0), Eigen::Vector3d(100, 100, 100)));
  const std::vector<Eigen::Vector3d> zigzag{{5, 5, 5}, {30, 60, 10}, {50, 10, 80}, {70, 90, 20}, {95, 50, 50}};
  auto r = lospo(world, zigzag);
  ASSERT_TRUE(r.ok()) << r.error().describe();
  ASSERT_EQ(r->path_m.size(), 2u);
  EXPECT_EQ(r->path_m.front(), zigzag.front());
  EXPECT_EQ(r->path_m.back(), zigzag.back());
  EXPECT_DOUBLE_EQ(r->length_m, (zigzag.back() - zigzag.front()).norm());
  EXPECT_DOUBLE_EQ(r->input_length_m, polylineLength(zigzag));
}

TEST(Lospo, WideDetourRoundAWallTightensToTheTautPath) {
  const BoxWorld world = testing::wallWorld();
  const Eigen::Vector3d s(20, 30, 10), g(80, 30, 10);
  const double taut = testing::wallWorldTautLength(s, g);
  // Goes round the wall far from its edge and wobbles in height.
  const std::vector<Eigen::Vector3d> detour{s, {15, 70, 3}, {30, 95, 18}, {70, 97, 2}, {90, 60, 15}, g};
  ASSERT_TRUE(world.denseCheck(detour, 0.01));
  double previous = polylineLength(detour);
  for (int passes : {1, 2, 4}) {
    auto r = lospo(world, detour, LospoOptions{.spacing_m = 0.5, .max_passes = passes});
    ASSERT_TRUE(r.ok());
    EXPECT_TRUE(world.denseCheck(r->path_m, 0.01));
    EXPECT_GE(r->length_m, taut - 1e-6);
    EXPECT_LE(r->length_m, previous + 1e-9) << passes << " passes";
    previous = r->length_m;
    if (passes == 1) {
      EXPECT_LT(r->length_m, 1.05 * taut);
    }
  }
  EXPECT_LT(previous, 1.01 * taut);
}

TEST(Lospo, NeverLengthensNorInvalidatesRrtStarPaths) {
  for (unsigned field = 1; field <= 6; ++field) {
    const BoxWorld world = testing::sphereField(field, 50);
    const Eigen::Vector3d s(2, 2, 2), g(98, 98, 98);
    RrtStarOptions o;
    o.seed = field;
    o.max_step_m = 10.0;
    auto plan = RrtStar(world, o).plan(s, g, TerminationCondition().withIterationBudget(1500));
    ASSERT_TRUE(plan.ok());
    ASSERT_TRUE(plan->solved()) << "field " << field;
    for (double spacing : {0.5, 3.0, 20.0}) {
      // With a vertex cap the spacing grows to length / 20 for the small spacings.
      const int max_vertices = spacing < 1.0 ? 20 : 0;
      auto r = lospo(world, plan->path_m, LospoOptions{.spacing_m = spacing, .max_vertices = max_vertices});
      ASSERT_TRUE(r.ok());
      EXPECT_LE(r->length_m, plan->length_m) << "field " << field << " spacing " << spacing;
      EXPECT_NEAR(r->length_m, polylineLength(r->path_m), 1e-9);
      EXPECT_TRUE(world.denseCheck(r->path_m, 0.01)) << "field " << field << " spacing " << spacing;
      EXPECT_EQ(r->path_m.front(), s);
      EXPECT_EQ(r->path_m.back(), g);
    }
  }
}

// Records every motion query, to check the order the seed prescribes.
class RecordingWorld : public MotionValidator {
 public:
  explicit RecordingWorld(const BoxWorld& inner) : inner_(inner) {}
  bool isStateValid(const Eigen::Vector3d& p) const override { return inner_.isStateValid(p); }
  bool isMotionValid(const Eigen::Vector3d& a, const Eigen::Vector3d& b) const override {
    std::lock_guard lock(mutex_);
    calls.emplace_back(a, b);
    return inner_.isMotionValid(a, b);
  }
  Eigen::AlignedBox3d samplingBounds() const override { return inner_.samplingBounds(); }
  mutable std::vector<std::pair<Eigen::Vector3d, Eigen::Vector3d>> calls;

 private:
  const BoxWorld& inner_;
  mutable std::mutex mutex_;
};

TEST(Lospo, SearchesFromTheGoalBackwardsForTheFarthestVisibleVertex) {
  const BoxWorld world = testing::wallWorld();
  const RecordingWorld recording(world);
  const Eigen::Vector3d s(40, 60, 10), c(50, 95, 10), g(60, 60, 10);
  const std::vector<Eigen::Vector3d> path{s, c, g};
  const double spacing = 10.0;
  // Without the point pre-filter every visibility test is a motion query, in the seed's order.
  auto r = lospo(recording, path, LospoOptions{.spacing_m = spacing, .merge_collinear = false, .point_prefilter = false});
  ASSERT_TRUE(r.ok());
  const std::vector<Eigen::Vector3d> dense = densifyPath(path, spacing);
  // Two input checks first, then the first vertex tries the goal, then each vertex back from it.
  ASSERT_GE(recording.calls.size(), 4u);
  EXPECT_EQ(recording.calls[2].first, s);
  EXPECT_EQ(recording.calls[2].second, g);
  EXPECT_EQ(recording.calls[3].first, s);
  EXPECT_EQ(recording.calls[3].second, dense[dense.size() - 2]);
  // The goal is blocked from s by the wall; the first connection goes to the farthest vertex s sees.
  std::size_t farthest = 0;
  for (std::size_t k = dense.size() - 1; k > 0; --k) {
    if (world.isMotionValid(s, dense[k])) {
      farthest = k;
      break;
    }
  }
  ASSERT_GT(farthest, 1u);
  ASSERT_LT(farthest, dense.size() - 1);
  // The second output vertex is the first vertex re-inserted along s -> dense[farthest].
  const Eigen::Vector3d dir = (dense[farthest] - s).normalized();
  const Eigen::Vector3d second = r->path_m[1];
  EXPECT_NEAR(((second - s) - dir * (second - s).dot(dir)).norm(), 0.0, 1e-9);
  EXPECT_LE((second - s).norm(), spacing + 1e-9);
  EXPECT_LE(r->length_m, polylineLength(path));
  EXPECT_TRUE(world.denseCheck(r->path_m, 0.01));
}

// The point pre-filter only skips motion checks that would fail: the same path comes out, with
// fewer motion checks, on RRT* paths through the wall and the sphere fields.
TEST(Lospo, PointPrefilterGivesTheSamePathWithFewerMotionChecks) {
  std::uint64_t with_checks = 0, without_checks = 0, point_checks = 0;
  for (unsigned field = 0; field <= 4; ++field) {
    const BoxWorld world = field == 0 ? testing::wallWorld() : testing::sphereField(field, 40);
    const Eigen::Vector3d s = field == 0 ? Eigen::Vector3d(20, 30, 10) : Eigen::Vector3d(2, 2, 2);
    const Eigen::Vector3d g = field == 0 ? Eigen::Vector3d(80, 30, 10) : Eigen::Vector3d(98, 98, 98);
    RrtStarOptions o;
    o.seed = 11 + field;
    auto plan = RrtStar(world, o).plan(s, g, TerminationCondition().withIterationBudget(1500));
    ASSERT_TRUE(plan.ok() && plan->solved()) << "field " << field;
    for (double spacing : {1.0, 4.0}) {
      LospoOptions lo{.spacing_m = spacing, .max_passes = 3};
      lo.point_prefilter = true;
      auto with = lospo(world, plan->path_m, lo);
      lo.point_prefilter = false;
      auto without = lospo(world, plan->path_m, lo);
      ASSERT_TRUE(with.ok() && without.ok());
      ASSERT_EQ(with->path_m.size(), without->path_m.size()) << "field " << field << " spacing " << spacing;
      for (std::size_t i = 0; i < with->path_m.size(); ++i) EXPECT_EQ(with->path_m[i], without->path_m[i]);
      EXPECT_EQ(with->passes, without->passes);
      EXPECT_LE(with->motion_checks, without->motion_checks);
      EXPECT_EQ(without->point_checks, 0u);
      with_checks += with->motion_checks;
      without_checks += without->motion_checks;
      point_checks += with->point_checks;
    }
  }
  EXPECT_LT(with_checks, without_checks);
  EXPECT_GT(point_checks, 0u);
}

TEST(Lospo, BadInputIsAnErrorNamingTheField) {
  const BoxWorld world = testing::wallWorld();
  auto r = lospo(world, {Eigen::Vector3d(1, 1, 1)});
  ASSERT_FALSE(r.ok());
  EXPECT_EQ(r.error().field, "path");
  // Straight through the wall.
  r = lospo(world, {Eigen::Vector3d(20, 30, 10), Eigen::Vector3d(30, 30, 10), Eigen::Vector3d(80, 30, 10)});
  ASSERT_FALSE(r.ok());
  EXPECT_EQ(r.error().code, ErrorCode::kInvalidArgument);
  EXPECT_EQ(r.error().field, "path");
  EXPECT_NE(r.error().message.find("segment 1 -> 2"), std::string::npos) << r.error().message;
  const std::vector<Eigen::Vector3d> ok{Eigen::Vector3d(20, 30, 10), Eigen::Vector3d(20, 40, 10)};
  r = lospo(world, ok, LospoOptions{.spacing_m = 0.0});
  ASSERT_FALSE(r.ok());
  EXPECT_EQ(r.error().field, "spacing_m");
  r = lospo(world, ok, LospoOptions{.spacing_m = 1e-9});
  ASSERT_FALSE(r.ok());
  EXPECT_EQ(r.error().field, "spacing_m");
  r = lospo(world, ok, LospoOptions{.max_vertices = -1});
  ASSERT_FALSE(r.ok());
  EXPECT_EQ(r.error().field, "max_vertices");
  r = lospo(world, ok, LospoOptions{.max_passes = 0});
  ASSERT_FALSE(r.ok());
  EXPECT_EQ(r.error().field, "max_passes");
  r = lospo(world, {Eigen::Vector3d(20, 30, 10), Eigen::Vector3d(std::nan(""), 40, 10)});
  ASSERT_FALSE(r.ok());
  EXPECT_EQ(r.error().field, "path");
}

TEST(Lospo, CancelledRunStillReturnsTheValidInput) {
  const BoxWorld world = testing::wallWorld();
  const std::vector<Eigen::Vector3d> detour{{20, 30, 10}, {30, 95, 18}, {70, 97, 2}, {80, 30, 10}};
  auto cancel = std::make_shared<std::atomic<bool>>(true);
  auto r = lospo(world, detour, LospoOptions{}, TerminationCondition().withCancelFlag(cancel));
  ASSERT_TRUE(r.ok());
  EXPECT_TRUE(r->stopped_early);
  EXPECT_TRUE(world.denseCheck(r->path_m, 0.01));
  EXPECT_LE(r->length_m, polylineLength(detour) + 1e-9);
  EXPECT_EQ(r->path_m.front(), detour.front());
  EXPECT_EQ(r->path_m.back(), detour.back());
}

TEST(Lospo, DensifyKeepsVerticesAndBoundsTheSpacing) {
  const std::vector<Eigen::Vector3d> path{{0, 0, 0}, {10, 0, 0}, {10, 3, 4}};
  const auto dense = densifyPath(path, 2.0);
  ASSERT_EQ(dense.size(), 1u + 5u + 3u);  // 10 m in 5 pieces, 5 m in 3 pieces
  EXPECT_EQ(dense[5], path[1]);
  EXPECT_EQ(dense.back(), path[2]);
  for (std::size_t i = 1; i < dense.size(); ++i) EXPECT_LE((dense[i] - dense[i - 1]).norm(), 2.0 + 1e-12);
  EXPECT_DOUBLE_EQ(polylineLength(dense), polylineLength(path));
}

}  // namespace
}  // namespace skyroute
