// The DDS entities of a MissionService on one domain, shared by its source files
// (mission_service.cpp, mission_service_shards.cpp). Nothing outside the service includes it.
#pragma once

#include <memory>
#include <optional>

#include "service/dds/mission_service.hpp"
#include "service/dds/ros2_mirror.hpp"
#include "service/dds/typed_io.hpp"
#include "service/dds/wait_loop.hpp"

namespace skyroute::dds {

// Members in creation order: the participant first, so it is destroyed last.
struct MissionService::Edge {
  int domain = 0;
  Entity participant;
  std::optional<Reader<MissionRequestData>> requests;
  std::optional<Reader<CancelRequestData>> cancels;
  std::optional<Reader<ObstacleUpdateData>> obstacles;
  std::optional<Reader<NoFlyZoneData>> zones;
  std::optional<Writer<TrajectoryData>> trajectories;
  std::optional<Writer<PlanStatusData>> statuses;
  std::optional<Writer<ServiceStatusData>> heartbeat;
  std::optional<Reader<ServiceStatusData>> rivals;  // every daemon's heartbeat, ours included
  std::optional<Reader<FleetRequestData>> fleet_requests;
  // Shard groups only (service.shard_group): every daemon's heartbeat, read for its liveliness
  // (shard_members.hpp), and every trajectory on the wire, the latest revision of each vehicle.
  std::optional<Reader<ServiceStatusData>> members;
  std::optional<Reader<TrajectoryData>> published;
  std::optional<Writer<FleetStatusData>> fleet_statuses;
  std::unique_ptr<Ros2Mirror> ros2;  // ROS 2 topics of every trajectory (ros2.enabled)
  std::optional<WaitLoop> loop;
};

}  // namespace skyroute::dds
