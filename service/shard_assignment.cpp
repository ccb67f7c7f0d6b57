#include "service/shard_assignment.hpp"

namespace skyroute {

std::uint64_t stableHash64(std::string_view text) {
  std::uint64_t h = 0xcbf29ce484222325ULL;  // FNV-1a 64 offset basis
  for (const char c : text) {
    h ^= static_cast<std::uint8_t>(c);
    h *= 0x100000001b3ULL;  // FNV-1a 64 prime
  }
  // FNV's low bits mix poorly for short keys that share a prefix ("uav-1", "uav-2", ...).
  h ^= h >> 30;
  h *= 0xbf58476d1ce4e5b9ULL;
  h ^= h >> 27;
  h *= 0x94d049bb133111ebULL;
  h ^= h >> 31;
  return h;
}

std::uint64_t rendezvousWeight(std::string_view member_id, std::string_view key) {
  // The member's length first, so ("ab", "c") and ("a", "bc") never hash the same text.
  std::string joined = std::to_string(member_id.size());
  joined += ':';
  joined += member_id;
  joined += '\n';
  joined += key;
  return stableHash64(joined);
}

std::string rendezvousOwner(const std::vector<std::string>& members, std::string_view key) {
  const std::string* best = nullptr;
  std::uint64_t best_weight = 0;
  for (const std::string& member : members) {
    const std::uint64_t weight = rendezvousWeight(member, key);
    if (best == nullptr || weight > best_weight || (weight == best_weight && member < *best)) {
      best = &member;
      best_weight = weight;
    }
  }
  return best ? *best : std::string();
}

}  // namespace skyroute
