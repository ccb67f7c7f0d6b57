// Which daemon of a shard group plans a key (a vehicle or a fleet request): rendezvous
// (highest-random-weight) hashing over the members' service ids. Every daemon computes it alone
// from the same inputs and reaches the same answer, with no coordinator. When a member leaves,
// only the keys it owned move (each to the member that ranked second for it); when one joins, it
// takes only the keys it now ranks first for.
//
// The hash is written here, not std::hash: daemons built apart (another compiler, another
// standard library) must agree on it.
#pragma once

#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

namespace skyroute {

// FNV-1a over the bytes, then a 64-bit finaliser (splitmix64's) so that keys differing in their
// last byte spread over the whole range. Stable across builds and platforms.
std::uint64_t stableHash64(std::string_view text);

// The weight of one member for one key: the hash of both, unambiguously joined.
std::uint64_t rendezvousWeight(std::string_view member_id, std::string_view key);

// The member with the highest weight for `key` (ties: the smaller id); "" when there are none.
// Members are service ids; their order does not matter and duplicates are harmless.
std::string rendezvousOwner(const std::vector<std::string>& members, std::string_view key);

}  // namespace skyroute
