#include "service/log_throttle.hpp"

#include <algorithm>

#include <spdlog/spdlog.h>

#include "service/number_text.hpp"

namespace skyroute {

LogThrottle::LogThrottle(double window_s, std::size_t max_keys) : window_s_(window_s), max_keys_(std::max<std::size_t>(1, max_keys)) {}

double LogThrottle::windowS() const {
  std::lock_guard lock(mutex_);
  return window_s_;
}

void LogThrottle::setWindowS(double window_s) {
  std::lock_guard lock(mutex_);
  window_s_ = window_s;
}

void LogThrottle::report(const Entry& entry) const {
  if (entry.repeats == 0) return;
  spdlog::warn("{} (repeated {} times in {} s)", entry.last_message, entry.repeats, numberText(window_s_));
}

void LogThrottle::warn(const std::string& key, const std::string& message, Clock::time_point now) {
  std::lock_guard lock(mutex_);
  const auto window = std::chrono::duration_cast<Clock::duration>(std::chrono::duration<double>(window_s_));
  if (auto it = entries_.find(key); it != entries_.end()) {
    Entry& entry = it->second;
    ++entry.repeats;
    entry.last_message = message;
    if (now - entry.window_start >= window) {
      report(entry);
      entry.window_start = now;
      entry.repeats = 0;
    }
    return;
  }
  if (entries_.size() >= max_keys_) {
    auto oldest = std::min_element(entries_.begin(), entries_.end(), [](const auto& a, const auto& b) {
      return a.second.window_start < b.second.window_start;
    });
    report(oldest->second);
    entries_.erase(oldest);
  }
  spdlog::warn("{}", message);
  entries_.emplace(key, Entry{now, 0, message});
}

void LogThrottle::flush(Clock::time_point now) {
  std::lock_guard lock(mutex_);
  const auto window = std::chrono::duration_cast<Clock::duration>(std::chrono::duration<double>(window_s_));
  for (auto it = entries_.begin(); it != entries_.end();) {
    Entry& entry = it->second;
    if (now - entry.window_start < window) {
      ++it;
    } else if (entry.repeats > 0) {
      report(entry);
      entry.window_start = now;
      entry.repeats = 0;
      ++it;
    } else {
      it = entries_.erase(it);
    }
  }
}

void LogThrottle::flushAll() {
  std::lock_guard lock(mutex_);
  for (const auto& [key, entry] : entries_) report(entry);
  entries_.clear();
}

}  // namespace skyroute
