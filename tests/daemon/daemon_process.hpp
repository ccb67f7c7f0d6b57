// skyrouted (or a skyroute tool) as a real child process for the end-to-end tests and the latency
// benchmark: spawned with its output in files, signalled, and waited for with a timeout.
#pragma once

#include <fcntl.h>
#include <signal.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

#include "tests/text_file.hpp"

extern char** environ;

namespace skyroute::testing {

// A path in the temporary folder that no other test process uses: skyroute_<tag>_<pid>_<name>.
inline std::string tempPath(const std::string& tag, const std::string& name) {
  return (std::filesystem::temp_directory_path() / ("skyroute_" + tag + "_" + std::to_string(::getpid()) + "_" + name))
      .string();
}

class ChildProcess {
 public:
  // argv[0] is the program path. stdout and stderr go to files named after `name`.
  static ChildProcess spawn(const std::vector<std::string>& argv, const std::string& name) {
    ChildProcess c;
    const auto dir = std::filesystem::temp_directory_path();
    const std::string stem = "skyroute_e2e_" + std::to_string(::getpid()) + "_" + name;
    c.out_path_ = (dir / (stem + ".out")).string();
    c.err_path_ = (dir / (stem + ".err")).string();
    posix_spawn_file_actions_t actions;
    posix_spawn_file_actions_init(&actions);
    posix_spawn_file_actions_addopen(&actions, STDOUT_FILENO, c.out_path_.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
    posix_spawn_file_actions_addopen(&actions, STDERR_FILENO, c.err_path_.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
    std::vector<char*> args;
    for (const std::string& a : argv) args.push_back(const_cast<char*>(a.c_str()));
    args.push_back(nullptr);
    if (posix_spawn(&c.pid_, argv.front().c_str(), &actions, nullptr, args.data(), environ) != 0) c.pid_ = -1;
    posix_spawn_file_actions_destroy(&actions);
    return c;
  }

  ChildProcess() = default;
  ChildProcess(ChildProcess&& o) noexcept { *this = std::move(o); }
  ChildProcess& operator=(ChildProcess&& o) noexcept {
    std::swap(pid_, o.pid_);
    std::swap(exited_, o.exited_);  // a process spawned into a waited-for one's place is running
    std::swap(code_, o.code_);
    std::swap(out_path_, o.out_path_);
    std::swap(err_path_, o.err_path_);
    return *this;
  }
  ~ChildProcess() {
    if (pid_ > 0 && !exited_) {
      ::kill(pid_, SIGKILL);
      int status = 0;
      ::waitpid(pid_, &status, 0);
    }
    if (!out_path_.empty()) std::filesystem::remove(out_path_);
    if (!err_path_.empty()) std::filesystem::remove(err_path_);
  }

  bool started() const { return pid_ > 0; }
  pid_t pid() const { return pid_; }
  // Resident set size from /proc/<pid>/status (VmRSS), in kB; -1 when it cannot be read.
  long rssKb() const {
    std::ifstream in("/proc/" + std::to_string(pid_) + "/status");
    std::string line;
    while (std::getline(in, line)) {
      if (line.rfind("VmRSS:", 0) == 0) return std::stol(line.substr(6));
    }
    return -1;
  }
  void signal(int sig) const {
    if (pid_ > 0) ::kill(pid_, sig);
  }
  bool running() {
    if (pid_ <= 0 || exited_) return false;
    int status = 0;
    if (::waitpid(pid_, &status, WNOHANG) == pid_) {
      exited_ = true;
      code_ = WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status);
      return false;
    }
    return true;
  }
  // Exit code (128 + signal if killed by one), or -1 if it did not end within timeout_s.
  int wait(double timeout_s) {
    const auto deadline = std::chrono::steady_clock::now() + std::chrono::duration<double>(timeout_s);
    while (running()) {
      if (std::chrono::steady_clock::now() >= deadline) return -1;
      std::this_thread::sleep_for(std::chrono::milliseconds(5));
    }
    return code_;
  }
  std::string out() const { return readTextFile(out_path_); }
  std::string err() const { return readTextFile(err_path_); }

 private:
  pid_t pid_ = -1;
  bool exited_ = false;
  int code_ = -1;
  std::string out_path_, err_path_;
};

// What a program run to its end returned and printed.
struct Ran {
  int code = -1;
  std::string out, err;
};

// Runs argv (argv[0] is the program path) to its end, at most timeout_s.
inline Ran runToEnd(const std::vector<std::string>& argv, const std::string& name, double timeout_s) {
  ChildProcess child = ChildProcess::spawn(argv, name);
  Ran r;
  r.code = child.wait(timeout_s);
  r.out = child.out();
  r.err = child.err();
  return r;
}

}  // namespace skyroute::testing
