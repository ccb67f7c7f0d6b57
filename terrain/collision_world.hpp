// CollisionWorld: the one place that answers "may the vehicle be here / fly this". Terrain checks
// run on the Heightfield (exact on its bilinear surface, nanoseconds); the terrain octree and the
// obstacles are FCL objects (the octree answers distance-to-terrain queries and cross-checks the
// heightfield in tests). Many readers may query while one writer updates obstacles.
#pragma once

#include <cstdint>
#include <limits>
#include <memory>
#include <mutex>
#include <optional>
#include <shared_mutex>
#include <string>
#include <vector>

#include "terrain/flyable_regions.hpp"
#include "terrain/heightfield.hpp"
#include "terrain/no_fly_zone.hpp"
#include "terrain/obstacle.hpp"
#include "terrain/terrain_octree.hpp"

namespace skyroute {

// Moving obstacles as a replanner sees them (seed 003 section 3-2) instead of blocking their whole
// sweep: where they are at a world time (or every place they pass in a window after it), with extra
// room kept from them, and only those near a focus point (far ones will have moved before the
// vehicle gets there; the replanning loop looks again as time goes on).
struct ObstacleSnapshot {
  double time_s = 0.0;
  double margin_m = 0.0;
  double window_s = 0.0;  // > 0: each blocks the stretch of track it covers in [time, time + window]
  Eigen::Vector3d focus_m = Eigen::Vector3d::Zero();
  double focus_radius_m = std::numeric_limits<double>::infinity();
  // Time band (with a window; off while band_fast_mps is 0): a vehicle leaving focus_m at `time`
  // is at distance d from it no sooner than d / band_fast_mps and, flying on, no later than
  // d / band_slow_mps, so a place at distance d is blocked only by where the obstacles are in
  // that interval widened by band_slack_s (clipped to the window). Without it a vehicle whose
  // current position an obstacle will sweep later in the window could not plan away from there.
  // A planning heuristic, not a guarantee: the caller checks the trajectory in time.
  double band_fast_mps = 0.0;
  double band_slow_mps = 0.0;
  double band_slack_s = 0.0;
};

struct CollisionWorldOptions {
  double vehicle_radius_m = 5.0;     // the vehicle's bounding sphere
  double min_clearance_m = 30.0;     // lowest height above ground allowed (>= vehicle radius)
  double ceiling_m = 1.0e9;          // highest up (altitude AMSL with the default frame) allowed
  double terrain_margin_m = 0.0;     // horizontal distance kept from the ground beside the path
                                     // (checks run on the terrain dilated by it; 0 = vertical AGL only)
  double octree_resolution_m = 30.0;
  bool build_octree = true;          // the heightfield alone is enough for every validity check
};

class CollisionWorld {
 public:
  static Result<std::shared_ptr<CollisionWorld>> create(std::shared_ptr<const Heightfield> terrain,
                                                        const CollisionWorldOptions& options);
  ~CollisionWorld();

  const Heightfield& terrain() const { return *terrain_; }
  std::shared_ptr<const Heightfield> terrainPtr() const { return terrain_; }
  const CollisionWorldOptions& options() const { return options_; }
  const TerrainOctree* octree() const { return octree_.get(); }

  // Obstacles. Upsert replaces an obstacle with the same id.
  void upsertObstacle(const Obstacle& obstacle);
  bool removeObstacle(std::uint64_t id);
  void clearObstacles();
  std::vector<Obstacle> obstacles() const;
  std::uint64_t obstacleVersion() const;  // grows with obstacle and no-fly zone changes
  // Grows with the changes of what stays in force (fixed obstacles and no-fly zones), not with a
  // moving obstacle's: what isStaticSegmentValid answers changes only with it.
  std::uint64_t staticVersion() const;

  // No-fly zones (checked by the caller with checkNoFlyZone): every validity check below keeps the
  // vehicle's sphere out of them, at the check's time when it has one (a zone out of force then
  // does not block), and always without a time.
  void setNoFlyZones(std::vector<NoFlyZone> zones);
  std::vector<NoFlyZone> noFlyZones() const;
  // The name of a zone the vehicle's sphere at p touches (in force at t_s when given).
  std::optional<std::string> noFlyZoneAt(const Eigen::Vector3d& p_m, std::optional<double> t_s = std::nullopt) const;

