#include "service/stall_watch.hpp"

#include <algorithm>
#include <chrono>

namespace skyroute {

std::int64_t StallWatch::steadyNowNs() {
  return std::chrono::duration_cast<std::chrono::nanoseconds>(std::chrono::steady_clock::now().time_since_epoch())
      .count();
}

namespace {

std::int64_t toNs(double seconds) { return std::max<std::int64_t>(1, static_cast<std::int64_t>(seconds * 1e9)); }

}  // namespace

StallWatch::StallWatch(double threshold_s, std::function<void()> on_stall, MonotonicNs now_ns)
    : threshold_ns_(toNs(threshold_s)),
      on_stall_(std::move(on_stall)),
      now_ns_(std::move(now_ns)),
      last_tick_ns_(now_ns_()) {}

StallWatch::~StallWatch() { stop(); }

void StallWatch::start() {
  stop();
  std::lock_guard lock(mutex_);
  stopping_ = false;
  last_tick_ns_ = now_ns_();
  thread_ = std::thread([this] { run(); });
}

void StallWatch::stop() {
  {
    std::lock_guard lock(mutex_);
    if (!thread_.joinable()) return;
    stopping_ = true;
  }
  wake_.notify_all();
  thread_.join();
}

double StallWatch::thresholdS() const {
  std::lock_guard lock(mutex_);
  return static_cast<double>(threshold_ns_) * 1e-9;
}

void StallWatch::setThresholdS(double threshold_s) {
  std::lock_guard lock(mutex_);
  threshold_ns_ = toNs(threshold_s);
}

void StallWatch::run() {
  std::unique_lock lock(mutex_);
  while (!stopping_) {
    // Four ticks per threshold: a tick is taken for a stall only when it comes more than three
    // quarters of the threshold late.
    const auto tick_period = std::chrono::nanoseconds(std::max<std::int64_t>(1, threshold_ns_ / 4));
    wake_.wait_for(lock, tick_period, [this] { return stopping_; });
    if (stopping_) break;
    lock.unlock();
    tick();
    lock.lock();
  }
}

void StallWatch::tick() {
  bool stalled = false;
  {
    std::lock_guard lock(mutex_);
    const std::int64_t before = stall_ns_;
    const std::int64_t now = now_ns_();
    measureLocked(now);
    last_tick_ns_ = now;
    stalled = stall_ns_ != before;
  }
  if (stalled && on_stall_) on_stall_();
}

void StallWatch::measureLocked(std::int64_t now_ns) {
  const std::int64_t gap_ns = now_ns - last_tick_ns_;
  if (gap_ns > threshold_ns_) stall_ns_ = std::max(stall_ns_, gap_ns);
}

bool StallWatch::suspect() const {
  std::lock_guard lock(mutex_);
  return stall_ns_ > 0 || now_ns_() - last_tick_ns_ > threshold_ns_;
}

std::optional<double> StallWatch::take() {
  std::lock_guard lock(mutex_);
  const std::int64_t now = now_ns_();
  measureLocked(now);
  // The gap is taken: the watch's next tick measures from here, not from before the stall.
  last_tick_ns_ = std::max(last_tick_ns_, now);
  const std::int64_t stall_ns = stall_ns_;
  stall_ns_ = 0;
  if (stall_ns == 0) return std::nullopt;
  return static_cast<double>(stall_ns) * 1e-9;
}

}  // namespace skyroute
