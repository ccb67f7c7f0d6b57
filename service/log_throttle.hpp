// Repeated warnings, rate-limited per key (e.g. vehicle and reason): the first occurrence is
// logged at once; repeats are only counted, and at the end of each window in which there were
// some, one line reports them: "<last message> (repeated 212 times in 10 s)". A window without a
// repeat ends the key's throttling (its next occurrence is logged at once again). So a vehicle
// blocked for a minute logs a handful of lines, not one per replanning cycle. Thread-safe; at most
// max_keys keys are tracked (the oldest is reported and dropped first).
#pragma once

#include <chrono>
#include <cstddef>
#include <map>
#include <mutex>
#include <string>

namespace skyroute {

class LogThrottle {
 public:
  using Clock = std::chrono::steady_clock;

  explicit LogThrottle(double window_s = 10.0, std::size_t max_keys = 4096);

  // Logs `message` at warn level, or counts it when `key` was logged less than a window ago.
  void warn(const std::string& key, const std::string& message, Clock::time_point now = Clock::now());
  // Reports and forgets the keys whose window has passed with repeats in it; call it regularly.
  void flush(Clock::time_point now = Clock::now());
  // Reports every window with repeats, ended or not (at shutdown).
  void flushAll();

  double windowS() const;
  void setWindowS(double window_s);

 private:
  struct Entry {
    Clock::time_point window_start;
    std::size_t repeats = 0;
    std::string last_message;
  };
  // Logs the window's summary if it had repeats (caller holds the lock).
  void report(const Entry& entry) const;

  double window_s_;  // under mutex_
  std::size_t max_keys_;
  mutable std::mutex mutex_;
  std::map<std::string, Entry> entries_;
};

}  // namespace skyroute
