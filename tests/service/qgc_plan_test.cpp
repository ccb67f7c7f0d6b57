// QGroundControl files of a trajectory, read back as QGroundControl would: the .plan's fields and
// types, AMSL altitudes, points within 1e-7 degrees, the route inside the corridor, mission points
// kept, the geofence; the QGC WPL 110 text; one .plan per vehicle.
#include "service/qgc_plan.hpp"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <optional>
#include <sstream>

#include <gtest/gtest.h>

#include "service/polyline_simplify.hpp"
#include "tests/text_file.hpp"

namespace skyroute {
namespace {

using nlohmann::json;

// A climbing, weaving flight near the embedded terrain, sampled every 0.5 s, with three legs.
Eigen::Vector3d weavingPositionM(double time_s) {
  return {20.0 * time_s, 400.0 * std::sin(time_s / 25.0), 900.0 + 0.8 * time_s};
}

TrajectoryData weavingTrajectory(const LocalFrame& frame, const std::string& vehicle = "uav-1") {
  TrajectoryData t;
  t.vehicle_id = vehicle;
  t.plan_id = "plan-" + vehicle;
  t.request_id = "req-" + vehicle;
  for (int i = 0; i <= 600; ++i) {
    const double time = 0.5 * i;
    TrajectorySampleData s;
    s.t_rel_s = time;
    s.position_enu_m = weavingPositionM(time);
    s.geo = frame.toGeo(s.position_enu_m);
    t.samples.push_back(s);
  }
  t.legs = {{0, 1, 0.0, 97.3}, {1, 2, 97.3, 201.1}, {2, 3, 201.1, 300.0}};
  t.visiting_order = {0, 1, 2, 3};
  return t;
}

std::string slurp(const std::string& path) { return skyroute::testing::readTextFile(path); }

// The keys and JSON types QGroundControl's loader checks (plan file format, mission version 2).
void expectPlanSchema(const json& plan) {
  ASSERT_TRUE(plan.is_object());
  EXPECT_EQ(plan.at("fileType"), "Plan");
  EXPECT_EQ(plan.at("version"), 1);
  EXPECT_TRUE(plan.at("groundStation").is_string());
  const json& mission = plan.at("mission");
  EXPECT_EQ(mission.at("version"), 2);
  EXPECT_TRUE(mission.at("firmwareType").is_number_integer());
  EXPECT_TRUE(mission.at("vehicleType").is_number_integer());
  EXPECT_TRUE(mission.at("cruiseSpeed").is_number());
  EXPECT_TRUE(mission.at("hoverSpeed").is_number());
  EXPECT_EQ(mission.at("globalPlanAltitudeMode"), 2);  // AMSL
  const json& home = mission.at("plannedHomePosition");
  ASSERT_TRUE(home.is_array());
  ASSERT_EQ(home.size(), 3u);
  for (const json& v : home) EXPECT_TRUE(v.is_number());
  ASSERT_TRUE(mission.at("items").is_array());
  ASSERT_FALSE(mission.at("items").empty());
  int jump = 1;
  for (const json& item : mission.at("items")) {
    EXPECT_EQ(item.at("type"), "SimpleItem");
    EXPECT_EQ(item.at("command"), 16);     // MAV_CMD_NAV_WAYPOINT
    EXPECT_EQ(item.at("frame"), 0);        // MAV_FRAME_GLOBAL: altitude AMSL
    EXPECT_EQ(item.at("AltitudeMode"), 2); // QGroundControl's absolute (AMSL)
    EXPECT_EQ(item.at("doJumpId"), jump++);
    EXPECT_TRUE(item.at("autoContinue").is_boolean());
    EXPECT_TRUE(item.at("Altitude").is_number());
    EXPECT_TRUE(item.at("AMSLAltAboveTerrain").is_null());
    const json& params = item.at("params");
    ASSERT_TRUE(params.is_array());
    ASSERT_EQ(params.size(), 7u);
    for (int p : {0, 1, 2, 4, 5, 6}) EXPECT_TRUE(params[p].is_number()) << p;
    EXPECT_TRUE(params[3].is_null());  // yaw: the autopilot's heading mode
    EXPECT_EQ(params[6], item.at("Altitude"));
  }
  const json& fence = plan.at("geoFence");
  EXPECT_EQ(fence.at("version"), 2);
  ASSERT_TRUE(fence.at("circles").is_array());
  ASSERT_TRUE(fence.at("polygons").is_array());
  for (const json& polygon : fence.at("polygons")) {
    EXPECT_EQ(polygon.at("version"), 1);
    EXPECT_TRUE(polygon.at("inclusion").is_boolean());
    for (const json& v : polygon.at("polygon")) {
      ASSERT_EQ(v.size(), 2u);
      EXPECT_TRUE(v[0].is_number() && v[1].is_number());
    }
  }
  EXPECT_EQ(plan.at("rallyPoints").at("version"), 2);
  EXPECT_TRUE(plan.at("rallyPoints").at("points").is_array());
}

class QgcPlanTest : public ::testing::Test {
 protected:
  void SetUp() override {
    auto f = LocalFrame::create(46.93, 15.05);
    ASSERT_TRUE(f.ok()) << f.error().describe();
    frame_.emplace(*f);
    // ctest runs every test as its own process, in parallel: one folder each.
    const std::string test = ::testing::UnitTest::GetInstance()->current_test_info()->name();
    dir_ = std::filesystem::path(::testing::TempDir()) / ("skyroute_qgc_plan_test_" + test);
    std::filesystem::remove_all(dir_);
    std::filesystem::create_directories(dir_);
  }
  void TearDown() override { std::filesystem::remove_all(dir_); }

