#include "service/polyline_simplify.hpp"

#include <algorithm>
#include <cmath>
#include <string>
#include <utility>

namespace skyroute {

double distanceToSegment(const Eigen::Vector3d& p, const Eigen::Vector3d& a, const Eigen::Vector3d& b) {
  const Eigen::Vector3d ab = b - a;
  const double length2 = ab.squaredNorm();
  if (length2 <= 0.0) return (p - a).norm();
  const double t = std::clamp((p - a).dot(ab) / length2, 0.0, 1.0);
  return (p - (a + t * ab)).norm();
}

Result<std::vector<std::size_t>> simplifyPolyline(const std::vector<Eigen::Vector3d>& points, double tolerance_m,
                                                  const std::vector<std::size_t>& keep) {
  if (!(tolerance_m > 0.0) || !std::isfinite(tolerance_m))
    return make_error(ErrorCode::kInvalidArgument, "tolerance_m", "must be a positive number of metres");
  for (std::size_t i = 0; i < points.size(); ++i)
    if (!points[i].allFinite())
      return make_error(ErrorCode::kInvalidArgument, "points[" + std::to_string(i) + "]", "is not finite");
  for (std::size_t k = 0; k < keep.size(); ++k)
    if (keep[k] >= points.size())
      return make_error(ErrorCode::kInvalidArgument, "keep[" + std::to_string(k) + "]",
                        "index " + std::to_string(keep[k]) + " is past the last vertex " +
                            std::to_string(points.size()) + " - 1");
  if (points.size() <= 2) {
    std::vector<std::size_t> all(points.size());
    for (std::size_t i = 0; i < all.size(); ++i) all[i] = i;
    return all;
  }

  std::vector<bool> kept(points.size(), false);
  kept.front() = kept.back() = true;
  for (std::size_t k : keep) kept[k] = true;
  // Each span between two fixed vertices is simplified on its own; an explicit stack instead of
  // recursion, since a sampled trajectory has thousands of vertices.
  std::vector<std::pair<std::size_t, std::size_t>> spans;
  for (std::size_t a = 0, b = 1; b < points.size(); ++b)
    if (kept[b]) {
      spans.emplace_back(a, b);
      a = b;
    }
  while (!spans.empty()) {
    const auto [a, b] = spans.back();
    spans.pop_back();
    double worst = -1.0;
    std::size_t worst_i = a;
    for (std::size_t i = a + 1; i < b; ++i) {
      const double d = distanceToSegment(points[i], points[a], points[b]);
      if (d > worst) {
        worst = d;
        worst_i = i;
      }
    }
    if (worst > tolerance_m) {
      kept[worst_i] = true;
      spans.emplace_back(a, worst_i);
      spans.emplace_back(worst_i, b);
    }
  }
  std::vector<std::size_t> out;
  for (std::size_t i = 0; i < points.size(); ++i)
    if (kept[i]) out.push_back(i);
  return out;
}

}  // namespace skyroute
