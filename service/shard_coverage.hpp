// Which requests a shard has read (docs/dds.md "Shards", "Members"): a shard owns a vehicle only
// when it read the vehicle's request, and every member must reach the same verdict from what the
// members advertise. A member has read every request that arrived while it was serving: from its
// start (plus a margin for discovery) in its current life, and, for a shard that journals its
// requests (--state-dir), during the earlier lives its journal kept. A life ended by a crash is
// known only up to the last time it wrote down that it had read everything so far
// (`covered_until`, a margin behind its clock when written); the time it was down is a gap.
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace skyroute {

// One earlier life of a member: it read every request that arrived from started_utc_ns + the
// join margin up to covered_until_utc_ns.
struct CoverageInterval {
  std::int64_t started_utc_ns = 0;
  std::int64_t covered_until_utc_ns = 0;
  bool operator==(const CoverageInterval&) const = default;
};

// How many earlier lives a member advertises (the newest ones): bounds its USER_DATA.
inline constexpr std::size_t kMaxPastCoverage = 4;

// Whether a member that started its current life at started_utc_ns, with these earlier lives,
// read a request that arrived at arrived_utc_ns.
bool coversArrival(std::int64_t started_utc_ns, const std::vector<CoverageInterval>& past,
                   std::int64_t arrived_utc_ns, std::int64_t join_margin_ns);

// The earlier lives worth advertising: those that cover some time, the newest kMaxPastCoverage,
// oldest first.
std::vector<CoverageInterval> advertisedCoverage(std::vector<CoverageInterval> lives, std::int64_t join_margin_ns);

// "s1-e1,s2-e2" (nanoseconds since the epoch) and back; nullopt for a malformed text.
std::string coverageText(const std::vector<CoverageInterval>& past);
std::optional<std::vector<CoverageInterval>> coverageFromText(std::string_view text);

}  // namespace skyroute
