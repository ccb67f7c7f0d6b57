#include "service/gcs_map_state.hpp"

#include <chrono>
#include <cmath>

#include <nlohmann/json.hpp>

#include "service/world_model.hpp"

namespace skyroute {
namespace {

using nlohmann::json;

// Decimal rounding that prints short: n / 10^k is the double nearest to the decimal.
double rounded(double v, double per_unit) { return std::round(v * per_unit) / per_unit; }
double roundedDeg(double deg) { return rounded(deg, 1e7); }  // about 1 cm
double roundedM(double m) { return rounded(m, 10.0); }
std::int64_t utcMs(std::int64_t utc_ns) { return utc_ns / 1'000'000; }

TrajectoryData thinned(const TrajectoryData& t, std::size_t max_samples) {
  if (t.samples.size() <= max_samples) return t;
  TrajectoryData out = t;
  out.samples.clear();
  const std::size_t stride = (t.samples.size() + max_samples - 2) / (max_samples - 1);
  for (std::size_t i = 0; i < t.samples.size(); i += stride) out.samples.push_back(t.samples[i]);
  if (out.samples.back().t_rel_s != t.samples.back().t_rel_s) out.samples.push_back(t.samples.back());
  return out;
}

std::vector<double> groundUnder(const Heightfield& terrain, const TrajectoryData& t) {
  std::vector<double> east(t.samples.size()), north(t.samples.size());
  for (std::size_t i = 0; i < t.samples.size(); ++i) {
    east[i] = t.samples[i].geo.lon_deg;
    north[i] = t.samples[i].geo.lat_deg;
  }
  // Through the terrain's own frame, so the profile is right even if the daemon anchors elsewhere.
  terrain.frame().lonLatToEastNorth(east.data(), north.data(), east.size());
  std::vector<double> ground(t.samples.size());
  for (std::size_t i = 0; i < ground.size(); ++i) ground[i] = terrain.heightAt(east[i], north[i]);
  return ground;
}

json geoJson(const LocalFrame& frame, const Eigen::Vector3d& enu_m) {
  const GeoPoint g = frame.toGeo(enu_m);
  return {{"lat_deg", roundedDeg(g.lat_deg)}, {"lon_deg", roundedDeg(g.lon_deg)}, {"alt_amsl_m", roundedM(g.alt_amsl_m)}};
}

json trajectoryJson(const TrajectoryData& t, const std::vector<double>& ground_m, std::size_t original_samples) {
  json utc = json::array(), lat = json::array(), lon = json::array(), alt = json::array(), ground = json::array();
  for (std::size_t i = 0; i < t.samples.size(); ++i) {
    const auto& s = t.samples[i];
    utc.push_back(utcMs(s.utc_ns));
    lat.push_back(roundedDeg(s.geo.lat_deg));
    lon.push_back(roundedDeg(s.geo.lon_deg));
    alt.push_back(roundedM(s.geo.alt_amsl_m));
    ground.push_back(std::isfinite(ground_m[i]) ? json(roundedM(ground_m[i])) : json(nullptr));
  }
  return {{"plan_id", t.plan_id},
          {"revision", t.revision},
          {"request_id", t.request_id},
          {"created_utc_ms", utcMs(t.created_utc_ns)},
          {"start_utc_ms", t.samples.empty() ? 0 : utcMs(t.samples.front().utc_ns)},
          {"end_utc_ms", t.samples.empty() ? 0 : utcMs(t.samples.back().utc_ns)},
          {"sample_count", original_samples},
          {"samples", {{"utc_ms", utc}, {"lat_deg", lat}, {"lon_deg", lon}, {"alt_amsl_m", alt}, {"ground_amsl_m", ground}}}};
}

json statusJson(const PlanStatusData& s) {
  return {{"request_id", s.request_id},     {"state", to_string(s.state)}, {"error", to_string(s.error_code)},
          {"field", s.field},               {"message", s.message},        {"planning_time_s", s.planning_time_s}};
}

json obstacleJson(const LocalFrame& frame, const Obstacle& track, const ObstacleUpdateData& update) {
  const bool moving = track.moving();
  const Eigen::Vector3d from = moving ? track.motion->from_m : track.centerAt(0.0);
  const Eigen::Vector3d to = moving ? track.motion->to_m : from;
  return {{"id", track.id},
          {"shape", to_string(track.shape)},
          {"size_m", {roundedM(track.size_m.x()), roundedM(track.size_m.y()), roundedM(track.size_m.z())}},
          {"motion", to_string(update.motionKind())},
          {"valid_from_utc_ms", utcMs(update.valid_from_utc_ns)},
          {"valid_until_utc_ms", update.valid_until_utc_ns != 0 ? json(utcMs(update.valid_until_utc_ns)) : json(nullptr)},
          // The centre goes from -> to -> from ... at speed_mps, leaving `from` at valid_from
          // (Obstacle::centerAt with worldObstacle's start time).
          {"track",
           {{"from", geoJson(frame, from)},
            {"to", geoJson(frame, to)},
            {"speed_mps", moving ? track.motion->speed_mps : 0.0},
            {"start_utc_ms", utcMs(update.valid_from_utc_ns)}}}};
}

}  // namespace

GcsMapState::GcsMapState(std::shared_ptr<const Heightfield> terrain, GeoPng image, std::string terrain_name)
    : terrain_(std::move(terrain)), image_(std::move(image)), terrain_name_(std::move(terrain_name)) {}

void GcsMapState::onTrajectory(const TrajectoryData& trajectory) {
  TrajectoryData kept = thinned(trajectory, kMaxSamplesPerVehicle);
  std::vector<double> ground = groundUnder(*terrain_, kept);
  std::lock_guard lock(mutex_);
  Vehicle& v = vehicles_[trajectory.vehicle_id];
  // A stale revision of the plan on display (reordered delivery) must not replace a newer one.
  if (v.trajectory && v.trajectory->plan_id == kept.plan_id && v.trajectory->revision > kept.revision) return;
  v.sample_count = trajectory.samples.size();
  v.trajectory = std::move(kept);
  v.ground_m = std::move(ground);
  changed();
}

void GcsMapState::onStatus(const PlanStatusData& status) {
  if (status.vehicle_id.empty()) return;
  std::lock_guard lock(mutex_);
  vehicles_[status.vehicle_id].status = status;
  changed();
}

void GcsMapState::onObstacle(const ObstacleUpdateData& update) {
  const std::int64_t now_ns = utcNowNs();
  std::lock_guard lock(mutex_);
  if (update.remove) {
    obstacles_.erase(update.obstacle.id);
  } else {
    obstacles_[update.obstacle.id] = {worldObstacle(update, WorldModelOptions{}.constant_velocity_horizon_s), update};
  }
  std::erase_if(obstacles_, [&](const auto& entry) {
    const std::int64_t until = entry.second.update.valid_until_utc_ns;
    return until != 0 && until <= now_ns;
  });
  changed();
}

void GcsMapState::onNoFlyZone(const NoFlyZoneData& zone) {
  std::lock_guard lock(mutex_);
  if (zone.remove) {
    zones_.erase(zone.zone_id);
  } else {
    zones_[zone.zone_id] = zone;
  }
  changed();
}

void GcsMapState::changed() {
  ++version_;
  cached_json_.reset();
  changed_cv_.notify_all();
}

GcsMapState::Snapshot GcsMapState::snapshot() const {
  std::lock_guard lock(mutex_);
  if (!cached_json_) cached_json_ = std::make_shared<const std::string>(render());
  return {version_, cached_json_};
}

std::uint64_t GcsMapState::version() const {
  std::lock_guard lock(mutex_);
  return version_;
}

std::uint64_t GcsMapState::waitForVersionAbove(std::uint64_t seen, double timeout_s) const {
  std::unique_lock lock(mutex_);
  changed_cv_.wait_for(lock, std::chrono::duration<double>(timeout_s), [&] { return version_ > seen || closed_; });
  return version_;
}

void GcsMapState::close() {
  std::lock_guard lock(mutex_);
  closed_ = true;
  changed_cv_.notify_all();
}

bool GcsMapState::closed() const {
  std::lock_guard lock(mutex_);
  return closed_;
}

std::string GcsMapState::render() const {
  const LocalFrame& frame = terrain_->frame();
  json vehicles = json::array();
  for (const auto& [id, v] : vehicles_) {
    json entry = {{"vehicle_id", id}, {"trajectory", nullptr}, {"status", nullptr}};
    if (v.trajectory) entry["trajectory"] = trajectoryJson(*v.trajectory, v.ground_m, v.sample_count);
    if (v.status) entry["status"] = statusJson(*v.status);
    vehicles.push_back(std::move(entry));
  }
  json obstacles = json::array();
  for (const auto& [id, o] : obstacles_) obstacles.push_back(obstacleJson(frame, o.track, o.update));
  json zones = json::array();
  for (const auto& [id, z] : zones_) {
    json ring = json::array();
    for (const GeoPoint& p : z.ring) ring.push_back({{"lat_deg", p.lat_deg}, {"lon_deg", p.lon_deg}});
    zones.push_back({{"id", id}, {"ring", std::move(ring)}, {"floor_amsl_m", z.floor_amsl_m},
                     {"ceiling_amsl_m", z.ceiling_amsl_m}});
  }
  const json state = {
      {"format", "skyroute-gcs-state"},
      {"format_version", 1},
      {"version", version_},
      {"map",
       {{"image", "hillshade.png"},
        {"width_px", image_.width_px},
        {"height_px", image_.height_px},
        {"west_deg", image_.west_deg},
        {"south_deg", image_.south_deg},
        {"east_deg", image_.east_deg},
        {"north_deg", image_.north_deg},
        {"terrain", terrain_name_},
        {"min_height_m", terrain_->minHeightM()},
        {"max_height_m", terrain_->maxHeightM()}}},
      {"vehicles", std::move(vehicles)},
      {"obstacles", std::move(obstacles)},
      {"no_fly_zones", std::move(zones)},
  };
  return state.dump();
}

}  // namespace skyroute
