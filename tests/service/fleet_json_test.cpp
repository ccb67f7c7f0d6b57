// The fleet JSON of `skyroute fleet --file`: round trip, defaults (vehicle ids, ends, limits) and
// errors that name the field with its path.
#include <gtest/gtest.h>

#include <functional>

#include "service/mission_json.hpp"

namespace skyroute {
namespace {

using nlohmann::json;

json point(double lat, double lon, double alt) { return {{"lat_deg", lat}, {"lon_deg", lon}, {"alt_amsl_m", alt}}; }

json minimalFleet() {
  return {{"begins", {point(46.91, 15.04, 1000), point(46.91, 15.13, 1000)}},
          {"tasks", {point(46.93, 15.06, 1050), {{"east_m", 100}, {"north_m", 200}, {"up_m", 1100}}}}};
}

TEST(FleetJson, RoundTripKeepsEveryField) {
  FleetRequestData f;
  f.request_id = "fleet-7";
  f.vehicle_ids = {"a", "b"};
  f.begins = {MissionPointData::wgs84(46.91, 15.04, 1000), MissionPointData::enu({-100, 50, 900})};
  f.tasks = {MissionPointData::wgs84(46.93, 15.06, 1050)};
  f.ends = {MissionPointData::wgs84(46.92, 15.05, 1000), MissionPointData::wgs84(46.92, 15.10, 1000)};
  f.limits.max_speed_mps = 25.0;
  f.limits.min_clearance_agl_m = 45.0;
  f.planner = "gmtpa";
  auto back = fleetFromJson(fleetToJson(f));
  ASSERT_TRUE(back.ok()) << back.error().describe();
  EXPECT_EQ(back->request_id, "fleet-7");
  EXPECT_EQ(back->vehicle_ids, f.vehicle_ids);
  ASSERT_EQ(back->begins.size(), 2u);
  EXPECT_EQ(back->begins[1].frame, MissionPointData::Frame::kEnu);
  EXPECT_EQ(back->begins[1].enu_m, Eigen::Vector3d(-100, 50, 900));
  EXPECT_DOUBLE_EQ(back->tasks[0].geo.lat_deg, 46.93);
  EXPECT_DOUBLE_EQ(back->ends[1].geo.lon_deg, 15.10);
  EXPECT_DOUBLE_EQ(back->limits.max_speed_mps, 25.0);
  EXPECT_DOUBLE_EQ(back->limits.min_clearance_agl_m, 45.0);
  EXPECT_EQ(back->planner, "gmtpa");
}

TEST(FleetJson, VehiclesAreNamedAndReturnToTheirBeginsByDefault) {
  auto f = fleetFromJson(minimalFleet());
  ASSERT_TRUE(f.ok()) << f.error().describe();
  EXPECT_EQ(f->vehicle_ids, (std::vector<std::string>{"uav-1", "uav-2"}));
  ASSERT_EQ(f->ends.size(), 2u);
  EXPECT_DOUBLE_EQ(f->ends[1].geo.lon_deg, 15.13);
  EXPECT_EQ(f->request_id, "");
  EXPECT_DOUBLE_EQ(f->limits.v_ref_mps, VehicleLimitsData{}.v_ref_mps);
  EXPECT_EQ(f->tasks[1].frame, MissionPointData::Frame::kEnu);
}

TEST(FleetJson, ErrorsNameTheFieldWithItsPath) {
  struct Case {
    std::function<void(json&)> spoil;
    std::string field;
  };
  const std::vector<Case> cases{
      {[](json& j) { j["tasks"][1] = {{"lat_deg", 46.9}, {"lon_deg", 15.0}}; }, "tasks[1].alt_amsl_m"},
      {[](json& j) { j["tasks"][0]["lat_deg"] = "north"; }, "tasks[0].lat_deg"},
      {[](json& j) { j.erase("tasks"); }, "tasks"},
      {[](json& j) { j.erase("begins"); }, "begins"},
      {[](json& j) { j["begins"] = 3; }, "begins"},
      {[](json& j) { j["vehicle_ids"] = {"a"}; }, "vehicle_ids"},
      {[](json& j) { j["vehicle_ids"] = {"a", 2}; }, "vehicle_ids[1]"},
      {[](json& j) { j["ends"] = {point(46.9, 15.0, 1000)}; }, "ends"},
      {[](json& j) { j["ends"] = {point(46.9, 15.0, 1000), 7}; }, "ends[1]"},
      {[](json& j) { j["limits"] = {{"max_speed_mps", "fast"}}; }, "limits.max_speed_mps"},
      {[](json& j) { j["planner"] = 1; }, "planner"},
  };
  for (const Case& c : cases) {
    json j = minimalFleet();
    c.spoil(j);
    auto f = fleetFromJson(j);
    ASSERT_FALSE(f.ok()) << c.field;
    EXPECT_EQ(f.error().field, c.field);
    EXPECT_NE(f.error().message.find(c.field), std::string::npos) << f.error().message;
  }
  EXPECT_FALSE(fleetFromJson(json::array()).ok());
}

}  // namespace
}  // namespace skyroute
