#include "service/dds/wait_loop.hpp"

#include <algorithm>
#include <array>
#include <chrono>

namespace skyroute::dds {

namespace {
// Attach arguments: index + 1 of a source; these two mark the stop triggers, the third a wake.
constexpr dds_attach_t kGuardArg = -1;
constexpr dds_attach_t kWaitsetArg = -2;
constexpr dds_attach_t kWakeArg = -3;
}  // namespace

Result<WaitLoop> WaitLoop::create(dds_entity_t participant) {
  auto waitset = createWaitset(participant);
  if (!waitset) return waitset.error();
  auto guard = createGuardCondition(participant);
  if (!guard) return guard.error();
  dds_return_t rc = dds_waitset_attach(waitset->get(), guard->get(), kGuardArg);
  if (rc != DDS_RETCODE_OK) return ddsError(rc, "dds_waitset_attach(guard condition)");
  rc = dds_waitset_attach(waitset->get(), waitset->get(), kWaitsetArg);
  if (rc != DDS_RETCODE_OK) return ddsError(rc, "dds_waitset_attach(waitset)");
  auto wake = createGuardCondition(participant);
  if (!wake) return wake.error();
  rc = dds_waitset_attach(waitset->get(), wake->get(), kWakeArg);
  if (rc != DDS_RETCODE_OK) return ddsError(rc, "dds_waitset_attach(wake condition)");
  return WaitLoop(std::move(*waitset), std::move(*guard), std::move(*wake));
}

Status WaitLoop::addSource(dds_entity_t reader, std::function<Status()> take) {
  auto condition = createReadCondition(reader, DDS_ANY_STATE);
  if (!condition) return condition.error();
  auto source = std::make_unique<Source>(Source{std::move(*condition), std::move(take)});
  const dds_return_t rc =
      dds_waitset_attach(waitset_.get(), source->condition.get(), static_cast<dds_attach_t>(sources_.size() + 1));
  if (rc != DDS_RETCODE_OK) return ddsError(rc, "dds_waitset_attach(read condition)");
  sources_.push_back(std::move(source));
  return Status::success();
}

Status WaitLoop::addStatus(dds_entity_t entity, uint32_t mask, std::function<void()> on_change) {
  dds_return_t rc = dds_set_status_mask(entity, mask);
  if (rc != DDS_RETCODE_OK) return ddsError(rc, "dds_set_status_mask");
  auto source = std::make_unique<Source>();
  source->take = [entity, mask, on_change = std::move(on_change)]() {
    uint32_t changed = 0;
    // Taking the status resets it, so the waitset stops reporting it until it changes again.
    const dds_return_t taken = dds_take_status(entity, &changed, mask);
    if (taken != DDS_RETCODE_OK) return Status(ddsError(taken, "dds_take_status"));
    if (changed != 0) on_change();
    return Status::success();
  };
  rc = dds_waitset_attach(waitset_.get(), entity, static_cast<dds_attach_t>(sources_.size() + 1));
  if (rc != DDS_RETCODE_OK) return ddsError(rc, "dds_waitset_attach(status)");
  sources_.push_back(std::move(source));
  return Status::success();
}

void WaitLoop::stop() const { (void)dds_set_guardcondition(guard_.get(), true); }

void WaitLoop::wake() const { (void)dds_set_guardcondition(wake_.get(), true); }

bool WaitLoop::stopRequested() const {
  // The waitset's own trigger (signalStop) cannot be read back; it stays set, so every later
  // wait reports it at once.
  bool guard = false;
  (void)dds_read_guardcondition(guard_.get(), &guard);
  return guard;
}

Result<WaitLoop::Outcome> WaitLoop::runOnce(double timeout_s) {
  std::array<dds_attach_t, 16> triggered{};
  const dds_return_t n = dds_waitset_wait(waitset_.get(), triggered.data(), triggered.size(),
                                          static_cast<dds_duration_t>(timeout_s * 1e9));
  if (n < 0) return ddsError(n, "dds_waitset_wait");
  bool stop_requested = false;
  for (dds_return_t i = 0; i < std::min<dds_return_t>(n, static_cast<dds_return_t>(triggered.size())); ++i) {
    const dds_attach_t arg = triggered[i];
    if (arg == kGuardArg || arg == kWaitsetArg) {
      stop_requested = true;
    } else if (arg == kWakeArg) {
      bool woken = false;
      (void)dds_take_guardcondition(wake_.get(), &woken);  // reset: the next wait waits again
    } else if (arg >= 1 && static_cast<std::size_t>(arg) <= sources_.size()) {
      Status taken = sources_[static_cast<std::size_t>(arg - 1)]->take();
      if (!taken) return taken.error();
    }
  }
  // More conditions than the array holds: they stay triggered and the next wait returns at once.
  if (stop_requested || stopRequested()) return Outcome::kStopped;
  return Outcome::kTimedOut;
}

Result<WaitLoop::Outcome> WaitLoop::run(std::optional<double> timeout_s) {
  using Clock = std::chrono::steady_clock;
  const auto deadline = timeout_s ? Clock::now() + std::chrono::duration_cast<Clock::duration>(
                                                       std::chrono::duration<double>(*timeout_s))
                                  : Clock::time_point::max();
  for (;;) {
    double wait_s = 3600.0;
    if (timeout_s) {
      wait_s = std::chrono::duration<double>(deadline - Clock::now()).count();
      if (wait_s <= 0.0) return Outcome::kTimedOut;
    }
    auto outcome = runOnce(wait_s);
    if (!outcome) return outcome.error();
    if (*outcome == Outcome::kStopped) return Outcome::kStopped;
  }
}

}  // namespace skyroute::dds
