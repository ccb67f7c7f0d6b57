// Typed writers and readers: each owns its topic and its DDS writer or reader, uses the topic's
// QoS (topics.hpp), and converts plain messages at the boundary (conversions.hpp).
#pragma once

#include <array>
#include <cstdint>
#include <functional>
#include <optional>
#include <string>
#include <tuple>
#include <type_traits>
#include <utility>
#include <vector>

#include "service/dds/dds_entities.hpp"
#include "service/dds/topics.hpp"

namespace skyroute::dds {

// Blocks until the writer matches at least `count` readers (or the reader `count` writers).
Status waitForPublicationMatched(dds_entity_t writer, uint32_t count, double timeout_s);
Status waitForSubscriptionMatched(dds_entity_t reader, uint32_t count, double timeout_s);
uint32_t matchedReaders(dds_entity_t writer);  // current matches (0 on a DDS error)
uint32_t matchedWriters(dds_entity_t reader);

// A GUID as 32 lower-case hex digits: the form messages carry (PlanStatus.requester).
std::string guidText(const dds_guid_t& guid);
// The GUID of one of this process's entities ("" on a DDS error).
std::string entityGuid(dds_entity_t entity);
// Whether `writer` has matched a reader of the participant that owns the endpoint `endpoint_guid`
// (32 hex digits, as guidText writes them; a participant is its GUID's first 12 bytes).
bool reachesParticipantOf(dds_entity_t writer, const std::string& endpoint_guid);
// The GUID of the remote writer a sample came from (its sample info's publication handle); ""
// when it is no longer matched.
std::string remoteWriterGuid(dds_entity_t reader, dds_instance_handle_t publication);

// Requests, whose `requester` the reader fills from the sample's writer, so the service can
// address its answers to that client alone. (A status's requester is what the service wrote.)
template <class Plain>
inline constexpr bool kStampsRequester =
    std::is_same_v<Plain, MissionRequestData> || std::is_same_v<Plain, CancelRequestData>;

// Trajectories, whose source_instance and source_role the reader fills with the daemon behind the sample's writer, so a
// ground station can show which daemon (primary or standby) it follows.
template <class Plain>
inline constexpr bool kStampsSource = std::is_same_v<Plain, TrajectoryData>;
// The instance id and role of the daemon behind the remote writer `publication`, from its
// USER_DATA (service_instance.hpp); empty when it has none or is no longer matched.
std::pair<std::string, std::string> remoteWriterSource(dds_entity_t reader, dds_instance_handle_t publication);

template <class Plain>
class Writer {
 public:
  using Traits = TopicTraits<Plain>;

  // user_data: the writer's USER_DATA QoS, which every matched reader can read at discovery,
  // before any sample (the daemon's writers name its instance there). owned: the strength and
  // liveliness lease of a daemon's writer of an owned topic (qos.hpp).
  static Result<Writer> create(dds_entity_t participant, const std::string& user_data = "",
                               const std::optional<OwnedWriterOptions>& owned = std::nullopt) {
    Qos qos = Traits::qos();
    if (!user_data.empty()) dds_qset_userdata(qos.get(), user_data.data(), user_data.size());
    auto topic = createTopic(participant, Traits::descriptor(), Traits::kName, qos.get());
    if (!topic) return topic.error();
    if (owned) applyOwnedWriterQos(qos.get(), *owned);
    auto writer = createWriter(participant, topic->get(), qos.get());
    if (!writer) return writer.error();
    return Writer(std::move(*topic), std::move(*writer));
  }

  Status write(const Plain& message) const { return send(dds_write, "dds_write on ", message); }

  // Tells readers the instance with this message's key is gone (transient-local history drops it).
  Status dispose(const Plain& key_holder) const { return send(dds_dispose, "dds_dispose on ", key_holder); }

  // This writer lets go of the instance with this message's key without disposing it: readers
  // keep its last sample, and another writer of equal strength can own it at once (a reader hands
  // an instance between equal writers only when its owner is gone or unregistered).
  Status unregisterInstance(const Plain& key_holder) const {
    return send(dds_unregister_instance, "dds_unregister_instance on ", key_holder);
  }

  // Waits until every matched reliable reader acknowledged what was written.
  Status waitForAcks(double timeout_s) const {
    const dds_return_t rc = dds_wait_for_acks(writer_.get(), static_cast<dds_duration_t>(timeout_s * 1e9));
    if (rc != DDS_RETCODE_OK) return ddsError(rc, std::string("dds_wait_for_acks on ") + Traits::kName);
    return Status::success();
  }
  Status waitForReaders(uint32_t count, double timeout_s) const {
    return waitForPublicationMatched(writer_.get(), count, timeout_s);
  }
  dds_entity_t handle() const { return writer_.get(); }

 private:
  Writer(Entity topic, Entity writer) : topic_(std::move(topic)), writer_(std::move(writer)) {}

  // Converts the message and hands it to dds_write or dds_dispose.
  Status send(dds_return_t (*dds_send)(dds_entity_t, const void*), const char* what, const Plain& message) const {
    WireSample<typename Traits::Wire> sample(Traits::descriptor());
    toWire(message, sample.msg());
    const dds_return_t rc = dds_send(writer_.get(), &sample.msg());
    if (rc != DDS_RETCODE_OK) return ddsError(rc, what + std::string(Traits::kName));
    return Status::success();
  }

