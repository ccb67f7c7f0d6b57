// Legs over a real DEM for the 3D planners' terrain tests (RRT* and LOSPO in rrt_star_test, the
// benchmarks' path refinement in tests/bench): seeded start/goal pairs 3-6 km apart, 30 m above
// the minimum clearance, whose straight line is blocked, and a dense check of a path against the
// raw heightfield and the ceiling that does not go through the planners' own motion checks.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <vector>

#include <Eigen/Core>

#include "planning/sampling/world_motion_validator.hpp"
#include "terrain/heightfield.hpp"

namespace skyroute::testing {

struct TerrainLeg {
  Eigen::Vector3d start_m;
  Eigen::Vector3d goal_m;
  double distance_m = 0.0;  // horizontal, start to goal
  int attempt = 0;          // which seeded draw this is (a seed for the planner)
};

// Calls use(leg) for seeded legs until it has returned true `wanted` times or 2000 draws are spent;
// returns how many times it returned true.
template <class Use>
int forEachBlockedLeg(const Heightfield& hf, const WorldMotionValidator& whole, double clearance_m, int wanted,
                      Use&& use) {
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
    const Eigen::Vector3d s(s2.x(), s2.y(), hf.heightAt(s2.x(), s2.y()) + clearance_m + 30.0);
    const Eigen::Vector3d g(g2.x(), g2.y(), hf.heightAt(g2.x(), g2.y()) + clearance_m + 30.0);
    if (!whole.isStateValid(s) || !whole.isStateValid(g) || whole.isMotionValid(s, g)) continue;
    if (use(TerrainLeg{s, g, d, attempt})) ++used;
  }
  return used;
}

struct PathHeights {
  double lowest_agl_m = 1e9;   // least height above the raw heightfield
  double highest_m = -1e9;     // greatest altitude
  bool ground_known = true;    // the heightfield had a height under every sample
};

// Every 2 m along the path.
inline PathHeights heightsAlong(const Heightfield& hf, const std::vector<Eigen::Vector3d>& path) {
  PathHeights out;
  for (std::size_t i = 0; i + 1 < path.size(); ++i) {
    const Eigen::Vector3d p0 = path[i], p1 = path[i + 1];
    const int n = std::max(1, static_cast<int>(std::ceil((p1 - p0).norm() / 2.0)));
    for (int k = 0; k <= n; ++k) {
      const Eigen::Vector3d p = p0 + (p1 - p0) * (double(k) / n);
      const double ground = hf.heightAt(p.x(), p.y());
      if (!std::isfinite(ground)) {
        out.ground_known = false;
        continue;
      }
      out.lowest_agl_m = std::min(out.lowest_agl_m, p.z() - ground);
      out.highest_m = std::max(out.highest_m, p.z());
    }
  }
  return out;
}

}  // namespace skyroute::testing
