// Which IDL type, topic name and QoS go with each plain message type. Topic names are fixed; tests
// separate themselves by domain id.
#pragma once

#include "service/dds/conversions.hpp"
#include "service/dds/no_fly_conversions.hpp"
#include "service/dds/qos.hpp"

namespace skyroute::dds {

template <class Plain>
struct TopicTraits;

// One topic: its plain type, the IDL struct (skyroute_msgs_<IDL>), the topic name and the QoS.
#define SKYROUTE_TOPIC(PLAIN, IDL, NAME, QOS)                                               \
  template <>                                                                               \
  struct TopicTraits<PLAIN> {                                                               \
    using Wire = skyroute_msgs_##IDL;                                                       \
    static constexpr const char* kName = NAME;                                              \
    static const dds_topic_descriptor_t* descriptor() { return &skyroute_msgs_##IDL##_desc; } \
    static Qos qos() { return QOS(); }                                                      \
  };

SKYROUTE_TOPIC(MissionRequestData, MissionRequest, "skyroute_mission_request", commandQos)
SKYROUTE_TOPIC(TrajectoryData, Trajectory, "skyroute_trajectory", trajectoryQos)
SKYROUTE_TOPIC(PlanStatusData, PlanStatus, "skyroute_plan_status", statusQos)
SKYROUTE_TOPIC(ObstacleUpdateData, ObstacleUpdate, "skyroute_obstacle_update", obstacleQos)
SKYROUTE_TOPIC(CancelRequestData, CancelRequest, "skyroute_cancel_request", commandQos)
SKYROUTE_TOPIC(ServiceStatusData, ServiceStatus, "skyroute_service_status", heartbeatQos)
SKYROUTE_TOPIC(FleetRequestData, FleetRequest, "skyroute_fleet_request", commandQos)
SKYROUTE_TOPIC(FleetStatusData, FleetStatus, "skyroute_fleet_status", statusQos)
// Obstacles' durability: a late-joining daemon gets the zones in force.
SKYROUTE_TOPIC(NoFlyZoneData, NoFlyZone, "skyroute_no_fly_zone", obstacleQos)

#undef SKYROUTE_TOPIC

}  // namespace skyroute::dds
