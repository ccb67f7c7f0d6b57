// The one table of exit codes of every `skyroute` subcommand (and of skyrouted's start-up), and
// the one way a subcommand fails: a message on stderr that names the option, or the file and
// field, then the code. The README and every --help show this table.
#pragma once

#include <string>
#include <string_view>

namespace skyroute::cli {

inline constexpr int kExitOk = 0;
inline constexpr int kExitPlanningFailed = 1;      // planning failed, or the service answered with a failure
inline constexpr int kExitUsage = 2;               // a bad option or option value
inline constexpr int kExitBadInput = 3;            // an input file unreadable or invalid
inline constexpr int kExitServiceUnavailable = 4;  // the service is unavailable, or an answer timed out
inline constexpr int kExitServiceLost = 5;         // the service that took the request went away, or
                                                   // (skyrouted) another daemon owns its service id
inline constexpr int kExitStateDirLocked = 6;      // (skyrouted) another daemon holds its state folder

// The table as --help footers and the README print it.
inline constexpr std::string_view kExitCodeTable =
    "Exit codes: 0 success, 1 planning failed, 2 usage, 3 an input file unreadable or invalid, "
    "4 the service unavailable or timed out, 5 the service lost while waiting for it.";

// Prints "skyroute <tool>: <message>" on stderr and throws CLI::RuntimeError(code), which main
// turns into the exit code.
[[noreturn]] void fail(const std::string& tool, int code, const std::string& message);

}  // namespace skyroute::cli
