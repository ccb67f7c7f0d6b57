// Structured logs for the daemon and the tools: every message is "event=<name> key=value ...";
// the text format prints it after a timestamp and level, the json format as one JSON object per
// line ({"time":..,"level":..,"msg":..}) for log collectors. Logs go to stderr.
#pragma once

#include <string>

#include "planning/core/result.hpp"

namespace skyroute {

// level: trace, debug, info, warn, error. format: text or json. Errors name the option.
Status setupLogging(const std::string& level, const std::string& format);

}  // namespace skyroute
