// The ground station's live picture, as the web map shows it: the terrain image and its WGS84
// bounds, each vehicle's current trajectory with the ground height under every sample and its
// latest plan status, the obstacles in force with the tracks the planner predicts for them, and
// the no-fly zones in force (from a file or the DDS zone topic).
//
// The DDS thread writes (on*), the web server's threads read: every change bumps a version, and
// snapshot() gives one version's JSON text, made once per version. The JSON layout is described in
// docs/gcs.md.
#pragma once

#include <condition_variable>
#include <cstdint>
#include <map>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <vector>

#include "service/geo_hillshade.hpp"
#include "service/mission_types.hpp"
#include "service/no_fly_zone_data.hpp"
#include "terrain/heightfield.hpp"

namespace skyroute {

class GcsMapState {
 public:
  // A trajectory longer than this is thinned (every k-th sample, the last one kept) for the page.
  static constexpr std::size_t kMaxSamplesPerVehicle = 2000;

  // terrain: the DEM the daemon plans on (its frame places obstacles, its heights the ground
  // profile); image: its hillshade on a WGS84 grid, served as /hillshade.png.
  GcsMapState(std::shared_ptr<const Heightfield> terrain, GeoPng image, std::string terrain_name);

  void onTrajectory(const TrajectoryData& trajectory);
  void onStatus(const PlanStatusData& status);
  void onObstacle(const ObstacleUpdateData& update);
  void onNoFlyZone(const NoFlyZoneData& zone);  // keyed by zone_id; remove lifts it

  struct Snapshot {
    std::uint64_t version = 0;  // 1 before anything arrived; grows with each change
    std::shared_ptr<const std::string> json;
  };
  Snapshot snapshot() const;
  std::uint64_t version() const;

  // Blocks until the version is above `seen`, timeout_s passes or close() is called; returns the
  // version then.
  std::uint64_t waitForVersionAbove(std::uint64_t seen, double timeout_s) const;
  // Nothing will change any more: wakes every waiter, now and later (the server is stopping).
  void close();
  bool closed() const;

  const GeoPng& image() const { return image_; }

 private:
  struct Vehicle {
    std::optional<TrajectoryData> trajectory;  // thinned
    std::size_t sample_count = 0;              // samples before thinning
    std::vector<double> ground_m;              // ground height under each kept sample (NaN off the DEM)
    std::optional<PlanStatusData> status;
  };
  struct ObstacleEntry {
    Obstacle track;  // as the planner predicts it (worldObstacle)
    ObstacleUpdateData update;
  };
  void changed();  // under mutex_: bump the version, drop the cached JSON, wake waiters
  std::string render() const;  // under mutex_

  const std::shared_ptr<const Heightfield> terrain_;
  const GeoPng image_;
  const std::string terrain_name_;

  mutable std::mutex mutex_;
  mutable std::condition_variable changed_cv_;
  std::uint64_t version_ = 1;
  bool closed_ = false;
  std::map<std::string, Vehicle> vehicles_;
  std::map<std::uint64_t, ObstacleEntry> obstacles_;
  std::map<std::string, NoFlyZoneData> zones_;
  mutable std::shared_ptr<const std::string> cached_json_;  // of version_
};

}  // namespace skyroute
