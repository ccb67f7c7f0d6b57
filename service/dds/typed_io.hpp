// Typed writers and readers: each owns its topic and its DDS writer or reader, uses the topic's
// QoS (topics.hpp), and converts plain messages at the boundary (conversions.hpp).
#pragma once

#include <array>
#include <cstdint>
#include <functional>
#include <utility>
#include <vector>

#include "service/dds/dds_entities.hpp"
#include "service/dds/topics.hpp"

namespace skyroute::dds {

// Blocks until the writer matches at least `count` readers (or the reader `count` writers).
Status waitForPublicationMatched(dds_entity_t writer, uint32_t count, double timeout_s);
Status waitForSubscriptionMatched(dds_entity_t reader, uint32_t count, double timeout_s);

template <class Plain>
class Writer {
 public:
  using Traits = TopicTraits<Plain>;

  static Result<Writer> create(dds_entity_t participant) {
    Qos qos = Traits::qos();
    auto topic = createTopic(participant, Traits::descriptor(), Traits::kName, qos.get());
    if (!topic) return topic.error();
    auto writer = createWriter(participant, topic->get(), qos.get());
    if (!writer) return writer.error();
    return Writer(std::move(*topic), std::move(*writer));
  }

  Status write(const Plain& message) const {
    WireSample<typename Traits::Wire> sample(Traits::descriptor());
    toWire(message, sample.msg());
    const dds_return_t rc = dds_write(writer_.get(), &sample.msg());
    if (rc != DDS_RETCODE_OK) return ddsError(rc, std::string("dds_write on ") + Traits::kName);
    return Status::success();
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
  Entity topic_;   // declared first: destroyed after the writer
  Entity writer_;
};

template <class Plain>
class Reader {
 public:
  using Traits = TopicTraits<Plain>;
  using SampleHandler = std::function<void(Plain&&)>;
  using ErrorHandler = std::function<void(const Error&)>;

  static Result<Reader> create(dds_entity_t participant) {
    Qos qos = Traits::qos();
    auto topic = createTopic(participant, Traits::descriptor(), Traits::kName, qos.get());
    if (!topic) return topic.error();
    auto reader = createReader(participant, topic->get(), qos.get());
    if (!reader) return reader.error();
    return Reader(std::move(*topic), std::move(*reader));
  }

  // Takes everything available; each valid sample is converted and passed to on_sample, each
  // sample that fails validation to on_error (the loop goes on). Returns the number taken, or
  // the DDS error. Handlers run after the loan is returned, on the caller's thread.
  Result<std::size_t> takeAvailable(const SampleHandler& on_sample, const ErrorHandler& on_error) const {
    constexpr std::size_t kBatch = 32;
    std::size_t total = 0;
    for (;;) {
      std::array<void*, kBatch> loans{};
      std::array<dds_sample_info_t, kBatch> infos{};
      const dds_return_t n = dds_take(reader_.get(), loans.data(), infos.data(), kBatch, kBatch);
      if (n < 0) return ddsError(n, std::string("dds_take on ") + Traits::kName);
      if (n == 0) return total;
      std::vector<Result<Plain>> converted;
      converted.reserve(static_cast<std::size_t>(n));
      for (dds_return_t i = 0; i < n; ++i)
        if (infos[i].valid_data) converted.push_back(fromWire(*static_cast<const typename Traits::Wire*>(loans[i])));
      const dds_return_t rc = dds_return_loan(reader_.get(), loans.data(), n);
      if (rc != DDS_RETCODE_OK) return ddsError(rc, std::string("dds_return_loan on ") + Traits::kName);
      for (auto& result : converted) {
        if (result.ok()) {
          on_sample(std::move(result).value());
        } else if (on_error) {
          on_error(result.error());
        }
      }
      total += static_cast<std::size_t>(n);
      if (static_cast<std::size_t>(n) < kBatch) return total;
    }
  }

  Status waitForWriters(uint32_t count, double timeout_s) const {
    return waitForSubscriptionMatched(reader_.get(), count, timeout_s);
  }
  dds_entity_t handle() const { return reader_.get(); }

 private:
  Reader(Entity topic, Entity reader) : topic_(std::move(topic)), reader_(std::move(reader)) {}
  Entity topic_;
  Entity reader_;
};

}  // namespace skyroute::dds
