#include "service/world_model.hpp"

#include "terrain/terrain_world.hpp"

#include <cmath>
#include <filesystem>
#include <limits>

#include "service/number_text.hpp"

namespace skyroute {

Obstacle worldObstacle(const ObstacleUpdateData& update, double constant_velocity_horizon_s) {
  Obstacle o = update.obstacle;
  const double from_s = static_cast<double>(update.valid_from_utc_ns) * 1e-9;
  if (update.constant_velocity_enu_mps && update.constant_velocity_enu_mps->norm() > 0.0) {
    const Eigen::Vector3d v = *update.constant_velocity_enu_mps;
    const double until_s = update.valid_until_utc_ns != 0 ? static_cast<double>(update.valid_until_utc_ns) * 1e-9
                                                          : from_s + constant_velocity_horizon_s;
    BackAndForth track;
    track.from_m = o.center_m;
    track.to_m = o.center_m + v * std::max(0.0, until_s - from_s);
    track.speed_mps = v.norm();
    track.start_time_s = from_s;
    o.motion = track;
  } else if (o.motion) {
    o.motion->start_time_s = from_s;
  }
  return o;
}

Result<std::shared_ptr<WorldModel>> WorldModel::create(std::shared_ptr<const Heightfield> terrain,
                                                       const WorldModelOptions& options, std::string terrain_name) {
  if (!terrain) return make_error(ErrorCode::kInvalidArgument, "terrain", "no terrain loaded");
  if (!(options.vehicle_radius_m > 0.0)) {
    return make_error(ErrorCode::kInvalidArgument, "vehicle_radius_m", "must be positive");
  }
  std::shared_ptr<WorldModel> model(new WorldModel());
  model->terrain_ = std::move(terrain);
  model->options_ = options;
  model->terrain_name_ = std::move(terrain_name);
  return model;
}

Result<std::shared_ptr<WorldModel>> WorldModel::load(const std::string& dem_path, const WorldModelOptions& options) {
  CollisionWorldOptions world_options;
  world_options.vehicle_radius_m = options.vehicle_radius_m;
  world_options.build_octree = false;  // the worlds check everything on the heightfield
  auto terrain = loadTerrainWorld(dem_path, world_options);
  if (!terrain.ok()) {
    Error e = terrain.error();
    if (e.field.empty()) e.field = dem_path;
    return e;
  }
  return create(terrain->heightfield, options, std::filesystem::path(dem_path).filename().string());
}

Result<std::shared_ptr<const CollisionWorld>> WorldModel::worldFor(double min_clearance_m, double ceiling_m) {
  if (!(min_clearance_m >= options_.vehicle_radius_m)) {
    return make_error(ErrorCode::kInvalidArgument, "limits.min_clearance_agl_m",
                      "must be at least the vehicle radius (" + numberText(options_.vehicle_radius_m) + " m)");
  }
  std::lock_guard lock(mutex_);
  const auto key = std::make_pair(min_clearance_m, ceiling_m);
  if (auto it = worlds_.find(key); it != worlds_.end()) return std::shared_ptr<const CollisionWorld>(it->second);
  if (worlds_.size() >= options_.max_worlds) {
    // Drop a world nobody plans in any more (only the map holds it).
    for (auto it = worlds_.begin(); it != worlds_.end(); ++it) {
      if (it->second.use_count() == 1) {
        worlds_.erase(it);
        break;
      }
    }
  }
  CollisionWorldOptions options;
  options.vehicle_radius_m = options_.vehicle_radius_m;
  options.min_clearance_m = min_clearance_m;
  options.ceiling_m = ceiling_m;
  options.terrain_margin_m = options_.terrain_margin_m;
  options.build_octree = false;  // every check the planners make runs on the heightfield
  auto world = CollisionWorld::create(terrain_, options);
  if (!world.ok()) return world.error();
  for (const auto& [id, entry] : obstacles_) (*world)->upsertObstacle(entry.first);
  (*world)->setNoFlyZones(zonesLocked());
  worlds_.emplace(key, *world);
  return std::shared_ptr<const CollisionWorld>(*world);
}

std::uint64_t WorldModel::apply(const ObstacleUpdateData& update) {
  std::lock_guard lock(mutex_);
  const std::uint64_t id = update.obstacle.id;
  ++version_;
  if (update.remove) {
    obstacles_.erase(id);
    updates_.erase(id);
    for (auto& [key, world] : worlds_) world->removeObstacle(id);
    return id;
  }
  const Obstacle o = worldObstacle(update, options_.constant_velocity_horizon_s);
  const double until_s = update.valid_until_utc_ns != 0 ? static_cast<double>(update.valid_until_utc_ns) * 1e-9
                                                        : std::numeric_limits<double>::infinity();
  obstacles_[id] = {o, until_s};
  updates_[id] = update;
  for (auto& [key, world] : worlds_) world->upsertObstacle(o);
  return id;
}

std::vector<ObstacleUpdateData> WorldModel::obstacleUpdates() const {
  std::lock_guard lock(mutex_);
  std::vector<ObstacleUpdateData> out;
  out.reserve(updates_.size());
  for (const auto& [id, update] : updates_) out.push_back(update);
  return out;
}

void WorldModel::adoptObstacles(const WorldModel& from) {
  const LocalFrame& old_frame = from.frame();
  const LocalFrame& new_frame = frame();
  auto move = [&](const Eigen::Vector3d& p) { return new_frame.toEnu(old_frame.toGeo(p)); };
  for (ObstacleUpdateData update : from.obstacleUpdates()) {
    Obstacle& o = update.obstacle;
    if (update.constant_velocity_enu_mps) {
      // The velocity turns with the frame: carry its end point over too.
      const Eigen::Vector3d ahead = move(o.center_m + *update.constant_velocity_enu_mps);
      o.center_m = move(o.center_m);
      update.constant_velocity_enu_mps = ahead - o.center_m;
    } else {
      o.center_m = move(o.center_m);
    }
    if (o.motion) {
      o.motion->from_m = move(o.motion->from_m);
      o.motion->to_m = move(o.motion->to_m);
    }
    apply(update);
  }
  const double up_shift_m = old_frame.anchor().alt_amsl_m - new_frame.anchor().alt_amsl_m;
  for (NoFlyZone zone : from.publishedNoFlyZones()) {
    for (Eigen::Vector2d& v : zone.ring_m) v = move(Eigen::Vector3d(v.x(), v.y(), 0.0)).head<2>();
    zone.floor_m += up_shift_m;
    zone.ceiling_m += up_shift_m;
    upsertNoFlyZone(std::move(zone));
  }
}

std::vector<NoFlyZone> WorldModel::zonesLocked() const {
  std::vector<NoFlyZone> zones = configured_zones_;
  for (const auto& [name, zone] : published_zones_) zones.push_back(zone);
  return zones;
}

void WorldModel::zonesChangedLocked() {
  ++version_;
  const std::vector<NoFlyZone> zones = zonesLocked();
  for (auto& [key, world] : worlds_) world->setNoFlyZones(zones);
}

void WorldModel::setNoFlyZones(std::vector<NoFlyZone> zones) {
  std::lock_guard lock(mutex_);
  configured_zones_ = std::move(zones);
  zonesChangedLocked();
}

void WorldModel::upsertNoFlyZone(NoFlyZone zone) {
  std::lock_guard lock(mutex_);
  std::string name = zone.name;
  published_zones_[std::move(name)] = std::move(zone);
  zonesChangedLocked();
}

bool WorldModel::removeNoFlyZone(const std::string& name) {
  std::lock_guard lock(mutex_);
  if (published_zones_.erase(name) == 0) return false;
  zonesChangedLocked();
  return true;
}

std::vector<NoFlyZone> WorldModel::noFlyZones() const {
  std::lock_guard lock(mutex_);
  return zonesLocked();
}

std::vector<NoFlyZone> WorldModel::publishedNoFlyZones() const {
  std::lock_guard lock(mutex_);
  std::vector<NoFlyZone> zones;
  for (const auto& [name, zone] : published_zones_) zones.push_back(zone);
  return zones;
}

std::size_t WorldModel::publishedNoFlyVertices(const std::string& except) const {
  std::lock_guard lock(mutex_);
  std::size_t vertices = 0;
  for (const auto& [name, zone] : published_zones_) {
    if (name != except) vertices += zone.ring_m.size();
  }
  return vertices;
}

std::size_t WorldModel::expire(double now_s) {
  std::lock_guard lock(mutex_);
  std::size_t removed = 0;
  for (auto it = obstacles_.begin(); it != obstacles_.end();) {
    if (it->second.second <= now_s) {
      for (auto& [key, world] : worlds_) world->removeObstacle(it->first);
      updates_.erase(it->first);
      it = obstacles_.erase(it);
      ++removed;
    } else {
      ++it;
    }
  }
  auto ended = [&](const NoFlyZone& z) { return z.valid_until_s && *z.valid_until_s <= now_s; };
  const std::size_t zones_ended =
      std::erase_if(configured_zones_, ended) +
      std::erase_if(published_zones_, [&](const auto& entry) { return ended(entry.second); });
  if (zones_ended > 0) zonesChangedLocked();
  removed += zones_ended;
  if (removed > 0) ++version_;
  return removed;
}

std::size_t WorldModel::obstacleCount() const {
  std::lock_guard lock(mutex_);
  return obstacles_.size();
}

std::optional<std::int64_t> WorldModel::validFromOf(std::uint64_t id) const {
  std::lock_guard lock(mutex_);
  const auto it = updates_.find(id);
  if (it == updates_.end()) return std::nullopt;
  return it->second.valid_from_utc_ns;
}

std::uint64_t WorldModel::version() const {
  std::lock_guard lock(mutex_);
  return version_;
}

}  // namespace skyroute
