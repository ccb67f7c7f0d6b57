#include "terrain/collision_world.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <mutex>
#include <tuple>

#include <fcl/geometry/octree/octree.h>
#include <fcl/geometry/shape/box.h>
#include <fcl/geometry/shape/capsule.h>
#include <fcl/geometry/shape/cylinder.h>
#include <fcl/geometry/shape/ellipsoid.h>
#include <fcl/geometry/shape/sphere.h>
#include <fcl/narrowphase/collision.h>
#include <fcl/narrowphase/distance.h>

namespace skyroute {
namespace {

using Geometry = fcl::CollisionGeometryd;

std::shared_ptr<Geometry> makeGeometry(const Obstacle& o) {
  switch (o.shape) {
    case ObstacleShape::kSphere: return std::make_shared<fcl::Sphered>(o.size_m.x());
    case ObstacleShape::kEllipsoid: return std::make_shared<fcl::Ellipsoidd>(o.size_m);
    case ObstacleShape::kBox: return std::make_shared<fcl::Boxd>(2.0 * o.size_m);
    case ObstacleShape::kCylinder: return std::make_shared<fcl::Cylinderd>(o.size_m.x(), 2.0 * o.size_m.z());
  }
  return std::make_shared<fcl::Sphered>(o.boundingRadius());
}

fcl::Transform3d translation(const Eigen::Vector3d& p) {
  fcl::Transform3d tf = fcl::Transform3d::Identity();
  tf.translation() = p;
  return tf;
}

// FCL capsules lie along z, centred at the origin: place one on the segment a -> b.
fcl::Transform3d capsulePose(const Eigen::Vector3d& a, const Eigen::Vector3d& b) {
  fcl::Transform3d tf = fcl::Transform3d::Identity();
  const Eigen::Vector3d d = b - a;
  if (d.norm() > 0.0) tf.linear() = Eigen::Quaterniond::FromTwoVectors(Eigen::Vector3d::UnitZ(), d).toRotationMatrix();
  tf.translation() = 0.5 * (a + b);
  return tf;
}

double pointSegmentDistance(const Eigen::Vector3d& p, const Eigen::Vector3d& a, const Eigen::Vector3d& b) {
  const Eigen::Vector3d ab = b - a;
  const double len2 = ab.squaredNorm();
  const double t = len2 > 0.0 ? std::clamp((p - a).dot(ab) / len2, 0.0, 1.0) : 0.0;
  return (a + t * ab - p).norm();
}

// Shortest distance between segments p0-p1 and q0-q1 (clamped closest points).
double segmentSegmentDistance(const Eigen::Vector3d& p0, const Eigen::Vector3d& p1, const Eigen::Vector3d& q0,
                              const Eigen::Vector3d& q1) {
  const Eigen::Vector3d d1 = p1 - p0;
  const Eigen::Vector3d d2 = q1 - q0;
  const Eigen::Vector3d r = p0 - q0;
  const double a = d1.squaredNorm();
  const double e = d2.squaredNorm();
  const double f = d2.dot(r);
  double s = 0.0;
  double t = 0.0;
  if (a <= 1e-12 && e <= 1e-12) return r.norm();
  if (a <= 1e-12) {
    t = std::clamp(f / e, 0.0, 1.0);
  } else {
    const double c = d1.dot(r);
    if (e <= 1e-12) {
      s = std::clamp(-c / a, 0.0, 1.0);
    } else {
      const double b = d1.dot(d2);
      const double denom = a * e - b * b;
      s = denom > 1e-12 ? std::clamp((b * f - c * e) / denom, 0.0, 1.0) : 0.0;
      t = (b * s + f) / e;
      if (t < 0.0) {
        t = 0.0;
        s = std::clamp(-c / a, 0.0, 1.0);
      } else if (t > 1.0) {
        t = 1.0;
        s = std::clamp((b - c) / a, 0.0, 1.0);
      }
    }
  }
  return ((p0 + s * d1) - (q0 + t * d2)).norm();
}

bool collide(const Geometry& g1, const fcl::Transform3d& tf1, const Geometry& g2, const fcl::Transform3d& tf2) {
  fcl::CollisionRequestd request;
  fcl::CollisionResultd result;
  fcl::collide(&g1, tf1, &g2, tf2, request, result);
  return result.isCollision();
}

double distance(const Geometry& g1, const fcl::Transform3d& tf1, const Geometry& g2, const fcl::Transform3d& tf2) {
  fcl::DistanceRequestd request;
  fcl::DistanceResultd result;
  return fcl::distance(&g1, tf1, &g2, tf2, request, result);
}

// The part of the snapshot's window in which a vehicle leaving its focus can be somewhere between
// `near_m` and `far_m` from it (the whole window without a time band); empty when t1 < t0.
std::pair<double, double> bandWindow(const ObstacleSnapshot& snapshot, double near_m, double far_m) {
  const double t0 = snapshot.time_s, t1 = snapshot.time_s + snapshot.window_s;
  if (!(snapshot.band_fast_mps > 0.0) || !(snapshot.band_slow_mps > 0.0)) return {t0, t1};
  return {std::max(t0, t0 + near_m / snapshot.band_fast_mps - snapshot.band_slack_s),
          std::min(t1, t0 + far_m / snapshot.band_slow_mps + snapshot.band_slack_s)};
}

// A moving obstacle that cannot reach the snapshot's focus region within its window is left out.
bool ignoredBySnapshot(const Obstacle& o, const ObstacleSnapshot& snapshot) {
  if (!std::isfinite(snapshot.focus_radius_m)) return false;
  const auto [from, to] = o.trackDuring(snapshot.time_s, snapshot.time_s + snapshot.window_s);
  return pointSegmentDistance(snapshot.focus_m, from, to) > snapshot.focus_radius_m + o.boundingRadius();
}

}  // namespace

struct CollisionWorld::FclObstacles {
  struct Entry {
    Obstacle obstacle;
    std::shared_ptr<Geometry> geometry;
    // A moving obstacle, when no time is given, blocks its whole sweep: a capsule from one end of
    // its motion to the other, as wide as its bounding sphere (exact for spheres, conservative else).
    std::shared_ptr<fcl::Capsuled> sweep;
    fcl::Transform3d sweep_pose = fcl::Transform3d::Identity();
  };
  std::vector<Entry> entries;
  std::shared_ptr<fcl::Sphered> vehicle;
  std::shared_ptr<fcl::OcTreed> terrain_octree;
};

CollisionWorld::~CollisionWorld() = default;

Result<std::shared_ptr<CollisionWorld>> CollisionWorld::create(std::shared_ptr<const Heightfield> terrain,
                                                               const CollisionWorldOptions& options) {
  if (!terrain) return make_error(ErrorCode::kInvalidArgument, "terrain", "is null");
  if (!(options.vehicle_radius_m > 0.0) || !std::isfinite(options.vehicle_radius_m)) {
    return make_error(ErrorCode::kInvalidArgument, "vehicle_radius_m", "must be positive and finite");
  }
  if (!(options.min_clearance_m >= options.vehicle_radius_m) || !std::isfinite(options.min_clearance_m)) {
    return make_error(ErrorCode::kInvalidArgument, "min_clearance_m", "must be finite and at least vehicle_radius_m");
  }
  if (std::isnan(options.ceiling_m) || options.ceiling_m <= terrain->minHeightM() + options.min_clearance_m) {
    return make_error(ErrorCode::kInvalidArgument, "ceiling_m",
                      "leaves no flyable height above the lowest ground plus the clearance");
  }
  if (!(options.terrain_margin_m >= 0.0)) {
    return make_error(ErrorCode::kInvalidArgument, "terrain_margin_m", "must be zero or positive");
  }
  if (options.build_octree && !(options.octree_resolution_m > 0.0)) {
    return make_error(ErrorCode::kInvalidArgument, "octree_resolution_m", "must be positive");
  }
  std::shared_ptr<CollisionWorld> world(new CollisionWorld());
  world->terrain_ = terrain;
  world->dilated_terrain_ = options.terrain_margin_m > 0.0 ? terrain->dilated(options.terrain_margin_m) : terrain;
  world->options_ = options;
  world->fcl_ = std::make_unique<FclObstacles>();
  world->fcl_->vehicle = std::make_shared<fcl::Sphered>(options.vehicle_radius_m);
  if (options.build_octree) {
    world->octree_ = TerrainOctree::build(terrain, TerrainOctreeOptions{options.octree_resolution_m, 0.0});
    world->fcl_->terrain_octree = std::make_shared<fcl::OcTreed>(world->octree_->tree());
  }
  return world;
}

void CollisionWorld::upsertObstacle(const Obstacle& obstacle) {
  FclObstacles::Entry entry;
  entry.obstacle = obstacle;
  entry.geometry = makeGeometry(obstacle);
  if (obstacle.moving()) {
    entry.sweep = std::make_shared<fcl::Capsuled>(obstacle.boundingRadius(),
                                                  (obstacle.motion->to_m - obstacle.motion->from_m).norm());
    entry.sweep_pose = capsulePose(obstacle.motion->from_m, obstacle.motion->to_m);
  }
  std::unique_lock lock(mutex_);
  auto& entries = fcl_->entries;
  auto it = std::find_if(entries.begin(), entries.end(), [&](const auto& e) { return e.obstacle.id == obstacle.id; });
  const bool fixed_changed = !obstacle.moving() || (it != entries.end() && !it->obstacle.moving());
  if (it != entries.end()) {
    *it = std::move(entry);
  } else {
    entries.push_back(std::move(entry));
  }
  ++obstacle_version_;
  if (fixed_changed) ++static_version_;
}

bool CollisionWorld::removeObstacle(std::uint64_t id) {
  std::unique_lock lock(mutex_);
  auto& entries = fcl_->entries;
  auto it = std::find_if(entries.begin(), entries.end(), [&](const auto& e) { return e.obstacle.id == id; });
  if (it == entries.end()) return false;
  if (!it->obstacle.moving()) ++static_version_;
  entries.erase(it);
  ++obstacle_version_;
  return true;
}

void CollisionWorld::clearObstacles() {
  std::unique_lock lock(mutex_);
  fcl_->entries.clear();
  ++obstacle_version_;
  ++static_version_;
}

std::vector<Obstacle> CollisionWorld::obstacles() const {
  std::shared_lock lock(mutex_);
  std::vector<Obstacle> out;
  out.reserve(fcl_->entries.size());
  for (const auto& e : fcl_->entries) out.push_back(e.obstacle);
  return out;
}

std::uint64_t CollisionWorld::obstacleVersion() const {
  std::shared_lock lock(mutex_);
  return obstacle_version_;
}

std::uint64_t CollisionWorld::staticVersion() const {
  std::shared_lock lock(mutex_);
  return static_version_;
}

void CollisionWorld::setNoFlyZones(std::vector<NoFlyZone> zones) {
  std::unique_lock lock(mutex_);
  zones_ = std::move(zones);
  ++obstacle_version_;
  ++static_version_;
}

std::vector<NoFlyZone> CollisionWorld::noFlyZones() const {
  std::shared_lock lock(mutex_);
  return zones_;
}

std::optional<std::string> CollisionWorld::noFlyZoneAt(const Eigen::Vector3d& p_m, std::optional<double> t_s) const {
  std::shared_lock lock(mutex_);
  const NoFlyZone* zone = zoneTouchingPoint(zones_, p_m, options_.vehicle_radius_m, t_s);
  if (!zone) return std::nullopt;
  return zone->name;
}

bool CollisionWorld::isTerrainValid(const Eigen::Vector3d& p_m) const {
  if (!(p_m.z() <= options_.ceiling_m)) return false;
  const double ground = dilated_terrain_->heightAt(p_m.x(), p_m.y());
  return p_m.z() - ground >= options_.min_clearance_m;  // false for NaN (outside or unknown)
}

bool CollisionWorld::isPointValid(const Eigen::Vector3d& p_m, const ObstacleSnapshot& snapshot) const {
  return isPointValidImpl(p_m, snapshot.time_s, snapshot.margin_m, snapshot.window_s, &snapshot);
}

bool CollisionWorld::isPointValid(const Eigen::Vector3d& p_m, std::optional<double> t_s, double obstacle_margin_m,
                                  double window_s) const {
  return isPointValidImpl(p_m, t_s, obstacle_margin_m, window_s, nullptr);
}

bool CollisionWorld::isPointValidImpl(const Eigen::Vector3d& p_m, std::optional<double> t_s, double obstacle_margin_m,
                                      double window_s, const ObstacleSnapshot* focus) const {
  if (!isTerrainValid(p_m)) return false;
  const double r = options_.vehicle_radius_m + std::max(0.0, obstacle_margin_m);
  const fcl::Sphered grown(r);
  const fcl::Sphered& vehicle = obstacle_margin_m > 0.0 ? grown : *fcl_->vehicle;
  const fcl::Transform3d vehicle_pose = translation(p_m);
  std::shared_lock lock(mutex_);
  if (zoneTouchingPoint(zones_, p_m, options_.vehicle_radius_m, t_s, window_s)) return false;
  for (const auto& e : fcl_->entries) {
    const Obstacle& o = e.obstacle;
    if (o.moving() && !t_s) {
      if (pointSegmentDistance(p_m, o.motion->from_m, o.motion->to_m) > o.boundingRadius() + r) continue;
      if (collide(vehicle, vehicle_pose, *e.sweep, e.sweep_pose)) return false;
      continue;
    }
    if (focus && o.moving() && ignoredBySnapshot(o, *focus)) continue;
    if (o.moving() && window_s > 0.0) {
      double t0 = *t_s, t1 = *t_s + window_s;
      if (focus) {
        const double d = (p_m - focus->focus_m).norm();
        std::tie(t0, t1) = bandWindow(*focus, d, d);
        if (t1 < t0) continue;
      }
      const auto [from, to] = o.trackDuring(t0, t1);
      if (pointSegmentDistance(p_m, from, to) <= o.boundingRadius() + r) return false;
      continue;
    }
    const Eigen::Vector3d c = o.centerAt(t_s.value_or(0.0));
    if ((p_m - c).norm() > o.boundingRadius() + r) continue;
    if (collide(vehicle, vehicle_pose, *e.geometry, translation(c))) return false;
  }
  return true;
}

bool CollisionWorld::isSegmentValid(const Eigen::Vector3d& a_m, const Eigen::Vector3d& b_m,
                                    const ObstacleSnapshot& snapshot) const {
  return isSegmentValidImpl(a_m, b_m, snapshot.time_s, snapshot.margin_m, snapshot.window_s, &snapshot);
}

bool CollisionWorld::isSegmentValid(const Eigen::Vector3d& a_m, const Eigen::Vector3d& b_m,
                                    std::optional<double> t_s, double obstacle_margin_m, double window_s) const {
  return isSegmentValidImpl(a_m, b_m, t_s, obstacle_margin_m, window_s, nullptr);
}

bool CollisionWorld::isSegmentValidImpl(const Eigen::Vector3d& a_m, const Eigen::Vector3d& b_m,
                                        std::optional<double> t_s, double obstacle_margin_m, double window_s,
                                        const ObstacleSnapshot* focus) const {
  if (!(std::max(a_m.z(), b_m.z()) <= options_.ceiling_m)) return false;
  const double lowest = dilated_terrain_->minHeightAboveGround(a_m, b_m);
  if (!(lowest >= options_.min_clearance_m)) return false;
  const double r = options_.vehicle_radius_m + std::max(0.0, obstacle_margin_m);
  const double length = (b_m - a_m).norm();
  std::shared_lock lock(mutex_);
  if (zoneTouchingSegment(zones_, a_m, b_m, options_.vehicle_radius_m, t_s, window_s)) return false;
  if (fcl_->entries.empty()) return true;
  const fcl::Capsuled swept(r, length);
  const fcl::Transform3d swept_pose = capsulePose(a_m, b_m);
  for (const auto& e : fcl_->entries) {
    const Obstacle& o = e.obstacle;
    if (focus && o.moving() && ignoredBySnapshot(o, *focus)) continue;
    if (o.moving() && t_s && window_s > 0.0) {  // everywhere it passes during the window
      double t0 = *t_s, t1 = *t_s + window_s;
      if (focus) {
        std::tie(t0, t1) = bandWindow(*focus, pointSegmentDistance(focus->focus_m, a_m, b_m),
                                      std::max((a_m - focus->focus_m).norm(), (b_m - focus->focus_m).norm()));
        if (t1 < t0) continue;
      }
      const auto [from, to] = o.trackDuring(t0, t1);
      if (segmentSegmentDistance(a_m, b_m, from, to) <= o.boundingRadius() + r) return false;
      continue;
    }
    if (o.moving() && t_s) {  // frozen at its place at t_s
      const Eigen::Vector3d c = o.centerAt(*t_s);
      if (pointSegmentDistance(c, a_m, b_m) > o.boundingRadius() + r) continue;
      if (collide(swept, swept_pose, *e.geometry, translation(c))) return false;
      continue;
    }
    if (o.moving()) {
      if (segmentSegmentDistance(a_m, b_m, o.motion->from_m, o.motion->to_m) > o.boundingRadius() + r) continue;
      if (collide(swept, swept_pose, *e.sweep, e.sweep_pose)) return false;
      continue;
    }
    if (pointSegmentDistance(o.center_m, a_m, b_m) > o.boundingRadius() + r) continue;
    if (collide(swept, swept_pose, *e.geometry, translation(o.center_m))) return false;
  }
  return true;
}

bool CollisionWorld::isStaticSegmentValid(const Eigen::Vector3d& a_m, const Eigen::Vector3d& b_m,
                                          std::optional<double> t_s, double duration_s) const {
  if (!(std::max(a_m.z(), b_m.z()) <= options_.ceiling_m)) return false;
  if (!(dilated_terrain_->minHeightAboveGround(a_m, b_m) >= options_.min_clearance_m)) return false;
  const double r = options_.vehicle_radius_m;
  std::shared_lock lock(mutex_);
  if (zoneTouchingSegment(zones_, a_m, b_m, r, t_s, duration_s)) return false;
  for (const auto& e : fcl_->entries) {
    const Obstacle& o = e.obstacle;
    if (o.moving() || pointSegmentDistance(o.center_m, a_m, b_m) > o.boundingRadius() + r) continue;
    const fcl::Capsuled swept(r, (b_m - a_m).norm());
    if (collide(swept, capsulePose(a_m, b_m), *e.geometry, translation(o.center_m))) return false;
  }
  return true;
}

namespace {
// Moving obstacles: within this distance (metres) of the vehicle's sphere counts as contact.
constexpr double kContactToleranceM = 0.05;
}  // namespace

bool CollisionWorld::isSegmentValidDuring(const Eigen::Vector3d& a_m, double t0_s, const Eigen::Vector3d& b_m,
                                          double t1_s) const {
  if (!(t1_s >= t0_s)) return false;
  if (!(std::max(a_m.z(), b_m.z()) <= options_.ceiling_m)) return false;
  if (!(dilated_terrain_->minHeightAboveGround(a_m, b_m) >= options_.min_clearance_m)) return false;
  const double duration = t1_s - t0_s;
  const double vehicle_speed = duration > 0.0 ? (b_m - a_m).norm() / duration : 0.0;
  const double r = options_.vehicle_radius_m;
  std::shared_lock lock(mutex_);
  if (zoneTouchingSegment(zones_, a_m, b_m, r, t0_s, duration)) return false;
  for (const auto& e : fcl_->entries) {
    const Obstacle& o = e.obstacle;
    if (!o.moving()) {
      if (pointSegmentDistance(o.center_m, a_m, b_m) > o.boundingRadius() + r) continue;
      const fcl::Capsuled swept(r, (b_m - a_m).norm());
      if (collide(swept, capsulePose(a_m, b_m), *e.geometry, translation(o.center_m))) return false;
      continue;
    }
    // Broad phase: can the two ever come close during the interval?
    if (segmentSegmentDistance(a_m, b_m, o.motion->from_m, o.motion->to_m) > o.boundingRadius() + r) continue;
    // Conservative advancement: with relative speed at most v, nothing can touch before d / v.
    const double relative_speed = vehicle_speed + o.motion->speed_mps;
    double t = t0_s;
    for (int iteration = 0;; ++iteration) {
      const double f = duration > 0.0 ? (t - t0_s) / duration : 0.0;
      const Eigen::Vector3d p = a_m + f * (b_m - a_m);
      const double d = distance(*fcl_->vehicle, translation(p), *e.geometry, translation(o.centerAt(t)));
      // Closer than the contact tolerance counts as touching. It bounds the work too: each step
      // advances at least tolerance / relative speed, so a path that grazes an obstacle costs at
      // most a few hundred distance queries per chord instead of up to 100,000 (seconds of a replan).
      if (d <= kContactToleranceM) return false;
      if (t >= t1_s) break;
      if (iteration > 100000) return false;  // cannot happen with the tolerance; refuse rather than guess
      t = relative_speed > 0.0 ? std::min(t1_s, t + std::max(d / relative_speed, 1e-6)) : t1_s;
    }
  }
  return true;
}

double CollisionWorld::terrainDistance(const Eigen::Vector3d& p_m, double cap_m) const {
  if (!fcl_->terrain_octree) {
    const auto agl = terrain_->heightAboveGround(p_m);
    return agl ? std::clamp(*agl, 0.0, cap_m) : 0.0;
  }
  const fcl::Sphered probe(1e-3);
  const double d = distance(probe, translation(p_m), *fcl_->terrain_octree, fcl::Transform3d::Identity());
  return d < 0.0 ? 0.0 : std::min(d, cap_m);
}

double CollisionWorld::obstacleDistance(const Eigen::Vector3d& p_m, double t_s) const {
  double best = std::numeric_limits<double>::infinity();
  std::shared_lock lock(mutex_);
  for (const auto& e : fcl_->entries) {
    const double d = distance(*fcl_->vehicle, translation(p_m), *e.geometry, translation(e.obstacle.centerAt(t_s)));
    best = std::min(best, std::max(0.0, d));
  }
  return best;
}

Eigen::AlignedBox3d CollisionWorld::flyableBounds() const {
  const Eigen::AlignedBox2d& en = terrain_->boundsEn();
  const double bottom = terrain_->minHeightM() + options_.min_clearance_m;
  const double top = std::min(options_.ceiling_m,
                              dilated_terrain_->maxHeightM() + std::max(500.0, 3.0 * options_.min_clearance_m));
  return Eigen::AlignedBox3d(Eigen::Vector3d(en.min().x(), en.min().y(), bottom),
                             Eigen::Vector3d(en.max().x(), en.max().y(), top));
}

const FlyableRegions& CollisionWorld::flyableRegions() const {
  std::call_once(regions_once_, [this] {
    regions_ = std::make_unique<const FlyableRegions>(
        FlyableRegions::build(*dilated_terrain_, options_.ceiling_m - options_.min_clearance_m));
  });
  return *regions_;
}

}  // namespace skyroute
