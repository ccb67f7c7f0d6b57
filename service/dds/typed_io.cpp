#include "service/dds/typed_io.hpp"

#include <chrono>

namespace skyroute::dds {

namespace {

// Waits on a private waitset for the entity's matched status to reach `count` current matches.
template <class GetCount>
Status waitForMatched(dds_entity_t entity, uint32_t status_mask, uint32_t count, double timeout_s,
                      const char* what, GetCount get_count) {
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
    uint32_t current = 0;
    rc = get_count(entity, &current);
    if (rc != DDS_RETCODE_OK) return ddsError(rc, what);
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

}  // namespace

Status waitForPublicationMatched(dds_entity_t writer, uint32_t count, double timeout_s) {
  return waitForMatched(writer, DDS_PUBLICATION_MATCHED_STATUS, count, timeout_s, "publication matched",
                        [](dds_entity_t w, uint32_t* current) {
                          dds_publication_matched_status_t status;
                          const dds_return_t rc = dds_get_publication_matched_status(w, &status);
                          *current = status.current_count;
                          return rc;
                        });
}

Status waitForSubscriptionMatched(dds_entity_t reader, uint32_t count, double timeout_s) {
  return waitForMatched(reader, DDS_SUBSCRIPTION_MATCHED_STATUS, count, timeout_s, "subscription matched",
                        [](dds_entity_t r, uint32_t* current) {
                          dds_subscription_matched_status_t status;
                          const dds_return_t rc = dds_get_subscription_matched_status(r, &status);
                          *current = status.current_count;
                          return rc;
                        });
}

uint32_t matchedReaders(dds_entity_t writer) {
  dds_publication_matched_status_t status{};
  return dds_get_publication_matched_status(writer, &status) == DDS_RETCODE_OK ? status.current_count : 0;
}

uint32_t matchedWriters(dds_entity_t reader) {
  dds_subscription_matched_status_t status{};
  return dds_get_subscription_matched_status(reader, &status) == DDS_RETCODE_OK ? status.current_count : 0;
}

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

std::string remoteWriterGuid(dds_entity_t reader, dds_instance_handle_t publication) {
  const Endpoint endpoint = matchedPublication(reader, publication);
  return endpoint ? guidText(endpoint->key) : "";
}

}  // namespace skyroute::dds
