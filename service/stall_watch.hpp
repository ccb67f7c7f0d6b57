// Notices when this process did not run for a while: SIGSTOP, a paused virtual machine, a host
// swapping or starved. A thread of its own does nothing but sleep a short tick and measure, on
// the monotonic clock, how long it really slept; a gap longer than the threshold is a stall.
// DDS liveliness runs in the same process, so a stall longer than the liveliness lease is one the
// other daemons may have taken for a death (docs/dds.md "Shards", "A paused shard").
//
// Callers that must not act on what they knew before a stall ask suspect() before they act (a
// stall was noticed and not taken yet, or the watch itself is overdue now: the process may have
// woken a moment before its watch did), and take() the stall once they have dealt with it.
// Thread-safe.
#pragma once

#include <condition_variable>
#include <cstdint>
#include <functional>
#include <mutex>
#include <optional>
#include <thread>

namespace skyroute {

class StallWatch {
 public:
  using MonotonicNs = std::function<std::int64_t()>;

  // threshold_s > 0: a gap longer than it is a stall; the watch ticks four times per threshold.
  // on_stall (optional) is called from the watch's thread when it notices one, e.g. to wake the
  // thread that deals with it. `now_ns` is the monotonic clock (tests give their own).
  explicit StallWatch(double threshold_s, std::function<void()> on_stall = {}, MonotonicNs now_ns = steadyNowNs);
  ~StallWatch();
  StallWatch(const StallWatch&) = delete;
  StallWatch& operator=(const StallWatch&) = delete;

  void start();  // starts the thread (the gap counts from now)
  void stop();   // joins it; the watch can be started again

  // A stall noticed and not yet taken, or the watch overdue now by more than the threshold.
  bool suspect() const;
  // The longest gap since the last take(), in seconds, when it was a stall (or the watch is
  // overdue now); afterwards suspect() is false until the next stall.
  std::optional<double> take();

  double thresholdS() const;
  void setThresholdS(double threshold_s);  // e.g. after a reload changed the lease
  // Tests without the thread: one tick at the clock's time now.
  void tickForTest() { tick(); }

  static std::int64_t steadyNowNs();

 private:
  void run();
  void tick();
  // The gap since the last tick, folded into stall_ns_ when it is one (caller holds mutex_).
  void measureLocked(std::int64_t now_ns);

  std::int64_t threshold_ns_;  // under mutex_
  const std::function<void()> on_stall_;
  const MonotonicNs now_ns_;
  mutable std::mutex mutex_;
  std::condition_variable wake_;
  std::int64_t last_tick_ns_ = 0;
  std::int64_t stall_ns_ = 0;  // the longest gap not yet taken; 0 = none
  bool stopping_ = false;
  std::thread thread_;
};

}  // namespace skyroute
