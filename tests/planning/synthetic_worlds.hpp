// Synthetic 3D worlds for planner tests: a box world with spheres and axis-aligned boxes (walls),
// a point vehicle, exact segment checks (closest point to a sphere's centre, slab test for boxes),
// and an independent dense check that only asks whether single points are inside an obstacle.
#pragma once

#include <algorithm>
#include <cmath>
#include <utility>
#include <vector>

#include <Eigen/Core>
#include <Eigen/Geometry>

#include "planning/core/motion_validator.hpp"

namespace skyroute::testing {

struct Sphere {
  Eigen::Vector3d centre;
  double radius;
};

class BoxWorld : public MotionValidator {
 public:
  explicit BoxWorld(Eigen::AlignedBox3d bounds) : bounds_(std::move(bounds)) {}
  void addSphere(const Eigen::Vector3d& c, double r) { spheres_.push_back({c, r}); }
  void addBox(const Eigen::Vector3d& lo, const Eigen::Vector3d& hi) { boxes_.emplace_back(lo, hi); }

  bool isStateValid(const Eigen::Vector3d& p) const override {
    return pointFree(p);
  }
  bool isMotionValid(const Eigen::Vector3d& a, const Eigen::Vector3d& b) const override {
    if (!bounds_.contains(a) || !bounds_.contains(b)) return false;  // the box is convex
    for (const auto& s : spheres_) {
      const Eigen::Vector3d ab = b - a;
      const double len2 = ab.squaredNorm();
      const double t = len2 > 0 ? std::clamp((s.centre - a).dot(ab) / len2, 0.0, 1.0) : 0.0;
      if ((a + t * ab - s.centre).norm() <= s.radius) return false;
    }
    for (const auto& box : boxes_) {
      if (segmentHitsBox(a, b, box)) return false;
    }
    return true;
  }
  Eigen::AlignedBox3d samplingBounds() const override { return bounds_; }

  // Independent of isMotionValid: only point-in-obstacle tests.
  bool pointFree(const Eigen::Vector3d& p) const {
    if (!bounds_.contains(p)) return false;
    for (const auto& s : spheres_) {
      if ((p - s.centre).norm() <= s.radius) return false;
    }
    for (const auto& box : boxes_) {
      if (box.contains(p)) return false;
    }
    return true;
  }
  // Every point along the path every step_m is free.
  bool denseCheck(const std::vector<Eigen::Vector3d>& path, double step_m) const {
    if (path.empty()) return false;
    for (std::size_t i = 0; i + 1 < path.size(); ++i) {
      const double len = (path[i + 1] - path[i]).norm();
      const int n = std::max(1, static_cast<int>(std::ceil(len / step_m)));
      for (int k = 0; k <= n; ++k) {
        if (!pointFree(path[i] + (path[i + 1] - path[i]) * (static_cast<double>(k) / n))) return false;
      }
    }
    return pointFree(path.back());
  }

 private:
  static bool segmentHitsBox(const Eigen::Vector3d& a, const Eigen::Vector3d& b, const Eigen::AlignedBox3d& box) {
    double t0 = 0.0, t1 = 1.0;
    const Eigen::Vector3d d = b - a;
    for (int i = 0; i < 3; ++i) {
      if (std::abs(d[i]) < 1e-15) {
        if (a[i] < box.min()[i] || a[i] > box.max()[i]) return false;
        continue;
      }
      double ta = (box.min()[i] - a[i]) / d[i];
      double tb = (box.max()[i] - a[i]) / d[i];
      if (ta > tb) std::swap(ta, tb);
      t0 = std::max(t0, ta);
      t1 = std::min(t1, tb);
      if (t0 > t1) return false;
    }
    return true;
  }

  Eigen::AlignedBox3d bounds_;
  std::vector<Sphere> spheres_;
  std::vector<Eigen::AlignedBox3d> boxes_;
};

// 100 x 100 x 20 m world with a wall at x in [48, 52] spanning the full height and y from 0 to 80:
// the only way round is past the vertical edge at (x, y) = (48 or 52, 80). Start and goal at the
// same height, so the taut path is the 2D shortest path round the two edge corners.
inline BoxWorld wallWorld() {
  BoxWorld w(Eigen::AlignedBox3d(Eigen::Vector3d(0, 0, 0), Eigen::Vector3d(100, 100, 20)));
  w.addBox(Eigen::Vector3d(48, -1, -1), Eigen::Vector3d(52, 80, 21));
  return w;
}
inline double wallWorldTautLength(const Eigen::Vector3d& s, const Eigen::Vector3d& g) {
  // s at x < 48 and g at x > 52, both with y < 80 and the same z: round the corners (48, 80) and (52, 80).
  const Eigen::Vector2d c1(48, 80), c2(52, 80);
  return (s.head<2>() - c1).norm() + (c2 - c1).norm() + (g.head<2>() - c2).norm();
}

// Seeded field of spheres in a 100 m cube, keeping start and goal corners clear.
inline BoxWorld sphereField(unsigned seed, int count) {
  BoxWorld w(Eigen::AlignedBox3d(Eigen::Vector3d(0, 0, 0), Eigen::Vector3d(100, 100, 100)));
  std::uint64_t state = seed * 6364136223846793005ULL + 1442695040888963407ULL;
  auto next = [&state]() {
    state = state * 6364136223846793005ULL + 1442695040888963407ULL;
    return static_cast<double>(state >> 11) * 0x1.0p-53;
  };
  for (int i = 0; i < count; ++i) {
    const Eigen::Vector3d c(10 + 80 * next(), 10 + 80 * next(), 10 + 80 * next());
    const double r = 4 + 8 * next();
    w.addSphere(c, r);
  }
  return w;
}

}  // namespace skyroute::testing