  Entity topic_;   // declared first: destroyed after the writer
  Entity writer_;
};

template <class Plain>
class Reader {
 public:
  using Traits = TopicTraits<Plain>;
  using SampleHandler = std::function<void(Plain&&)>;
  using ErrorHandler = std::function<void(const Error&)>;
  // A sample that failed validation, with what identifies its sender (identityFromWire), so the
  // service can answer it (a request with a NaN still gets a status naming the field).
  using RejectHandler = std::function<void(const Error&, const Plain& identity)>;

  // ignore_own_participant: the reader is not matched with the writers of its own participant
  // (a daemon that follows what the others publish, not its own samples).
  static Result<Reader> create(dds_entity_t participant, bool ignore_own_participant = false) {
    Qos qos = Traits::qos();
    auto topic = createTopic(participant, Traits::descriptor(), Traits::kName, qos.get());
    if (!topic) return topic.error();
    if (ignore_own_participant) dds_qset_ignorelocal(qos.get(), DDS_IGNORELOCAL_PARTICIPANT);
    auto reader = createReader(participant, topic->get(), qos.get());
    if (!reader) return reader.error();
    return Reader(std::move(*topic), std::move(*reader));
  }

  // Takes what is available, at most 256 samples a call; each valid sample is converted and
  // passed to on_sample, each sample that fails validation to on_error (the loop goes on).
  // Returns the number taken, or the DDS error. Handlers run after the loan is returned, on the
  // caller's thread.
  Result<std::size_t> takeAvailable(const SampleHandler& on_sample, const ErrorHandler& on_error) const {
    return take<false>(on_sample, [&](const Error& e, const Plain*) {
      if (on_error) on_error(e);
    });
  }
  // The same, passing each rejected sample's identity to on_reject.
  Result<std::size_t> takeAvailableWithRejects(const SampleHandler& on_sample, const RejectHandler& on_reject) const {
    return take<true>(on_sample, [&](const Error& e, const Plain* identity) { on_reject(e, *identity); });
  }

  Status waitForWriters(uint32_t count, double timeout_s) const {
    return waitForSubscriptionMatched(reader_.get(), count, timeout_s);
  }
  dds_entity_t handle() const { return reader_.get(); }

 private:
  Reader(Entity topic, Entity reader) : topic_(std::move(topic)), reader_(std::move(reader)) {}

  template <bool kWithIdentity, class OnFailure>
  Result<std::size_t> take(const SampleHandler& on_sample, const OnFailure& on_failure) const {
    constexpr std::size_t kBatch = 32;
    // At most this many per call: under a flood the reader never empties, and the thread that
    // takes also has other work (the daemon's heartbeat). What is left keeps the read condition
    // triggered, so the next wait returns at once.
    constexpr std::size_t kMaxPerCall = 8 * kBatch;
    std::size_t total = 0;
    for (;;) {
      std::array<void*, kBatch> loans{};
      std::array<dds_sample_info_t, kBatch> infos{};
      const dds_return_t n = dds_take(reader_.get(), loans.data(), infos.data(), kBatch, kBatch);
      if (n < 0) return ddsError(n, std::string("dds_take on ") + Traits::kName);
      if (n == 0) return total;
      std::vector<std::pair<Result<Plain>, Plain>> converted;
      converted.reserve(static_cast<std::size_t>(n));
      for (dds_return_t i = 0; i < n; ++i) {
        if (!infos[i].valid_data) continue;
        const auto& wire = *static_cast<const typename Traits::Wire*>(loans[i]);
        Result<Plain> result = fromWire(wire);
        Plain identity{};
        if constexpr (kWithIdentity) {
          if (!result.ok()) identity = identityFromWire(wire);
        }
        if constexpr (kStampsRequester<Plain>) {
          const std::string sender = remoteWriterGuid(reader_.get(), infos[i].publication_handle);
          if (result.ok()) result.value().requester = sender;
          identity.requester = sender;
        }
        if constexpr (kStampsSource<Plain>) {
          if (result.ok()) {
            std::tie(result.value().source_instance, result.value().source_role) =
                remoteWriterSource(reader_.get(), infos[i].publication_handle);
          }
        }
        converted.emplace_back(std::move(result), std::move(identity));
      }
      // Handlers run after the loan is returned, so a slow handler never holds the reader's memory.
      const dds_return_t rc = dds_return_loan(reader_.get(), loans.data(), n);
      if (rc != DDS_RETCODE_OK) return ddsError(rc, std::string("dds_return_loan on ") + Traits::kName);
      for (auto& [result, identity] : converted) {
        if (result.ok()) {
          on_sample(std::move(result).value());
        } else {
          on_failure(result.error(), &identity);
        }
      }
      total += static_cast<std::size_t>(n);
      if (static_cast<std::size_t>(n) < kBatch || total >= kMaxPerCall) return total;
    }
  }

  Entity topic_;
  Entity reader_;
};

}  // namespace skyroute::dds