  std::optional<LocalFrame> frame_;
  std::filesystem::path dir_;
};

TEST_F(QgcPlanTest, PlanFileValidatesRoundTripsAndStaysInTheCorridor) {
  const TrajectoryData t = weavingTrajectory(*frame_);
  const GeofencePolygon zone{{{46.95, 15.06}, {46.96, 15.06}, {46.96, 15.08}, {46.95, 15.06}}};  // closed ring
  QgcPlanOptions options;
  options.corridor_m = 4.0;
  auto mission = qgcMissionFromTrajectory(t, {zone}, options);
  ASSERT_TRUE(mission.ok()) << mission.error().describe();
  const std::string path = (dir_ / "uav-1.plan").string();
  ASSERT_TRUE(writeQgcPlan(path, *mission).ok());

  const json plan = json::parse(slurp(path), nullptr, false);
  ASSERT_FALSE(plan.is_discarded());
  expectPlanSchema(plan);

  const json& home = plan["mission"]["plannedHomePosition"];
  EXPECT_NEAR(home[0].get<double>(), t.samples.front().geo.lat_deg, 1e-7);
  EXPECT_NEAR(home[1].get<double>(), t.samples.front().geo.lon_deg, 1e-7);
  EXPECT_NEAR(home[2].get<double>(), t.samples.front().geo.alt_amsl_m, 1e-3);
  // 6000 m flown in 300 s (plus the weave): the mean speed is the cruise speed.
  EXPECT_GT(plan["mission"]["cruiseSpeed"].get<double>(), 20.0);
  EXPECT_LT(plan["mission"]["cruiseSpeed"].get<double>(), 30.0);

  const json& items = plan["mission"]["items"];
  ASSERT_EQ(items.size(), mission->items.size());
  EXPECT_LT(items.size(), t.samples.size() / 5) << "the simplification should drop most samples";
  std::vector<Eigen::Vector3d> route, flown;
  for (const auto& s : t.samples) flown.push_back(s.position_enu_m);
  for (std::size_t i = 0; i < items.size(); ++i) {
    const json& p = items[i]["params"];
    const GeoPoint read{p[4].get<double>(), p[5].get<double>(), p[6].get<double>()};
    const GeoPoint& written = mission->items[i].point;
    EXPECT_NEAR(read.lat_deg, written.lat_deg, 1e-7) << i;
    EXPECT_NEAR(read.lon_deg, written.lon_deg, 1e-7) << i;
    EXPECT_NEAR(read.alt_amsl_m, written.alt_amsl_m, 1e-6) << i;
    // AMSL, unconverted: the flight's own altitude at that time.
    EXPECT_NEAR(read.alt_amsl_m, weavingPositionM(mission->items[i].time_s).z(), 1e-3) << i;
    route.push_back(frame_->toEnu(read));
  }
  // The straight lines between the items, as read back, stay within the corridor of the flight.
  for (std::size_t s = 0; s + 1 < route.size(); ++s)
    for (int j = 0; j <= 40; ++j) {
      const Eigen::Vector3d q = route[s] + (route[s + 1] - route[s]) * (j / 40.0);
      double nearest = 1e18;
      for (std::size_t k = 0; k + 1 < flown.size(); ++k)
        nearest = std::min(nearest, distanceToSegment(q, flown[k], flown[k + 1]));
      EXPECT_LE(nearest, options.corridor_m + 1e-3) << "segment " << s;
    }
  // Begin, the two inner leg boundaries (97.3 s and 201.1 s, between samples) and end are items,
  // where the flight is at those times (a straight line between two samples 0.5 s apart is within
  // a few centimetres of this curve).
  std::vector<double> mission_times;
  for (const auto& item : mission->items)
    if (item.mission_point) {
      mission_times.push_back(item.time_s);
      EXPECT_LT((frame_->toEnu(item.point) - weavingPositionM(item.time_s)).norm(), 0.05) << item.time_s;
    }
  EXPECT_EQ(mission_times, (std::vector<double>{0.0, 97.3, 201.1, 300.0}));

  const json& polygons = plan["geoFence"]["polygons"];
  ASSERT_EQ(polygons.size(), 1u);
  EXPECT_EQ(polygons[0]["inclusion"], false);  // keep out
  ASSERT_EQ(polygons[0]["polygon"].size(), 3u);  // the closing vertex dropped
  EXPECT_NEAR(polygons[0]["polygon"][2][0].get<double>(), 46.96, 1e-12);
  EXPECT_NEAR(polygons[0]["polygon"][2][1].get<double>(), 15.08, 1e-12);
}

TEST_F(QgcPlanTest, WaypointsTextIsQgcWpl110) {
  const TrajectoryData t = weavingTrajectory(*frame_);
  auto mission = qgcMissionFromTrajectory(t);
  ASSERT_TRUE(mission.ok()) << mission.error().describe();
  const std::string path = (dir_ / "uav-1.waypoints").string();
  ASSERT_TRUE(writeQgcWaypoints(path, *mission).ok());
  std::istringstream lines(slurp(path));
  std::string line;
  std::getline(lines, line);
  EXPECT_EQ(line, "QGC WPL 110");
  std::size_t seq = 0;
  while (std::getline(lines, line)) {
    std::vector<std::string> cols;
    std::stringstream row(line);
    std::string col;
    while (std::getline(row, col, '\t')) cols.push_back(col);
    ASSERT_EQ(cols.size(), 12u) << line;
    EXPECT_EQ(std::stoul(cols[0]), seq);
    EXPECT_EQ(cols[1], seq == 0 ? "1" : "0");  // line 0 is home
    EXPECT_EQ(cols[2], "0");                   // MAV_FRAME_GLOBAL: AMSL
    EXPECT_EQ(cols[3], "16");
    EXPECT_EQ(cols[11], "1");
    const GeoPoint expected = seq == 0 ? mission->home : mission->items[seq - 1].point;
    EXPECT_NEAR(std::stod(cols[8]), expected.lat_deg, 1e-7) << line;
    EXPECT_NEAR(std::stod(cols[9]), expected.lon_deg, 1e-7) << line;
    EXPECT_NEAR(std::stod(cols[10]), expected.alt_amsl_m, 1e-3) << line;
    ++seq;
  }
  EXPECT_EQ(seq, mission->items.size() + 1);
}

TEST_F(QgcPlanTest, WithoutLegsTheEndsAreTheMissionPoints) {
  TrajectoryData t = weavingTrajectory(*frame_);
  t.legs.clear();
  QgcPlanOptions options;
  options.corridor_m = 1e6;  // everything fits: only the mission points remain
  options.cruise_speed_mps = 12.5;
  auto mission = qgcMissionFromTrajectory(t, {}, options);
  ASSERT_TRUE(mission.ok()) << mission.error().describe();
  ASSERT_EQ(mission->items.size(), 2u);
  EXPECT_EQ(mission->items.back().time_s, t.samples.back().t_rel_s);
  EXPECT_EQ(qgcPlanJson(*mission)["mission"]["cruiseSpeed"], 12.5);
  EXPECT_TRUE(qgcPlanJson(*mission)["geoFence"]["polygons"].empty());
}

TEST_F(QgcPlanTest, BadInputNamesTheField) {
  const TrajectoryData t = weavingTrajectory(*frame_);
  QgcPlanOptions options;
  options.corridor_m = 0.0;
  auto corridor = qgcMissionFromTrajectory(t, {}, options);
  ASSERT_FALSE(corridor.ok());
  EXPECT_EQ(corridor.error().field, "corridor_m");

  TrajectoryData one = t;
  one.samples.resize(1);
  auto short_one = qgcMissionFromTrajectory(one);
  ASSERT_FALSE(short_one.ok());
  EXPECT_EQ(short_one.error().field, "samples");

  auto line = qgcMissionFromTrajectory(t, {GeofencePolygon{{{46.9, 15.0}, {46.91, 15.0}, {46.9, 15.0}}}});
  ASSERT_FALSE(line.ok());
  EXPECT_EQ(line.error().field, "no_fly_zones[0].ring");
  auto far = qgcMissionFromTrajectory(t, {GeofencePolygon{{{46.9, 15.0}, {46.91, 15.0}, {46.9, 15.1}}},
                                          GeofencePolygon{{{46.9, 15.0}, {95.0, 15.0}, {46.9, 15.1}}}});
  ASSERT_FALSE(far.ok());
  EXPECT_EQ(far.error().field, "no_fly_zones[1].ring[1].lat_deg");
}

TEST_F(QgcPlanTest, OnePlanPerVehicle) {
  const std::vector<TrajectoryData> fleet = {weavingTrajectory(*frame_, "uav/1"), weavingTrajectory(*frame_, "uav-2")};
  const std::string dir = (dir_ / "plans").string();  // created on the way
  auto written = writeQgcPlanPerVehicle(dir, fleet);
  ASSERT_TRUE(written.ok()) << written.error().describe();
  ASSERT_EQ(written->size(), 2u);
  EXPECT_EQ((*written)[0], (dir_ / "plans" / "uav_1.plan").string());
  EXPECT_EQ((*written)[1], (dir_ / "plans" / "uav-2.plan").string());
  for (const auto& path : *written) {
    const json plan = json::parse(slurp(path), nullptr, false);
    ASSERT_FALSE(plan.is_discarded()) << path;
    expectPlanSchema(plan);
  }
  auto clash = writeQgcPlanPerVehicle(dir, {weavingTrajectory(*frame_, "a/b"), weavingTrajectory(*frame_, "a_b")});
  ASSERT_FALSE(clash.ok());
  EXPECT_EQ(clash.error().field, "a_b");
}

}  // namespace
}  // namespace skyroute
