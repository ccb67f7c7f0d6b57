// The skyrouted daemons on a domain, each named by its instance id and by the GUID of one of its
// entities (whose first 12 bytes are its participant's), so a tool can ask whether a writer of
// its own reaches each daemon (reachesParticipantOf) rather than only counting readers (a
// ground station reads the same topics). A daemon names itself in its participant's USER_DATA;
// under DDS Security, where a participant announces nothing, in its heartbeat writer's.
#pragma once

#include <string>
#include <vector>

#include <dds/dds.h>

namespace skyroute::dds {

struct DaemonParticipant {
  std::string instance_id;
  std::string guid;  // 32 hex digits (guidText)
};

// participant_reader: a reader of the built-in DCPSParticipant topic (createParticipantReader);
// heartbeat_reader: a reader of skyroute_service_status. One entry per instance.
std::vector<DaemonParticipant> daemonParticipants(dds_entity_t participant_reader, dds_entity_t heartbeat_reader);

}  // namespace skyroute::dds