  // Valid: inside the DEM, at least min_clearance above the (radius-dilated) ground, under the
  // ceiling, and the vehicle sphere clear of every obstacle. Without a time, a moving obstacle
  // blocks every place it can reach (its whole back-and-forth sweep); with a time, only where it
  // is at that time.
  // obstacle_margin_m grows the vehicle's sphere against obstacles only (not the terrain): a
  // replanner that freezes obstacles at time t_s keeps this much more room from them.
  // window_s > 0 (with a time): each moving obstacle blocks every place it passes during
  // [t_s, t_s + window_s] (its bounding sphere swept along that stretch of track).
  bool isPointValid(const Eigen::Vector3d& p_m, std::optional<double> t_s = std::nullopt,
                    double obstacle_margin_m = 0.0, double window_s = 0.0) const;
  bool isPointValid(const Eigen::Vector3d& p_m, const ObstacleSnapshot& snapshot) const;
  bool isTerrainValid(const Eigen::Vector3d& p_m) const;  // terrain, bounds and ceiling only
  // The sphere swept along a -> b, exactly against the terrain surface and obstacles (no samples).
  // Without a time, moving obstacles block their whole sweep; with one, they are frozen where they
  // are at t_s (a snapshot, for replanning), and obstacle_margin_m grows the sphere against them.
  bool isSegmentValid(const Eigen::Vector3d& a_m, const Eigen::Vector3d& b_m, std::optional<double> t_s = std::nullopt,
                      double obstacle_margin_m = 0.0, double window_s = 0.0) const;
  bool isSegmentValid(const Eigen::Vector3d& a_m, const Eigen::Vector3d& b_m, const ObstacleSnapshot& snapshot) const;
  // Terrain, ceiling, fixed obstacles and no-fly zones only; moving obstacles ignored (for the part
  // of a trajectory beyond the horizon where their positions are not worth predicting: replanning
  // will see them). With a time, only the zones in force at some time of [t_s, t_s + duration_s]
  // block (the segment flown then); without, every zone does.
  bool isStaticSegmentValid(const Eigen::Vector3d& a_m, const Eigen::Vector3d& b_m,
                            std::optional<double> t_s = std::nullopt, double duration_s = 0.0) const;
  // Vehicle moving at constant velocity from a at t0 to b at t1, against moving obstacles at their
  // positions over that interval (conservative advancement on FCL distances: no tunnelling).
  bool isSegmentValidDuring(const Eigen::Vector3d& a_m, double t0_s, const Eigen::Vector3d& b_m,
                            double t1_s) const;
  // Euclidean distance from p to the nearest terrain voxel (FCL on the octree), capped at cap_m.
  double terrainDistance(const Eigen::Vector3d& p_m, double cap_m = 1000.0) const;
  // Smallest distance between the vehicle sphere's surface and any obstacle at time t_s (inf if none).
  double obstacleDistance(const Eigen::Vector3d& p_m, double t_s) const;

  // The flyable box: the DEM's ENU rectangle, from the lowest ground plus clearance to the
  // ceiling (or the highest ground plus a margin when the ceiling is unlimited).
  Eigen::AlignedBox3d flyableBounds() const;

  // The connected regions of the terrain a vehicle can fly over below the ceiling (the checked,
  // dilated surface; obstacles and no-fly zones not counted), labelled on first use and kept:
  // the proof that two places cannot be joined, in microseconds after the first call.
  const FlyableRegions& flyableRegions() const;

 private:
  struct FclObstacles;
  CollisionWorld() = default;
  bool isPointValidImpl(const Eigen::Vector3d& p_m, std::optional<double> t_s, double obstacle_margin_m,
                        double window_s, const ObstacleSnapshot* focus) const;
  bool isSegmentValidImpl(const Eigen::Vector3d& a_m, const Eigen::Vector3d& b_m, std::optional<double> t_s,
                          double obstacle_margin_m, double window_s, const ObstacleSnapshot* focus) const;

  std::shared_ptr<const Heightfield> terrain_;
  std::shared_ptr<const Heightfield> dilated_terrain_;
  CollisionWorldOptions options_;
  std::unique_ptr<TerrainOctree> octree_;
  mutable std::shared_mutex mutex_;
  std::unique_ptr<FclObstacles> fcl_;
  std::vector<NoFlyZone> zones_;
  std::uint64_t obstacle_version_ = 0;
  std::uint64_t static_version_ = 0;
  mutable std::once_flag regions_once_;
  mutable std::unique_ptr<const FlyableRegions> regions_;
};

}  // namespace skyroute
