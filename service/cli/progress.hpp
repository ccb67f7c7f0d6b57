// Progress of long work on a terminal: one line per step on stderr, with the time since the start,
// only when stderr is a terminal or the user asked for it (--progress), so logs and pipes stay
// clean.
#pragma once

#include <chrono>
#include <functional>
#include <string>

namespace skyroute::cli {

class TerminalProgress {
 public:
  // forced: --progress given. Otherwise shown only when stderr is a terminal.
  explicit TerminalProgress(bool forced);
  bool enabled() const { return enabled_; }
  // "[  1.2 s] <what>" on stderr.
  void step(const std::string& what) const;
  // The same at most once per period_s (the first after period_s), for loops that wait: `what`
  // is only called when a line is due.
  void every(double period_s, const std::function<std::string()>& what) const;

 private:
  bool enabled_ = false;
  std::chrono::steady_clock::time_point started_;
  mutable std::chrono::steady_clock::time_point last_line_;
};

}  // namespace skyroute::cli
