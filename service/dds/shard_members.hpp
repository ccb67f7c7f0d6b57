// The live members of a shard group, from the heartbeat topic: every daemon's heartbeat writer
// names its shard group in its USER_DATA (service_instance.hpp), and its instance on a reader
// (keyed by service_id) stops being alive when the writer's liveliness lease runs out (a killed
// daemon, dds.liveliness_lease_s) or it leaves. No membership protocol of our own: DDS discovery
// and liveliness are the membership.
#pragma once

#include <string>
#include <vector>

#include <dds/dds.h>

#include "service/dds/service_instance.hpp"

namespace skyroute::dds {

// The daemons in `group` behind the writers `heartbeat_reader` is matched with, less those whose
// heartbeat instance is known not alive. The reader's samples are read, never taken: the reader
// keeps the latest state of each service_id (keep-last 1). A matched daemon whose first heartbeat
// has not arrived counts as live, a restarted one too (the state that says not alive is then its
// predecessor's, named by the instance id of the last heartbeat). A member's start is that of its current life: its heartbeat's
// life_started_utc_ns when later than its USER_DATA's start (a shard that stalled began anew).
std::vector<ServiceInstance> liveShardMembers(dds_entity_t heartbeat_reader, const std::string& group);

}  // namespace skyroute::dds
