// Rendezvous assignment of vehicles to the daemons of a shard group: balanced, stable when a
// member leaves or joins (only the keys that must move do), the same whatever the member order,
// and the hash pinned so that daemons of different builds agree.
#include <gtest/gtest.h>

#include <algorithm>
#include <map>
#include <string>
#include <vector>

#include "service/shard_assignment.hpp"

namespace skyroute {
namespace {

std::vector<std::string> vehicleKeys(int n) {
  std::vector<std::string> keys;
  for (int i = 0; i < n; ++i) keys.push_back("vehicle:uav-" + std::to_string(i));
  return keys;
}

std::map<std::string, std::string> assign(const std::vector<std::string>& members, const std::vector<std::string>& keys) {
  std::map<std::string, std::string> owner;
  for (const std::string& k : keys) owner[k] = rendezvousOwner(members, k);
  return owner;
}

TEST(ShardAssignment, ThousandVehiclesSpreadEvenlyOverThreeAndFourMembers) {
  const auto keys = vehicleKeys(1000);
  for (const std::vector<std::string>& members :
       {std::vector<std::string>{"shard-a", "shard-b", "shard-c"},
        std::vector<std::string>{"skyrouted-1", "skyrouted-2", "skyrouted-3", "skyrouted-4"}}) {
    std::map<std::string, int> count;
    for (const auto& [key, owner] : assign(members, keys)) ++count[owner];
    const double fair = 1000.0 / static_cast<double>(members.size());
    for (const std::string& m : members) {
      // A binomial count's standard deviation here is about 15: 20% is more than four of them.
      EXPECT_NEAR(count[m], fair, 0.2 * fair) << m << " of " << members.size();
    }
  }
}

TEST(ShardAssignment, WhenAMemberLeavesOnlyItsVehiclesMoveAndTheyMoveEvenly) {
  const auto keys = vehicleKeys(1000);
  const std::vector<std::string> four{"shard-a", "shard-b", "shard-c", "shard-d"};
  const std::vector<std::string> three{"shard-a", "shard-b", "shard-d"};  // shard-c left
  const auto before = assign(four, keys);
  const auto after = assign(three, keys);
  std::map<std::string, int> gained;
  for (const std::string& k : keys) {
    if (before.at(k) != "shard-c") {
      EXPECT_EQ(after.at(k), before.at(k)) << k << " moved though its owner stayed";
    } else {
      EXPECT_NE(after.at(k), "shard-c");
      ++gained[after.at(k)];
    }
  }
  // The leaver's vehicles spread over the others, not onto one of them.
  for (const std::string& m : three) EXPECT_GT(gained[m], 30) << m;
  // And joining again moves exactly those back.
  EXPECT_EQ(assign(four, keys), before);
}

TEST(ShardAssignment, OwnerDoesNotDependOnMemberOrderOrDuplicates) {
  const auto keys = vehicleKeys(200);
  std::vector<std::string> members{"b", "a", "d", "c"};
  const auto first = assign(members, keys);
  std::sort(members.begin(), members.end());
  EXPECT_EQ(assign(members, keys), first);
  members.push_back("c");
  EXPECT_EQ(assign(members, keys), first);
  EXPECT_EQ(rendezvousOwner({}, "vehicle:x"), "");
  EXPECT_EQ(rendezvousOwner({"only"}, "vehicle:x"), "only");
}

TEST(ShardAssignment, HashIsFnv1aWithAFinaliserPinnedAcrossBuilds) {
  // Independent reference: FNV-1a 64 of "a" is 0xaf63dc4c8601ec8c (the FNV authors' test vectors),
  // and the finaliser is splitmix64's, computed here step by step.
  std::uint64_t h = 0xaf63dc4c8601ec8cULL;
  h ^= h >> 30;
  h *= 0xbf58476d1ce4e5b9ULL;
  h ^= h >> 27;
  h *= 0x94d049bb133111ebULL;
  h ^= h >> 31;
  EXPECT_EQ(stableHash64("a"), h);
  EXPECT_NE(stableHash64("uav-1"), stableHash64("uav-2"));
  // Member and key are joined unambiguously.
  EXPECT_NE(rendezvousWeight("ab", "c"), rendezvousWeight("a", "bc"));
}

}  // namespace
}  // namespace skyroute
