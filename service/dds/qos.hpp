// QoS per topic family, following docs/dds.md. The same QoS object serves the topic, its writers
// and its readers, so every reader's request matches every writer's offer.
#pragma once

#include "service/dds/dds_entities.hpp"

namespace skyroute::dds {

// Trajectories: reliable, transient-local, keep-last 1 per vehicle, and the durability-service
// history set to keep-last 1 too (Cyclone serves late joiners from that history, not the
// writer's). Writers do not auto-dispose, so a restarted writer does not erase trajectories.
Qos trajectoryQos();

// Obstacle updates: the same durability as trajectories, keep-last 1 per obstacle, so a daemon
// that starts late still learns the obstacles that are in force.
Qos obstacleQos();

// Requests, cancels, fleet requests and plan statuses: reliable, volatile, keep-all (none may be
// dropped under a burst); a writer blocks at most max_blocking_s when a reader lags.
Qos commandQos(double max_blocking_s = 1.0);

// Service heartbeat: best effort, volatile, keep-last 1 per service.
Qos heartbeatQos();

// ROS 2 latched topics (the daemon's ROS 2 mirror): the trajectories' QoS, written in XCDR1, the
// only data representation ROS 2's Cyclone RMW accepts.
Qos rosLatchedQos();

// PX4's uXRCE-DDS streams, both ways: best effort (PX4 publishes best effort, and a late setpoint
// is worth nothing), volatile, keep-last 1, XCDR1.
Qos px4StreamQos();

}  // namespace skyroute::dds
