// The bounds of every string that reaches the service from outside: DDS messages, mission and
// fleet files, obstacle feeds, no-fly zones and the configuration (docs/dds.md, "Text bounds").
// They are checked before anything else is done with a message, so that no string can grow a
// topic name, a journal record, a log line or a CSV row past what its consumer takes.
//
//   id          1-64 characters from A-Z a-z 0-9 _ - . , the first a letter, a digit or '_'.
//               Vehicle ids, zone ids, service ids. Such an id always makes a valid ROS 2 name
//               part once '-' and '.' become '_' (ros_names.hpp), well inside DDS's topic name
//               limit; it cannot hold a space, a newline, a comma, a quote or a leading '=',
//               so it can neither forge a log line nor start a spreadsheet formula.
//   request id  the same set, up to 128 characters (a client may build it from a vehicle id,
//               its process id and a time).
//   name        up to 64 printable ASCII characters (planner names).
//   derived id  plan ids and a fleet vehicle's request id: the id set, up to 256 characters.
//   free text   up to 4096 bytes with no control characters but tab (messages, error fields).
#pragma once

#include <cstddef>
#include <optional>
#include <string>
#include <string_view>

#include "planning/core/result.hpp"

namespace skyroute {

inline constexpr std::size_t kMaxIdChars = 64;
inline constexpr std::size_t kMaxRequestIdChars = 128;
inline constexpr std::size_t kMaxNameChars = 64;
inline constexpr std::size_t kMaxFreeTextBytes = 4096;
// Ids the service derives from others (plan ids, a fleet vehicle's request id): the same set.
inline constexpr std::size_t kMaxDerivedIdChars = 256;

// Whether text is an id of at most max_chars characters (see above); empty is not an id.
bool isValidId(std::string_view text, std::size_t max_chars = kMaxIdChars);

// The problem with an id, naming `field`, or nothing. An empty id is "missing".
std::optional<Error> checkId(std::string_view text, std::string_view field, std::size_t max_chars = kMaxIdChars);
// The same, where an empty id means "not given" and passes.
std::optional<Error> checkOptionalId(std::string_view text, std::string_view field,
                                     std::size_t max_chars = kMaxIdChars);
std::optional<Error> checkName(std::string_view text, std::string_view field, std::size_t max_chars = kMaxNameChars);
std::optional<Error> checkFreeText(std::string_view text, std::string_view field,
                                   std::size_t max_bytes = kMaxFreeTextBytes);

// A string from outside made safe to quote in a log line or an answer: at most 64 characters,
// every character outside the id set shown as '?', and the length said when it was cut
// ("uav?1", "aaaa...(70000 characters)"). Used where a refused input is named.
std::string echoOfUntrusted(std::string_view text);

// Free text the service writes (a status message) within the free-text bound: control characters
// but tab shown as '?', and cut at a UTF-8 character boundary.
std::string boundedFreeText(std::string_view text, std::size_t max_bytes = kMaxFreeTextBytes);

}  // namespace skyroute
