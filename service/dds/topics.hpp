// Which IDL type, topic name and QoS go with each plain message type. Topic names are fixed; tests
// separate themselves by domain id.
#pragma once

#include "service/dds/conversions.hpp"
#include "service/dds/no_fly_conversions.hpp"
#include "service/dds/qos.hpp"

namespace skyroute::dds {

template <class Plain>
struct TopicTraits;

template <>
struct TopicTraits<MissionRequestData> {
  using Wire = skyroute_msgs_MissionRequest;
  static constexpr const char* kName = "skyroute_mission_request";
  static const dds_topic_descriptor_t* descriptor() { return &skyroute_msgs_MissionRequest_desc; }
  static Qos qos() { return commandQos(); }
};

template <>
struct TopicTraits<TrajectoryData> {
  using Wire = skyroute_msgs_Trajectory;
  static constexpr const char* kName = "skyroute_trajectory";
  static const dds_topic_descriptor_t* descriptor() { return &skyroute_msgs_Trajectory_desc; }
  static Qos qos() { return trajectoryQos(); }
};

template <>
struct TopicTraits<PlanStatusData> {
  using Wire = skyroute_msgs_PlanStatus;
  static constexpr const char* kName = "skyroute_plan_status";
  static const dds_topic_descriptor_t* descriptor() { return &skyroute_msgs_PlanStatus_desc; }
  static Qos qos() { return commandQos(); }
};

template <>
struct TopicTraits<ObstacleUpdateData> {
  using Wire = skyroute_msgs_ObstacleUpdate;
  static constexpr const char* kName = "skyroute_obstacle_update";
  static const dds_topic_descriptor_t* descriptor() { return &skyroute_msgs_ObstacleUpdate_desc; }
  static Qos qos() { return obstacleQos(); }
};

template <>
struct TopicTraits<CancelRequestData> {
  using Wire = skyroute_msgs_CancelRequest;
  static constexpr const char* kName = "skyroute_cancel_request";
  static const dds_topic_descriptor_t* descriptor() { return &skyroute_msgs_CancelRequest_desc; }
  static Qos qos() { return commandQos(); }
};

template <>
struct TopicTraits<ServiceStatusData> {
  using Wire = skyroute_msgs_ServiceStatus;
  static constexpr const char* kName = "skyroute_service_status";
  static const dds_topic_descriptor_t* descriptor() { return &skyroute_msgs_ServiceStatus_desc; }
  static Qos qos() { return heartbeatQos(); }
};

template <>
struct TopicTraits<FleetRequestData> {
  using Wire = skyroute_msgs_FleetRequest;
  static constexpr const char* kName = "skyroute_fleet_request";
  static const dds_topic_descriptor_t* descriptor() { return &skyroute_msgs_FleetRequest_desc; }
  static Qos qos() { return commandQos(); }
};

template <>
struct TopicTraits<FleetStatusData> {
  using Wire = skyroute_msgs_FleetStatus;
  static constexpr const char* kName = "skyroute_fleet_status";
  static const dds_topic_descriptor_t* descriptor() { return &skyroute_msgs_FleetStatus_desc; }
  static Qos qos() { return commandQos(); }
};

template <>
struct TopicTraits<NoFlyZoneData> {
  using Wire = skyroute_msgs_NoFlyZone;
  static constexpr const char* kName = "skyroute_no_fly_zone";
  static const dds_topic_descriptor_t* descriptor() { return &skyroute_msgs_NoFlyZone_desc; }
  static Qos qos() { return obstacleQos(); }  // the same durability: late joiners get the zones in force
};

}  // namespace skyroute::dds
