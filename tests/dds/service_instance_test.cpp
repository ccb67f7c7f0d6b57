// A daemon's instance as its USER_DATA carries it: the role travels with it, a daemon that names
// none is a primary, and only two instances of one service_id in the same role are rivals (a
// primary and its hot standby serve together).
#include <gtest/gtest.h>

#include "service/dds/service_instance.hpp"

namespace skyroute::dds {
namespace {

TEST(ServiceInstance, RoleTravelsInTheUserDataAndDecidesWhoIsARival) {
  const ServiceInstance standby = ServiceInstance::current("svc", 0.5, "standby");
  auto parsed = ServiceInstance::fromUserData(standby.userData());
  ASSERT_TRUE(parsed);
  EXPECT_EQ(parsed->role, "standby");
  EXPECT_EQ(parsed->instance_id, standby.instance_id);
  EXPECT_NE(parsed->describe().find("standby"), std::string::npos);

  // USER_DATA of a daemon from before roles: a primary.
  auto old = ServiceInstance::fromUserData("skyrouted-instance/1;service_id=svc;instance=abc;pid=1;started_utc_ns=5");
  ASSERT_TRUE(old);
  EXPECT_EQ(old->role, "primary");

  const ServiceInstance primary = ServiceInstance::current("svc", 0.5, "primary");
  const ServiceInstance second_primary = ServiceInstance::current("svc", 0.5, "primary");
  const ServiceInstance other_service = ServiceInstance::current("other", 0.5, "primary");
  EXPECT_FALSE(primary.rivals(standby));
  EXPECT_FALSE(standby.rivals(primary));
  EXPECT_TRUE(primary.rivals(second_primary));
  EXPECT_TRUE(primary.rivals(*old));
  EXPECT_FALSE(primary.rivals(other_service));
  EXPECT_TRUE(standby.rivals(*parsed));
}

TEST(ServiceInstance, AShardsEarlierLivesTravelInTheUserData) {
  ServiceInstance shard = ServiceInstance::current("shard-a", 0.5, "primary");
  shard.shard_group = "g";
  EXPECT_EQ(ServiceInstance::fromUserData(shard.userData())->past_coverage, std::vector<CoverageInterval>{});
  shard.past_coverage = {{1'000, 5'000}, {7'000, 9'000}};
  auto parsed = ServiceInstance::fromUserData(shard.userData());
  ASSERT_TRUE(parsed);
  EXPECT_EQ(parsed->past_coverage, shard.past_coverage);
  EXPECT_EQ(parsed->shard_group, "g");
  // A coverage it cannot read: the daemon is still known, as one that read only its current life.
  auto odd = ServiceInstance::fromUserData("skyrouted-instance/1;service_id=s;instance=i;coverage=x-y;shard_group=g");
  ASSERT_TRUE(odd);
  EXPECT_TRUE(odd->past_coverage.empty());
  EXPECT_EQ(odd->shard_group, "g");
}

}  // namespace
}  // namespace skyroute::dds
