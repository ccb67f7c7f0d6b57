#include "service/state_dir_lock.hpp"

#include <fcntl.h>
#include <sys/file.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <filesystem>
#include <string_view>

namespace skyroute {

namespace {

// The holder's line as it wrote it (at most one line, 256 bytes), or "" when it wrote nothing yet.
std::string holderOf(int fd) {
  char buffer[257] = {};
  const ssize_t n = ::pread(fd, buffer, sizeof buffer - 1, 0);
  if (n <= 0) return "";
  std::string_view text(buffer, static_cast<std::size_t>(n));
  text = text.substr(0, text.find('\n'));
  return std::string(text);
}

}  // namespace

Result<StateDirLock> StateDirLock::acquire(const std::string& dir, const std::string& instance_id,
                                           std::int64_t started_utc_ns) {
  const std::string path = (std::filesystem::path(dir) / kFileName).string();
  const int fd = ::open(path.c_str(), O_RDWR | O_CREAT | O_CLOEXEC, 0644);
  if (fd < 0) {
    return make_error(ErrorCode::kFileNotFound, path,
                      "state folder lock " + path + " cannot be opened: " + std::strerror(errno));
  }
  if (::flock(fd, LOCK_EX | LOCK_NB) != 0) {
    const int why = errno;
    const std::string holder = holderOf(fd);
    ::close(fd);
    if (why != EWOULDBLOCK) {
      return make_error(ErrorCode::kFileNotFound, path, "state folder lock " + path + " cannot be taken: " + std::strerror(why));
    }
    return make_error(ErrorCode::kInvalidArgument, kLockedField,
                      "the state folder " + dir + " is in use by another skyrouted (" +
                          (holder.empty() ? std::string("it has not written its pid yet") : holder) + ", holding " + path +
                          "); not starting: two daemons on one journal would resume each other's vehicles (give "
                          "each daemon its own service.state_dir, or stop the other one)");
  }
  const std::string line = "pid=" + std::to_string(::getpid()) + " instance=" + instance_id +
                           " started_utc_ns=" + std::to_string(started_utc_ns) + "\n";
  // Best effort: a full disk must not keep the daemon from starting on its journal. Written over
  // the last holder's line first, then cut to length, so no new block is needed for it.
  if (::pwrite(fd, line.data(), line.size(), 0) == static_cast<ssize_t>(line.size())) {
    (void)!::ftruncate(fd, static_cast<off_t>(line.size()));
  }
  return StateDirLock(fd, path);
}

StateDirLock::StateDirLock(StateDirLock&& other) noexcept : fd_(other.fd_), path_(std::move(other.path_)) {
  other.fd_ = -1;
}

StateDirLock& StateDirLock::operator=(StateDirLock&& other) noexcept {
  if (this != &other) {
    if (fd_ >= 0) ::close(fd_);
    fd_ = other.fd_;
    path_ = std::move(other.path_);
    other.fd_ = -1;
  }
  return *this;
}

StateDirLock::~StateDirLock() {
  if (fd_ >= 0) ::close(fd_);  // closing the last descriptor releases the flock
}

bool isStateDirLocked(const Error& e) {
  return e.code == ErrorCode::kInvalidArgument && e.field == StateDirLock::kLockedField;
}

}  // namespace skyroute
