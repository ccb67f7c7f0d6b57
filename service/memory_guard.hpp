// Refusing work the machine cannot hold, before it starts: the free memory (MemAvailable of
// /proc/meminfo) against an estimate, with a message that names the option to change and both
// numbers. Better a refusal at once than a minute of swapping and an OOM kill.
#pragma once

#include <cstddef>
#include <optional>
#include <string>

#include "planning/core/result.hpp"

namespace skyroute {

// MemAvailable of a /proc/meminfo text, in bytes; nullopt when it has none.
std::optional<std::size_t> parseMemAvailable(const std::string& meminfo_text);
// The machine's free memory (MemAvailable of /proc/meminfo); nullopt when it cannot be read.
std::optional<std::size_t> availableMemoryBytes();

// "512 MiB", "13.1 GiB"
std::string bytesText(std::size_t bytes);

// kInvalidArgument naming `option` (e.g. "--octree-res") when estimate_bytes exceeds limit_bytes;
// the message says what the work is, both amounts, and where the limit came from.
Status checkMemoryEstimate(std::size_t estimate_bytes, std::size_t limit_bytes, const std::string& limit_source,
                           const std::string& option, const std::string& what);

}  // namespace skyroute
