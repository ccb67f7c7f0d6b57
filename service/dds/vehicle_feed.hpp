// What a follower of one vehicle (`skyroute px4`) takes from skyrouted: that vehicle's
// trajectories, the retraction of its trajectory (the daemon disposes it when the mission is
// cancelled), and whether the daemon is alive (any ServiceStatus heartbeat or trajectory).
// Polled: take() returns what arrived since the last call, without blocking.
#pragma once

#include <string>
#include <vector>

#include "service/dds/typed_io.hpp"

namespace skyroute::dds {

class VehicleFeed {
 public:
  struct Update {
    std::vector<TrajectoryData> trajectories;  // in arrival order
    bool retracted = false;                    // disposed: its samples, if any, are dropped
    bool heard_daemon = false;
    std::vector<Error> rejected;               // samples that failed validation
  };

  static Result<VehicleFeed> create(dds_entity_t participant, std::string vehicle_id);

  Result<Update> take() const;
  const Reader<TrajectoryData>& trajectories() const { return trajectories_; }

 private:
  VehicleFeed(std::string vehicle_id, Reader<TrajectoryData> trajectories, Reader<ServiceStatusData> heartbeat)
      : vehicle_id_(std::move(vehicle_id)), trajectories_(std::move(trajectories)), heartbeat_(std::move(heartbeat)) {}
  Status takeRetractions(Update& update) const;

  std::string vehicle_id_;
  Reader<TrajectoryData> trajectories_;
  Reader<ServiceStatusData> heartbeat_;
};

}  // namespace skyroute::dds
