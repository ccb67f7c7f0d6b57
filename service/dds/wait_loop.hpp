// A waitset that dispatches samples of several typed readers on the calling thread (never in
// Cyclone's listener threads), until stop() triggers its guard condition or a deadline passes.
// stop() and wake() (ends the current wait early, once) may be called from any thread. From a
// signal handler, call signalStop() with the handle from waitsetHandle(): it only triggers the
// waitset (as the Cyclone examples do).
#pragma once

#include <functional>
#include <memory>
#include <optional>
#include <vector>

#include "service/dds/typed_io.hpp"

namespace skyroute::dds {

class WaitLoop {
 public:
  enum class Outcome { kStopped, kTimedOut };

  static Result<WaitLoop> create(dds_entity_t participant);

  // Adds a reader: whenever it has data, its samples go to on_sample and bad ones to on_error.
  // The reader must outlive the loop.
  template <class Plain>
  Status add(const Reader<Plain>& reader, typename Reader<Plain>::SampleHandler on_sample,
             typename Reader<Plain>::ErrorHandler on_error) {
    return addTaking(reader.handle(), [&reader, on_sample = std::move(on_sample), on_error = std::move(on_error)] {
      return reader.takeAvailable(on_sample, on_error);
    });
  }

  // The same, with rejected samples passed with their identity (Reader::takeAvailableWithRejects).
  template <class Plain>
  Status addWithRejects(const Reader<Plain>& reader, typename Reader<Plain>::SampleHandler on_sample,
                        typename Reader<Plain>::RejectHandler on_reject) {
    return addTaking(reader.handle(), [&reader, on_sample = std::move(on_sample), on_reject = std::move(on_reject)] {
      return reader.takeAvailableWithRejects(on_sample, on_reject);
    });
  }

  // Calls on_change whenever one of the `mask` statuses of `entity` changes (e.g. a reader's
  // DDS_SUBSCRIPTION_MATCHED_STATUS: a writer appeared or went away). The entity must outlive the loop.
  Status addStatus(dds_entity_t entity, uint32_t mask, std::function<void()> on_change);

  // Dispatches until stop() (kStopped) or until timeout_s passes (kTimedOut; nullopt = forever).
  Result<Outcome> run(std::optional<double> timeout_s = std::nullopt);
  // One wait of at most timeout_s, dispatching what arrived; kStopped if a stop was requested.
  Result<Outcome> runOnce(double timeout_s);

  void stop() const;  // thread-safe
  void wake() const;  // thread-safe: the current (or next) wait returns at once, kTimedOut
  bool stopRequested() const;
  dds_entity_t waitsetHandle() const { return waitset_.get(); }
  static void signalStop(dds_entity_t waitset) { (void)dds_waitset_set_trigger(waitset, true); }

 private:
  WaitLoop(Entity waitset, Entity guard, Entity wake)
      : waitset_(std::move(waitset)), guard_(std::move(guard)), wake_(std::move(wake)) {}
  Status addSource(dds_entity_t reader, std::function<Status()> take);

  // A reader source whose take returns the number of samples taken or the error.
  template <class Take>
  Status addTaking(dds_entity_t reader, Take take) {
    return addSource(reader, [take = std::move(take)]() {
      auto taken = take();
      if (!taken) return Status(taken.error());
      return Status::success();
    });
  }

  struct Source {
    Entity condition;  // a read condition; empty for a status source (the entity is attached)
    std::function<Status()> take;
  };
  Entity waitset_;
  Entity guard_;
  Entity wake_;
  std::vector<std::unique_ptr<Source>> sources_;
};

}  // namespace skyroute::dds
