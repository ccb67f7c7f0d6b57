// The NoFlyZone message: what goes out comes back, and what cannot be a zone is refused naming
// the member. No participant needed.
#include <cmath>
#include <limits>

#include <gtest/gtest.h>

#include "service/dds/no_fly_conversions.hpp"

namespace skyroute::dds {
namespace {

NoFlyZoneData tower() {
  NoFlyZoneData z;
  z.zone_id = "tower";
  z.ring = {GeoPoint{46.93, 15.06, 0.0}, GeoPoint{46.93, 15.08, 0.0}, GeoPoint{46.94, 15.07, 0.0}};
  z.floor_amsl_m = 200.0;
  z.ceiling_amsl_m = 1500.0;
  z.valid_from_utc_ns = 1'795'615'200'000'000'000LL;
  z.valid_until_utc_ns = 1'795'629'600'000'000'000LL;
  return z;
}

TEST(NoFlyConversion, RoundTrip) {
  WireSample<skyroute_msgs_NoFlyZone> wire(&skyroute_msgs_NoFlyZone_desc);
  toWire(tower(), wire.msg());
  auto back = fromWire(wire.msg());
  ASSERT_TRUE(back.ok()) << back.error().describe();
  EXPECT_EQ(back->zone_id, "tower");
  ASSERT_EQ(back->ring.size(), 3u);
  EXPECT_EQ(back->ring[2].lat_deg, 46.94);
  EXPECT_EQ(back->ring[2].lon_deg, 15.07);
  EXPECT_EQ(back->floor_amsl_m, 200.0);
  EXPECT_EQ(back->ceiling_amsl_m, 1500.0);
  EXPECT_EQ(back->valid_from_utc_ns, tower().valid_from_utc_ns);
  EXPECT_EQ(back->valid_until_utc_ns, tower().valid_until_utc_ns);
  EXPECT_FALSE(back->remove);
}

TEST(NoFlyConversion, RefusesWhatCannotBeAZone) {
  NoFlyZoneData nameless = tower();
  nameless.zone_id.clear();
  WireSample<skyroute_msgs_NoFlyZone> a(&skyroute_msgs_NoFlyZone_desc);
  toWire(nameless, a.msg());
  EXPECT_EQ(fromWire(a.msg()).error().field, "zone_id");

  NoFlyZoneData nan = tower();
  nan.ring[1].lat_deg = std::numeric_limits<double>::quiet_NaN();
  WireSample<skyroute_msgs_NoFlyZone> b(&skyroute_msgs_NoFlyZone_desc);
  toWire(nan, b.msg());
  EXPECT_EQ(fromWire(b.msg()).error().field, "ring[1].lat_deg");

  NoFlyZoneData lift = nan;  // a removal carries only its id
  lift.remove = true;
  WireSample<skyroute_msgs_NoFlyZone> c(&skyroute_msgs_NoFlyZone_desc);
  toWire(lift, c.msg());
  auto lifted = fromWire(c.msg());
  ASSERT_TRUE(lifted.ok());
  EXPECT_TRUE(lifted->remove);
  EXPECT_EQ(lifted->zone_id, "tower");
}

TEST(NoFlyConversion, CountsTheRingBeforeLookingAtIt) {
  NoFlyZoneData big = tower();
  big.ring.assign(kMaxNoFlyZoneVertices + 1, GeoPoint{std::numeric_limits<double>::quiet_NaN(), 15.0, 0.0});
  WireSample<skyroute_msgs_NoFlyZone> wire(&skyroute_msgs_NoFlyZone_desc);
  toWire(big, wire.msg());
  const auto refused = fromWire(wire.msg());
  ASSERT_FALSE(refused.ok());
  EXPECT_EQ(refused.error().field, "ring");  // not ring[0].lat_deg: the count comes first
  EXPECT_EQ(refused.error().message, "ring has 10001 vertices, more than the 10000 a zone may have (zone 'tower')");
  big.ring.assign(kMaxNoFlyZoneVertices, GeoPoint{46.93, 15.06, 0.0});
  WireSample<skyroute_msgs_NoFlyZone> at_bound(&skyroute_msgs_NoFlyZone_desc);
  toWire(big, at_bound.msg());
  EXPECT_TRUE(fromWire(at_bound.msg()).ok());  // the geometry is checked where it meets a terrain
}

}  // namespace
}  // namespace skyroute::dds
