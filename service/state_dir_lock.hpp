// One skyrouted per state folder: an exclusive flock(2) on DIR/skyrouted.lock, held for the
// daemon's life. The kernel drops the lock with the process, kill -9 included, so a crash never
// leaves the folder locked; a second daemon on the folder is refused naming the holder (the pid,
// instance id and start time the holder wrote into the file). Two daemons on one journal would
// resume each other's vehicles after a restart (docs/journal.md "A second daemon").
#pragma once

#include <string>

#include "planning/core/result.hpp"

namespace skyroute {

class StateDirLock {
 public:
  static constexpr const char* kFileName = "skyrouted.lock";
  // The field of the refusal when another process holds the lock (skyrouted exits with its own
  // code then: isStateDirLocked).
  static constexpr const char* kLockedField = "service.state_dir";

  // Takes the lock of `dir` (which must exist) and writes "pid=... instance=... started_utc_ns=..."
  // into the file. Errors: kInvalidArgument with field kLockedField when another process holds it
  // (the message names the file and the holder); kFileNotFound when the file cannot be opened.
  // A failed write of the holder's line (a full disk) is no error: the lock is what counts.
  static Result<StateDirLock> acquire(const std::string& dir, const std::string& instance_id,
                                      std::int64_t started_utc_ns);

  StateDirLock(StateDirLock&& other) noexcept;
  StateDirLock& operator=(StateDirLock&& other) noexcept;
  StateDirLock(const StateDirLock&) = delete;
  StateDirLock& operator=(const StateDirLock&) = delete;
  ~StateDirLock();  // releases the lock (the file stays: removing it would race a new holder)

  const std::string& path() const { return path_; }

 private:
  StateDirLock(int fd, std::string path) : fd_(fd), path_(std::move(path)) {}
  int fd_ = -1;
  std::string path_;
};

// Whether a start-up error is the refusal of a state folder another daemon holds.
bool isStateDirLocked(const Error& e);

}  // namespace skyroute
