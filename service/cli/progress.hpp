// Progress of long work on a terminal: one line per step on stderr, with the time since the start,
// only when stderr is a terminal or the user asked for it (--progress), so logs and pipes stay
// clean.
#pragma once

#include <chrono>
#include <string>

namespace skyroute::cli {

class TerminalProgress {
 public:
  // forced: --progress given. Otherwise shown only when stderr is a terminal.
  explicit TerminalProgress(bool forced);
  bool enabled() const { return enabled_; }
  // "[  1.2 s] <what>" on stderr.
  void step(const std::string& what) const;

 private:
  bool enabled_ = false;
  std::chrono::steady_clock::time_point started_;
};

}  // namespace skyroute::cli
