// The engine's world: the terrain (one heightfield, shared) and the obstacles in force, seen
// through one CollisionWorld per (minimum clearance, ceiling) pair that requests ask for, so each
// vehicle is checked with its own limits while every world holds the same obstacles.
// The world clock is UTC seconds since the Unix epoch, the clock of ObstacleUpdateData.
// Thread-safe: the engine's planners read while the DDS edge's updates write.
#pragma once

#include <cstdint>
#include <map>
#include <memory>
#include <optional>
#include <mutex>
#include <string>
#include <utility>
#include <vector>

#include "service/mission_types.hpp"
#include "terrain/collision_world.hpp"
#include "terrain/heightfield.hpp"

namespace skyroute {

struct WorldModelOptions {
  double vehicle_radius_m = 5.0;          // every vehicle's bounding sphere
  double terrain_margin_m = 0.0;          // horizontal distance kept from the ground
  // A constant-velocity obstacle without an end of validity is predicted this far ahead (it is
  // modelled as a track from its position to where it will be then).
  double constant_velocity_horizon_s = 3600.0;
  std::size_t max_worlds = 64;            // distinct (clearance, ceiling) pairs kept
};

// The obstacle an update describes, on the world clock: a back-and-forth motion starts at
// valid_from; a constant velocity becomes a track from the position at valid_from to the position
// at valid_until (or the prediction horizon).
Obstacle worldObstacle(const ObstacleUpdateData& update, double constant_velocity_horizon_s);

class WorldModel {
 public:
  static Result<std::shared_ptr<WorldModel>> create(std::shared_ptr<const Heightfield> terrain,
                                                    const WorldModelOptions& options, std::string terrain_name);
  // The DEM file's heightfield as a world model: the one way the daemon and the CLI load their
  // terrain, so both plan on the same world. Errors name the file.
  static Result<std::shared_ptr<WorldModel>> load(const std::string& dem_path, const WorldModelOptions& options);

  const Heightfield& terrain() const { return *terrain_; }
  const LocalFrame& frame() const { return terrain_->frame(); }
  const std::string& terrainName() const { return terrain_name_; }

  // The collision world for a vehicle's limits (made on first use, with the obstacles in force).
  // Errors name the limit: kInvalidArgument "limits.min_clearance_agl_m" below the vehicle radius.
  Result<std::shared_ptr<const CollisionWorld>> worldFor(double min_clearance_m, double ceiling_m);

  // Applies an update (validated by the caller). Returns the obstacle's id.
  std::uint64_t apply(const ObstacleUpdateData& update);
  // The updates in force, as applied (a world on another terrain takes them over).
  std::vector<ObstacleUpdateData> obstacleUpdates() const;
  // Applies `from`'s obstacles and no-fly zones here; positions go through WGS84 when the two
  // frames differ, so an obstacle or a zone stays where it is on the ground.
  void adoptObstacles(const WorldModel& from);
  // Drops obstacles and no-fly zones whose validity ended at or before now_s; returns how many.
  std::size_t expire(double now_s);
  std::size_t obstacleCount() const;
  // valid_from of the update in force for obstacle `id`; nothing when no such obstacle is.
  std::optional<std::int64_t> validFromOf(std::uint64_t id) const;
  std::uint64_t version() const;  // grows with every change of the obstacles or no-fly zones

  // No-fly zones (checked by the caller), of two kinds: the configured set (a file), replaced as a
  // whole, and published zones (DDS), keyed by name, which a world on another terrain takes over
  // (adoptObstacles) while the configured set comes from the new configuration. Every world gets
  // both; zones whose window ends are dropped by expire() like obstacles.
  void setNoFlyZones(std::vector<NoFlyZone> zones);
  void upsertNoFlyZone(NoFlyZone zone);
  bool removeNoFlyZone(const std::string& name);  // false: no published zone of that name
  std::vector<NoFlyZone> noFlyZones() const;      // configured, then published
  std::vector<NoFlyZone> publishedNoFlyZones() const;
  // The vertices of the published zones together, less those of the zone named `except`.
  std::size_t publishedNoFlyVertices(const std::string& except = "") const;

 private:
  WorldModel() = default;

  std::shared_ptr<const Heightfield> terrain_;
  WorldModelOptions options_;
  std::string terrain_name_;
  mutable std::mutex mutex_;
  std::map<std::pair<double, double>, std::shared_ptr<CollisionWorld>> worlds_;
  std::map<std::uint64_t, std::pair<Obstacle, double>> obstacles_;  // id -> obstacle, valid until (s; inf)
  std::map<std::uint64_t, ObstacleUpdateData> updates_;             // id -> the update it came from
  std::vector<NoFlyZone> zonesLocked() const;
  void zonesChangedLocked();  // version and every world
  std::vector<NoFlyZone> configured_zones_;
  std::map<std::string, NoFlyZone> published_zones_;
  std::uint64_t version_ = 0;
};

}  // namespace skyroute
