#include "service/dds/typed_io.hpp"

#include <chrono>

#include "service/dds/service_instance.hpp"

namespace skyroute::dds {

namespace {

// dds_get_publication_matched_status or dds_get_subscription_matched_status.
template <class MatchedStatus>
using GetMatchedStatus = dds_return_t (*)(dds_entity_t, MatchedStatus*);

// Waits on a private waitset for the entity's matched status to reach `count` current matches.
template <class MatchedStatus>
Status waitForMatched(dds_entity_t entity, uint32_t status_mask, GetMatchedStatus<MatchedStatus> get_status,
                      uint32_t count, double timeout_s, const char* what) {
  dds_return_t rc = dds_set_status_mask(entity, status_mask);
  if (rc != DDS_RETCODE_OK) return ddsError(rc, "dds_set_status_mask");
  const dds_entity_t participant = dds_get_participant(entity);
  if (participant < 0) return ddsError(participant, "dds_get_participant");
  auto waitset = createWaitset(participant);
  if (!waitset) return waitset.error();
  rc = dds_waitset_attach(waitset->get(), entity, entity);
  if (rc != DDS_RETCODE_OK) return ddsError(rc, "dds_waitset_attach");

  const auto deadline = std::chrono::steady_clock::now() + std::chrono::duration<double>(timeout_s);
  for (;;) {
    MatchedStatus status{};
    rc = get_status(entity, &status);
    if (rc != DDS_RETCODE_OK) return ddsError(rc, what);
    const uint32_t current = status.current_count;
    if (current >= count) return Status::success();
    const auto left = std::chrono::duration_cast<std::chrono::nanoseconds>(deadline - std::chrono::steady_clock::now());
    if (left.count() <= 0)
      return make_error(ErrorCode::kTimeout, what,
                        std::string(what) + ": " + std::to_string(current) + " of " + std::to_string(count) +
                            " matches after " + std::to_string(timeout_s) + " s");
    rc = dds_waitset_wait(waitset->get(), nullptr, 0, left.count());
    if (rc < 0) return ddsError(rc, "dds_waitset_wait");
  }
}

// The current match count; 0 when it cannot be read.
template <class MatchedStatus>
uint32_t currentMatches(dds_entity_t entity, GetMatchedStatus<MatchedStatus> get_status) {
  MatchedStatus status{};
  return get_status(entity, &status) == DDS_RETCODE_OK ? status.current_count : 0;
}

}  // namespace

Status waitForPublicationMatched(dds_entity_t writer, uint32_t count, double timeout_s) {
  return waitForMatched(writer, DDS_PUBLICATION_MATCHED_STATUS, dds_get_publication_matched_status, count, timeout_s,
                        "publication matched");
}

Status waitForSubscriptionMatched(dds_entity_t reader, uint32_t count, double timeout_s) {
  return waitForMatched(reader, DDS_SUBSCRIPTION_MATCHED_STATUS, dds_get_subscription_matched_status, count,
                        timeout_s, "subscription matched");
}

uint32_t matchedReaders(dds_entity_t writer) { return currentMatches(writer, dds_get_publication_matched_status); }

uint32_t matchedWriters(dds_entity_t reader) { return currentMatches(reader, dds_get_subscription_matched_status); }

std::string guidText(const dds_guid_t& guid) {
  static constexpr char kHex[] = "0123456789abcdef";
  std::string out;
  out.reserve(32);
  for (uint8_t byte : guid.v) {
    out.push_back(kHex[byte >> 4]);
    out.push_back(kHex[byte & 0xf]);
  }
  return out;
}

std::string entityGuid(dds_entity_t entity) {
  dds_guid_t guid{};
  if (dds_get_guid(entity, &guid) != DDS_RETCODE_OK) return "";
  return guidText(guid);
}

bool reachesParticipantOf(dds_entity_t writer, const std::string& endpoint_guid) {
  constexpr std::size_t kPrefixDigits = 24;  // 12 bytes of GUID prefix
  if (endpoint_guid.size() != 32) return false;
  std::vector<dds_instance_handle_t> handles(16);
  for (;;) {
    const dds_return_t n = dds_get_matched_subscriptions(writer, handles.data(), handles.size());
    if (n < 0) return false;
    // More matches than room: only the first handles.size() were filled; ask again with room.
    if (static_cast<std::size_t>(n) > handles.size()) {
      handles.resize(static_cast<std::size_t>(n));
      continue;
    }
    for (dds_return_t i = 0; i < n; ++i) {
      const Endpoint reader(dds_get_matched_subscription_data(writer, handles[static_cast<std::size_t>(i)]));
      if (reader && guidText(reader->participant_key).compare(0, kPrefixDigits, endpoint_guid, 0, kPrefixDigits) == 0)
        return true;
    }
    return false;
  }
}

std::string remoteWriterGuid(dds_entity_t reader, dds_instance_handle_t publication) {
  const Endpoint endpoint = matchedPublication(reader, publication);
  return endpoint ? guidText(endpoint->key) : "";
}

std::pair<std::string, std::string> remoteWriterSource(dds_entity_t reader, dds_instance_handle_t publication) {
  const Endpoint endpoint = matchedPublication(reader, publication);
  if (!endpoint || endpoint->qos == nullptr) return {};
  void* value = nullptr;
  std::size_t size = 0;
  if (!dds_qget_userdata(endpoint->qos, &value, &size) || value == nullptr) return {};
  const auto instance = ServiceInstance::fromUserData(std::string_view(static_cast<const char*>(value), size));
  dds_free(value);
  if (!instance) return {};
  return {instance->instance_id, instance->role};
}

}  // namespace skyroute::dds
