#include "service/dds/shard_members.hpp"

#include <array>
#include <map>

#include "service/dds/topics.hpp"

namespace skyroute::dds {

std::vector<ServiceInstance> liveShardMembers(dds_entity_t heartbeat_reader, const std::string& group) {
  using Wire = TopicTraits<ServiceStatusData>::Wire;
  std::map<std::string, bool> alive;  // service_id -> its heartbeat instance is alive
  constexpr std::size_t kBatch = 256;
  std::array<void*, kBatch> loans{};
  std::array<dds_sample_info_t, kBatch> infos{};
  const dds_return_t n = dds_read(heartbeat_reader, loans.data(), infos.data(), kBatch, kBatch);
  for (dds_return_t i = 0; i < n; ++i) {
    // An invalid sample (the instance lost its writers) still carries the key.
    const auto* status = static_cast<const Wire*>(loans[i]);
    if (status->service_id == nullptr) continue;
    alive[status->service_id] = infos[i].instance_state == DDS_IST_ALIVE;
  }
  if (n > 0) (void)dds_return_loan(heartbeat_reader, loans.data(), n);
  std::vector<ServiceInstance> members;
  for (ServiceInstance& instance : matchedInstances(heartbeat_reader)) {
    if (instance.shard_group != group) continue;
    auto state = alive.find(instance.service_id);
    if (state != alive.end() && !state->second) continue;
    members.push_back(std::move(instance));
  }
  return members;
}

}  // namespace skyroute::dds
