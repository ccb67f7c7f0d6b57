// Who a running daemon is, on the wire: its service_id, an instance id unique to the process, its
// role (primary or hot standby), its host, pid and start time. Written into the USER_DATA QoS of its participant and of its heartbeat
// writer, every other participant learns it at discovery, before any sample: a daemon sees at once that another one
// serves its service_id (the older stays; the younger refuses to start, or stops), and a client
// counts the live services it must reach.
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include <dds/dds.h>

#include "service/shard_coverage.hpp"

namespace skyroute::dds {

struct ServiceInstance {
  std::string service_id;
  std::string instance_id;
  std::string host;
  std::int64_t pid = 0;
  std::int64_t started_utc_ns = 0;
  double heartbeat_period_s = 1.0;  // at start (a reload may change it; each heartbeat says)
  std::string role = "primary";     // service.role: primary or standby (a daemon that names none: primary)
  std::string shard_group;          // service.shard_group ("" = not sharded, or a daemon that names none)
  // A shard's earlier lives its journal kept (shard_coverage.hpp): which older requests it read.
  std::vector<CoverageInterval> past_coverage;

  // A new instance of this process (random instance id), started now.
  static ServiceInstance current(const std::string& service_id, double heartbeat_period_s = 1.0,
                                 const std::string& role = "primary");
  // "skyrouted-instance/1;service_id=...;instance=...;host=...;pid=...;started_utc_ns=...;heartbeat_period_s=...;role=...
  // [;shard_group=...][;coverage=s1-e1,...]" (an older reader skips the fields it does not know)
  std::string userData() const;
  static std::optional<ServiceInstance> fromUserData(std::string_view text);

  // Which of two instances with one service_id keeps serving: the one started first (ties: the
  // smaller instance id), so both sides reach the same verdict on their own.
  bool precedes(const ServiceInstance& other) const;
  // Whether the two serve one service_id in the same role, so one of them must stop (a primary
  // and its standby are partners, not rivals).
  bool rivals(const ServiceInstance& other) const { return service_id == other.service_id && role == other.role; }
  std::string describe() const;  // "instance 3f2a... (primary, pid 1234 on host, started 2026-...Z)"
};

// The daemons behind every heartbeat writer `heartbeat_reader` is matched with (this process's
// own included), from their USER_DATA. Writers without it are skipped.
std::vector<ServiceInstance> matchedInstances(dds_entity_t heartbeat_reader);

// The instance a discovered participant or endpoint announces in its QoS's USER_DATA; nothing for
// another program's (no or foreign USER_DATA) or a null QoS.
std::optional<ServiceInstance> announcedInstance(const dds_qos_t* qos);

// The daemons among the live participants a DCPSParticipant reader (createParticipantReader) has
// discovered, from their USER_DATA: participant discovery comes first, so this is the earliest
// count of the daemons on a domain (their endpoints follow).
std::vector<ServiceInstance> discoveredInstances(dds_entity_t participant_reader);

}  // namespace skyroute::dds
