// Runs the `skyroute` CLI as a user would (a shell command line, stderr folded into stdout) and
// returns its exit code and output, for the CLI tests.
#pragma once

#include <sys/wait.h>

#include <array>
#include <cstdio>
#include <string>

namespace skyroute::testing {

struct CliOutput {
  int exit_code = -1;
  std::string text;
};

inline CliOutput runCli(const std::string& args) {
  CliOutput out;
  const std::string cmd = std::string(SKYROUTE_CLI) + " " + args + " 2>&1";
  FILE* pipe = popen(cmd.c_str(), "r");
  if (!pipe) return out;
  std::array<char, 4096> buf{};
  while (std::fgets(buf.data(), buf.size(), pipe)) out.text += buf.data();
  const int status = pclose(pipe);
  out.exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  return out;
}

}  // namespace skyroute::testing
