#include "planning/sampling/leg_sampling_regions.hpp"

#include <algorithm>
#include <limits>

#include "planning/sampling/world_motion_validator.hpp"

namespace skyroute {
namespace {

constexpr double kUnderCeilingM = 1.0;

Eigen::AlignedBox3d spanningHeights(const Eigen::AlignedBox2d& box) {
  const double inf = std::numeric_limits<double>::infinity();
  return Eigen::AlignedBox3d(Eigen::Vector3d(box.min().x(), box.min().y(), -inf),
                             Eigen::Vector3d(box.max().x(), box.max().y(), inf));
}

Eigen::AlignedBox2d plan(const Eigen::AlignedBox3d& box) {
  return Eigen::AlignedBox2d(box.min().head<2>(), box.max().head<2>());
}

}  // namespace

LegSamplingRegions::LegSamplingRegions(const CollisionWorld& world, const Eigen::Vector3d& a_m,
                                       const Eigen::Vector3d& b_m, double margin_m)
    : world_(world), a_m_(a_m), b_m_(b_m), margin_m_(margin_m) {
  connected_ = world_.flyableRegions().connected(a_m_.head<2>(), b_m_.head<2>());
  if (!connected_) step_ = 3;
}

std::optional<double> LegSamplingRegions::lowestConnectingCeilingM() const {
  if (connected_) return std::nullopt;
  const auto ground = world_.flyableRegions().lowestConnectingGroundM(a_m_.head<2>(), b_m_.head<2>());
  if (!ground) return std::nullopt;
  return *ground + world_.options().min_clearance_m;
}

std::optional<Eigen::AlignedBox3d> LegSamplingRegions::next() {
  const Eigen::AlignedBox2d& terrain = world_.terrain().boundsEn();
  const FlyableRegions& regions = world_.flyableRegions();
  while (step_ < 3) {
    const int step = step_++;
    Eigen::AlignedBox2d box;
    if (step == 0) {
      box = plan(WorldMotionValidator::corridor(a_m_, b_m_, margin_m_));
      // Skipped only when the regions prove no path stays inside it: a leg that could be
      // solved there is planned exactly as with the corridor alone.
      if (!regions.connectedWithin(a_m_.head<2>(), b_m_.head<2>(), box)) continue;
    } else if (step == 1) {
      const std::vector<Eigen::Vector3d> way = regions.shortestWay(a_m_.head<2>(), b_m_.head<2>());
      if (way.empty()) continue;
      Eigen::AlignedBox2d way_box;
      way_box.extend(a_m_.head<2>());
      way_box.extend(b_m_.head<2>());
      const double clearance_m = world_.options().min_clearance_m;
      for (std::size_t k = 0; k < way.size(); ++k) {
        way_box.extend(way[k].head<2>());
        guide_.emplace_back(way[k].x(), way[k].y(), way[k].z() + clearance_m);
        if (k > 0) guide_spacing_m_ = std::max(guide_spacing_m_, (way[k] - way[k - 1]).head<2>().norm());
      }
      // The margin also covers the half block round each point of the way.
      box = Eigen::AlignedBox2d(way_box.min().array() - margin_m_, way_box.max().array() + margin_m_);
    } else {
      box = terrain;
    }
    const Eigen::AlignedBox2d clipped = box.intersection(terrain);
    bool covered = false;
    for (const Eigen::AlignedBox2d& before : given_) covered = covered || before.contains(clipped);
    if (covered) continue;
    given_.push_back(clipped);
    ++tried_;
    whole_tried_ = clipped.contains(terrain);
    // The corridor is handed out as it always was (the validator clips it to the terrain).
    return step == 0 ? WorldMotionValidator::corridor(a_m_, b_m_, margin_m_) : spanningHeights(box);
  }
  return std::nullopt;
}

std::vector<Eigen::Vector3d> LegSamplingRegions::wayUnderCeiling() const {
  std::vector<Eigen::Vector3d> path;
  if (guide_.empty()) return path;
  // A little under the ceiling, so that rounding in the checks never puts a point above it.
  const double z_m = world_.options().ceiling_m - kUnderCeilingM;
  auto push = [&path](const Eigen::Vector3d& p) {
    if (path.empty() || (p - path.back()).norm() > 1e-6) path.push_back(p);
  };
  push(a_m_);
  push(Eigen::Vector3d(a_m_.x(), a_m_.y(), std::max(a_m_.z(), z_m)));
  // The ground under the way a little lower still: a geographic DEM's grid lines are not quite
  // straight in ENU, so a straight piece may stray a few centimetres off its grid line.
  const double max_ground_m = z_m - world_.options().min_clearance_m - kUnderCeilingM;
  for (const Eigen::Vector2d& g : world_.flyableRegions().gridWay(a_m_.head<2>(), b_m_.head<2>(), max_ground_m)) {
    push(Eigen::Vector3d(g.x(), g.y(), z_m));
  }
  if (path.size() < 3) return {};
  push(Eigen::Vector3d(b_m_.x(), b_m_.y(), std::max(b_m_.z(), z_m)));
  push(b_m_);
  return path;
}

}  // namespace skyroute
