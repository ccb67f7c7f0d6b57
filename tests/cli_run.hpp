// Runs the `skyroute` CLI (or any command line) as a user would, stderr folded into stdout, and
// returns its exit code and output, for the CLI and end-to-end tests.
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

// Any shell command line, stderr folded into stdout.
inline CliOutput runCommand(const std::string& command_line) {
  CliOutput out;
  const std::string cmd = command_line + " 2>&1";
  FILE* pipe = popen(cmd.c_str(), "r");
  if (!pipe) return out;
  std::array<char, 4096> buf{};
  while (std::fgets(buf.data(), buf.size(), pipe)) out.text += buf.data();
  const int status = pclose(pipe);
  out.exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  return out;
}

#ifdef SKYROUTE_CLI
inline CliOutput runCli(const std::string& args) { return runCommand(std::string(SKYROUTE_CLI) + " " + args); }
#endif

}  // namespace skyroute::testing
