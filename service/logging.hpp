// Structured logs for the daemon and the tools: every message is "event=<name> key=value ...";
// the text format prints it after a timestamp and level, the json format as one JSON object per
// line with the message's own fields ({"time":..,"level":..,"pid":..,"event":..,"vehicle":..,
// "duration_s":..}) for log collectors. Logs go to stderr.
#pragma once

#include <string>
#include <string_view>

#include <nlohmann/json.hpp>

#include "planning/core/result.hpp"

namespace skyroute {

// level: trace, debug, info, warn, error. format: text or json. Errors name the option.
Status setupLogging(const std::string& level, const std::string& format);

// The fields of an "event=<name> key=value key=\"quoted value\" ..." message, in order: numbers
// and true/false typed, quoted values unescaped. Text that is not key=value lands in "msg" (the
// whole message when it has no fields).
nlohmann::ordered_json logEventFields(std::string_view message);

}  // namespace skyroute
