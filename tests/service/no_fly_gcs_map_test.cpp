// The ground station's map state shows the no-fly zones in force: a zone as it arrives (from a
// file or the DDS topic) appears with its ring and heights, a new one with the same id replaces
// it, and a lifted one goes.
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "service/gcs_map_state.hpp"
#include "tests/service/gcs_fixtures.hpp"

namespace skyroute {
namespace {

NoFlyZoneData zone(const std::string& id, double ceiling_amsl_m) {
  NoFlyZoneData z;
  z.zone_id = id;
  z.ring = {GeoPoint{46.93, 15.06, 0.0}, GeoPoint{46.93, 15.08, 0.0}, GeoPoint{46.94, 15.07, 0.0}};
  z.floor_amsl_m = 100.0;
  z.ceiling_amsl_m = ceiling_amsl_m;
  return z;
}

TEST(NoFlyGcsMap, ZonesAppearAreReplacedAndGo) {
  auto state = testing::embeddedTerrainMapState();
  ASSERT_TRUE(state);
  state->onNoFlyZone(zone("tower", 900.0));
  state->onNoFlyZone(zone("range", 1200.0));
  state->onNoFlyZone(zone("tower", 950.0));  // replaces the first
  nlohmann::json s = nlohmann::json::parse(*state->snapshot().json);
  ASSERT_EQ(s["no_fly_zones"].size(), 2u);
  const auto& tower = s["no_fly_zones"][1];  // by id: range, tower
  EXPECT_EQ(tower["id"], "tower");
  EXPECT_EQ(tower["ceiling_amsl_m"], 950.0);
  EXPECT_EQ(tower["floor_amsl_m"], 100.0);
  ASSERT_EQ(tower["ring"].size(), 3u);
  EXPECT_EQ(tower["ring"][2]["lat_deg"], 46.94);
  EXPECT_EQ(tower["ring"][2]["lon_deg"], 15.07);
  const std::uint64_t version = state->version();
  NoFlyZoneData lift;
  lift.zone_id = "range";
  lift.remove = true;
  state->onNoFlyZone(lift);
  EXPECT_GT(state->version(), version);
  s = nlohmann::json::parse(*state->snapshot().json);
  ASSERT_EQ(s["no_fly_zones"].size(), 1u);
  EXPECT_EQ(s["no_fly_zones"][0]["id"], "tower");
}

}  // namespace
}  // namespace skyroute
