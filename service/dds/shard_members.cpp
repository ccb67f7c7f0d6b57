#include "service/dds/shard_members.hpp"

#include <array>
#include <map>

#include "service/dds/topics.hpp"

namespace skyroute::dds {

std::vector<ServiceInstance> liveShardMembers(dds_entity_t heartbeat_reader, const std::string& group) {
  using Wire = TopicTraits<ServiceStatusData>::Wire;
  struct Latest {
    bool alive = false;                  // its heartbeat instance is alive
    std::string instance_id;             // the daemon behind its latest heartbeat
    std::int64_t life_started_utc_ns = 0;
  };
  std::map<std::string, Latest> latest;  // service_id -> its latest heartbeat
  constexpr std::size_t kBatch = 256;
  std::array<void*, kBatch> loans{};
  std::array<dds_sample_info_t, kBatch> infos{};
  const dds_return_t n = dds_read(heartbeat_reader, loans.data(), infos.data(), kBatch, kBatch);
  for (dds_return_t i = 0; i < n; ++i) {
    // An invalid sample (the instance lost its writers) still carries the key.
    const auto* status = static_cast<const Wire*>(loans[i]);
    if (status->service_id == nullptr) continue;
    Latest& l = latest[status->service_id];
    l.alive = infos[i].instance_state == DDS_IST_ALIVE;
    if (infos[i].valid_data && status->instance_id != nullptr) {
      l.instance_id = status->instance_id;
      l.life_started_utc_ns = status->life_started_utc_ns;
    }
  }
  if (n > 0) (void)dds_return_loan(heartbeat_reader, loans.data(), n);
  std::vector<ServiceInstance> members;
  for (ServiceInstance& instance : matchedInstances(heartbeat_reader)) {
    if (instance.shard_group != group) continue;
    auto state = latest.find(instance.service_id);
    // Not alive: unless that state is a predecessor's (a daemon restarted under the same
    // service_id is live from its match, as one whose first heartbeat has not arrived).
    const bool predecessors = state != latest.end() && !state->second.instance_id.empty() &&
                              state->second.instance_id != instance.instance_id;
    if (state != latest.end() && !state->second.alive && !predecessors) continue;
    // A shard that began a new life after a stall says so in its heartbeats (its USER_DATA keeps
    // its process's start): it counts as a member that joined then.
    if (state != latest.end() && state->second.instance_id == instance.instance_id &&
        state->second.life_started_utc_ns > instance.started_utc_ns) {
      instance.started_utc_ns = state->second.life_started_utc_ns;
    }
    members.push_back(std::move(instance));
  }
  return members;
}

}  // namespace skyroute::dds
