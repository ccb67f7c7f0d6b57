// The 3D planners' real-terrain tests (RRT* and LOSPO in rrt_star_test, the benchmarks' path
// refinement in tests/bench): the White Mountains (N44W072) under a 900 m ceiling, seeded legs
// 3-6 km long, 30 m above the minimum clearance, whose straight line is blocked, planned by RRT*
// and LOSPO, and a dense check of a path against the raw heightfield and the ceiling that does not
// go through the planners' own motion checks.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <utility>
#include <vector>

#include <Eigen/Core>
#include <gtest/gtest.h>

#include "planning/sampling/lospo.hpp"
#include "planning/sampling/rrt_star.hpp"
#include "planning/sampling/world_motion_validator.hpp"
#include "terrain/terrain_world.hpp"
#include "tests/test_data.hpp"

namespace skyroute::testing {

struct TerrainLeg {
  Eigen::Vector3d start_m;
  Eigen::Vector3d goal_m;
  double distance_m = 0.0;  // horizontal, start to goal
  int attempt = 0;          // which seeded draw this is (the planner's seed)
};

class WhiteMountains : public ::testing::Test {
 protected:
  void SetUp() override {
    SKYROUTE_REQUIRE_SHARED(dem_path, "dem/N44W072.hgt");
    options_.ceiling_m = 900.0;
    options_.build_octree = false;
    auto world = loadTerrainWorld(dem_path, options_);
    ASSERT_TRUE(world.ok()) << world.error().describe();
    world_ = std::move(world).value();
  }

  // Calls use(leg, validator, rrt_star, lospo) for seeded legs that RRT* (4000 iterations, seeded
  // by the leg's draw, in a corridor round the leg) solves, with LOSPO (50 m spacing) on its path,
  // until it has done so `wanted` times or 2000 draws are spent (some valleys are closed under the
  // ceiling); returns how many legs it used.
  template <class Use>
  int forEachPlannedLeg(int wanted, Use&& use) const {
    const Heightfield& hf = *world_.heightfield;
    const WorldMotionValidator whole(world_.collision);
    const Eigen::AlignedBox2d en = hf.boundsEn();
    std::uint64_t state = 99;
    auto next = [&state]() {
      state = state * 6364136223846793005ULL + 1442695040888963407ULL;
      return static_cast<double>(state >> 11) * 0x1.0p-53;
    };
    int used = 0;
    for (int attempt = 0; attempt < 2000 && used < wanted; ++attempt) {
      const Eigen::Vector2d s2 = en.min() + (en.sizes().array() * Eigen::Array2d(0.1 + 0.8 * next(), 0.1 + 0.8 * next())).matrix();
      const double d = 3000 + 3000 * next(), a = 6.283185307179586 * next();
      const Eigen::Vector2d g2 = s2 + d * Eigen::Vector2d(std::cos(a), std::sin(a));
      if (!en.contains(g2)) continue;
      const TerrainLeg leg{Eigen::Vector3d(s2.x(), s2.y(), hf.heightAt(s2.x(), s2.y()) + options_.min_clearance_m + 30.0),
                           Eigen::Vector3d(g2.x(), g2.y(), hf.heightAt(g2.x(), g2.y()) + options_.min_clearance_m + 30.0),
                           d, attempt};
      if (!whole.isStateValid(leg.start_m) || !whole.isStateValid(leg.goal_m) || whole.isMotionValid(leg.start_m, leg.goal_m)) {
        continue;
      }
      const WorldMotionValidator v(world_.collision, WorldMotionValidator::corridor(leg.start_m, leg.goal_m, 0.5 * d));
      RrtStarOptions o;
      o.seed = static_cast<std::uint64_t>(attempt);
      auto r = RrtStar(v, o).plan(leg.start_m, leg.goal_m, TerminationCondition().withIterationBudget(4000));
      EXPECT_TRUE(r.ok());
      if (!r.ok() || !r->solved()) continue;
      ++used;
      auto shortened = lospo(v, r->path_m, LospoOptions{.spacing_m = 50.0});
      EXPECT_TRUE(shortened.ok()) << shortened.error().describe();
      if (shortened.ok()) use(leg, v, *r, *shortened);
    }
    return used;
  }

  // Every 2 m along the path the raw heightfield is known and at least the clearance below, and
  // the path is under the ceiling.
  void expectClearOfTerrain(const std::vector<Eigen::Vector3d>& path, int attempt) const {
    const Heightfield& hf = *world_.heightfield;
    double lowest_agl = 1e9, highest = -1e9;
    for (std::size_t i = 0; i + 1 < path.size(); ++i) {
      const Eigen::Vector3d p0 = path[i], p1 = path[i + 1];
      const int n = std::max(1, static_cast<int>(std::ceil((p1 - p0).norm() / 2.0)));
      for (int k = 0; k <= n; ++k) {
        const Eigen::Vector3d p = p0 + (p1 - p0) * (double(k) / n);
        const double ground = hf.heightAt(p.x(), p.y());
        ASSERT_TRUE(std::isfinite(ground)) << "attempt " << attempt;
        lowest_agl = std::min(lowest_agl, p.z() - ground);
        highest = std::max(highest, p.z());
      }
    }
    EXPECT_GE(lowest_agl, options_.min_clearance_m - 1e-6) << "attempt " << attempt;
    EXPECT_LE(highest, options_.ceiling_m + 1e-9) << "attempt " << attempt;
  }

  CollisionWorldOptions options_;
  TerrainWorld world_;
};

}  // namespace skyroute::testing
