#include "service/dds/daemon_participants.hpp"

#include <algorithm>
#include <map>
#include <optional>
#include <vector>

#include "service/dds/dds_entities.hpp"
#include "service/dds/service_instance.hpp"
#include "service/dds/typed_io.hpp"

namespace skyroute::dds {

std::vector<DaemonParticipant> daemonParticipants(dds_entity_t participant_reader, dds_entity_t heartbeat_reader) {
  std::map<std::string, std::string> guid_of;  // instance id -> GUID
  // Room for every participant a host's loopback configuration allows (121) and more: a daemon left
  // out would be a daemon not waited for.
  constexpr std::size_t kMost = 512;
  std::vector<void*> loans(kMost, nullptr);
  std::vector<dds_sample_info_t> infos(kMost);
  // Read, not take: the reader keeps every participant's latest state.
  const dds_return_t n = dds_read(participant_reader, loans.data(), infos.data(), kMost, kMost);
  for (dds_return_t i = 0; i < n; ++i) {
    if (!infos[i].valid_data || infos[i].instance_state != DDS_IST_ALIVE) continue;
    const auto* participant = static_cast<const dds_builtintopic_participant_t*>(loans[i]);
    if (auto instance = announcedInstance(participant->qos)) guid_of[instance->instance_id] = guidText(participant->key);
  }
  if (n > 0) (void)dds_return_loan(participant_reader, loans.data(), n);
  std::vector<dds_instance_handle_t> handles(kMost);
  const dds_return_t m = dds_get_matched_publications(heartbeat_reader, handles.data(), handles.size());
  for (dds_return_t i = 0; i < std::min<dds_return_t>(m, static_cast<dds_return_t>(handles.size())); ++i) {
    const Endpoint writer = matchedPublication(heartbeat_reader, handles[static_cast<std::size_t>(i)]);
    if (!writer) continue;
    if (auto instance = announcedInstance(writer->qos)) guid_of.emplace(instance->instance_id, guidText(writer->key));
  }
  std::vector<DaemonParticipant> out;
  for (auto& [instance, guid] : guid_of) out.push_back(DaemonParticipant{instance, guid});
  return out;
}

}  // namespace skyroute::dds
