// QoS per topic family, following docs/dds.md. The same QoS object serves the topic, its writers
// and its readers, so every reader's request matches every writer's offer.
#pragma once

#include "service/dds/dds_entities.hpp"

namespace skyroute::dds {

// Trajectories, plan and fleet statuses and the service heartbeat use EXCLUSIVE ownership, on
// the topic, the writers and every reader alike (a mismatch would not match): per instance a
// reader takes only the live writer of the highest strength, so a primary daemon and its hot
// standby (one service_id, docs/dds.md) both publish and ground stations hear one of them. The
// strength and the liveliness lease are the writer's own (ownedWriterQos).

// Trajectories: reliable, transient-local, keep-last 1 per vehicle, and the durability-service
// history set to keep-last 1 too (Cyclone serves late joiners from that history, not the
// writer's). Writers do not auto-dispose, so a restarted writer does not erase trajectories.
Qos trajectoryQos();

// Obstacle updates: the same durability as trajectories, keep-last 1 per obstacle, so a daemon
// that starts late still learns the obstacles that are in force.
Qos obstacleQos();

// Requests, cancels and fleet requests: reliable, volatile, keep-all (none may be dropped under a
// burst); a writer blocks at most max_blocking_s when a reader lags.
Qos commandQos(double max_blocking_s = 1.0);

// Plan and fleet statuses: the commands' QoS with exclusive ownership.
Qos statusQos();

// Service heartbeat: best effort, volatile, keep-last 1 per service, exclusive ownership.
Qos heartbeatQos();

// What a daemon's writer of an owned topic offers besides the topic's QoS: its ownership strength
// and an AUTOMATIC liveliness lease, after which readers hand its instances to the next strongest
// writer (a killed primary's to the standby). Autodispose stays off, so a primary that stops
// cleanly does not dispose the trajectories its standby goes on serving.
struct OwnedWriterOptions {
  int32_t ownership_strength = 0;
  double liveliness_lease_s = 0.5;
};
void applyOwnedWriterQos(dds_qos_t* qos, const OwnedWriterOptions& options);

// ROS 2 latched topics (the daemon's ROS 2 mirror): the trajectories' QoS, written in XCDR1, the
// only data representation ROS 2's Cyclone RMW accepts.
Qos rosLatchedQos();

// PX4's uXRCE-DDS streams, both ways: best effort (PX4 publishes best effort, and a late setpoint
// is worth nothing), volatile, keep-last 1, XCDR1.
Qos px4StreamQos();

}  // namespace skyroute::dds
