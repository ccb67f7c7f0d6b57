// Errors about a mission point name it as the user wrote it (latitude, longitude, altitude) and
// say what is wrong: outside the DEM (with its bounds), a DEM void, under the ground (with the
// ground height), above the ceiling, latitude and longitude swapped. Checked through the mission
// pipeline's validate stage and the engine's submit check, the paths the CLI and the daemon share.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <limits>

#include "service/engine.hpp"
#include "service/mission_pipeline.hpp"
#include "service/mission_point_check.hpp"
#include "service/number_text.hpp"
#include "terrain/dem.hpp"
#include "terrain/heightfield.hpp"
#include "tests/terrain_data.hpp"

namespace skyroute {
namespace {

class NullSink : public EngineSink {
 public:
  void publishStatus(const PlanStatusData&) override {}
  void publishTrajectory(const TrajectoryData&) override {}
  void retractTrajectory(const std::string&) override {}
};

class MissionPointCheck : public ::testing::Test {
 protected:
  static void SetUpTestSuite() { terrain_ = testing::defaultTerrainHeightfield(); }

  void SetUp() override {
    ASSERT_TRUE(terrain_) << "data/default_terrain.tif did not load";
    auto world = WorldModel::create(terrain_, WorldModelOptions{}, "default_terrain");
    ASSERT_TRUE(world.ok());
    world_ = *world;
  }

  // A WGS84 point agl_m above the ground at east/north metres from the terrain's centre.
  MissionPointData geo(double east_m, double north_m, double agl_m) const {
    const double ground_m = terrain_->heightAt(east_m, north_m);
    const GeoPoint g = terrain_->frame().toGeo(Eigen::Vector3d(east_m, north_m, ground_m + agl_m));
    return MissionPointData::wgs84(g.lat_deg, g.lon_deg, g.alt_amsl_m);
  }
  MissionRequestData request() const {
    MissionRequestData r;
    r.request_id = "r";
    r.vehicle_id = "uav-1";
    r.begin = geo(-4000, -4000, 150);
    r.points = {geo(0, 0, 200)};
    r.end = geo(4000, 4000, 150);
    return r;
  }
  PlanError validate(const MissionRequestData& r) const {
    MissionPipeline pipeline(world_, PipelineOptions{});
    auto ordered = pipeline.order(r, 0.0);
    EXPECT_FALSE(ordered.ok()) << "the request was accepted";
    return ordered.ok() ? PlanError{} : ordered.error();
  }
  static std::string text(double v) { return numberText(v, 9); }
  static std::string oneDecimal(double v) {
    char buf[32];
    std::snprintf(buf, sizeof buf, "%.1f", v);
    return buf;
  }

  static inline std::shared_ptr<const Heightfield> terrain_;
  std::shared_ptr<WorldModel> world_;
};

TEST_F(MissionPointCheck, BoundsCoverTheTerrainInLatitudeAndLongitude) {
  const GeoBoundsDeg b = terrainGeoBounds(*terrain_);
  const GeoPoint centre = terrain_->frame().anchor();
  EXPECT_TRUE(b.contains(centre.lat_deg, centre.lon_deg));
  const auto& box = terrain_->boundsEn();
  for (const Eigen::Vector2d& corner : {box.min(), box.max(), Eigen::Vector2d(box.min().x(), box.max().y())}) {
    const GeoPoint g = terrain_->frame().toGeo(Eigen::Vector3d(corner.x(), corner.y(), 0.0));
    EXPECT_NEAR(std::min(std::abs(g.lat_deg - b.south_deg), std::abs(g.lat_deg - b.north_deg)), 0.0, 0.01);
  }
  // 320 cells of 40 m: about 0.115 degrees of latitude.
  EXPECT_NEAR(b.north_deg - b.south_deg, 12800.0 / 111200.0, 0.005);
}

TEST_F(MissionPointCheck, OutsideTheDemNamesThePointAsWrittenAndTheBounds) {
  MissionRequestData r = request();
  r.points[0] = MissionPointData::wgs84(10.5, 20.25, 900);
  const PlanError e = validate(r);
  EXPECT_EQ(e.code, PlanErrorCode::kOutsideMap);
  EXPECT_EQ(e.field, "points[0]");
  EXPECT_EQ(e.point_index, 1);
  EXPECT_NE(e.message.find("points[0] (10.5, 20.25, 900 m AMSL) is outside the DEM (" +
                           describe(terrainGeoBounds(*terrain_)) + ")"),
            std::string::npos)
      << e.message;
  EXPECT_EQ(e.message.find("ENU"), std::string::npos) << e.message;
  EXPECT_EQ(e.message.find("swapped"), std::string::npos) << e.message;
}

TEST_F(MissionPointCheck, SwappedLatitudeAndLongitudeAreNamed) {
  MissionRequestData r = request();
  const MissionPointData good = r.end;
  r.end = MissionPointData::wgs84(good.geo.lon_deg, good.geo.lat_deg, good.geo.alt_amsl_m);
  const PlanError e = validate(r);
  EXPECT_EQ(e.code, PlanErrorCode::kOutsideMap);
  EXPECT_EQ(e.field, "end");
  EXPECT_NE(e.message.find("latitude and longitude may be swapped"), std::string::npos) << e.message;

  // A latitude beyond 90 degrees is refused by the structural check, with the same hint.
  r.end = MissionPointData::wgs84(120.0, 15.1, 900);
  const PlanError beyond = validate(r);
  EXPECT_EQ(beyond.field, "end.lat_deg");
  EXPECT_NE(beyond.message.find("latitude and longitude may be swapped"), std::string::npos) << beyond.message;
}

TEST_F(MissionPointCheck, UnderTheGroundGivesTheGroundHeight) {
  MissionRequestData r = request();
  r.begin = geo(-4000, -4000, -20);
  const double ground_m = terrain_->heightAt(-4000, -4000);
  const PlanError e = validate(r);
  EXPECT_EQ(e.code, PlanErrorCode::kUnderGround);
  EXPECT_EQ(e.field, "begin");
  EXPECT_NE(e.message.find("begin (" + text(r.begin.geo.lat_deg) + ", " + text(r.begin.geo.lon_deg)), std::string::npos)
      << e.message;
  EXPECT_NE(e.message.find("the ground here is " + oneDecimal(ground_m) + " m AMSL"), std::string::npos) << e.message;
  EXPECT_NE(e.message.find("at least " + oneDecimal(ground_m + 30.0) + " m AMSL"), std::string::npos) << e.message;
}

TEST_F(MissionPointCheck, AboveTheCeilingSaysSo) {
  MissionRequestData r = request();
  r.limits.ceiling_amsl_m = 1500.0;
  r.points[0] = MissionPointData::wgs84(r.points[0].geo.lat_deg, r.points[0].geo.lon_deg, 1600.0);
  const PlanError e = validate(r);
  EXPECT_EQ(e.field, "points[0]");
  EXPECT_NE(e.message.find("1600 m AMSL) is above the ceiling"), std::string::npos) << e.message;
  EXPECT_NE(e.message.find("ceiling 1500.0 m AMSL"), std::string::npos) << e.message;
}

TEST_F(MissionPointCheck, EngineRefusesAtSubmitWithTheSameWords) {
  NullSink sink;
  auto engine = Engine::create(world_, EngineOptions{}, sink, [] { return std::int64_t{1'800'000'000'000'000'000LL}; });
  ASSERT_TRUE(engine.ok()) << engine.error().describe();
  MissionRequestData r = request();
  const MissionPointData good = r.begin;
  r.begin = MissionPointData::wgs84(good.geo.lon_deg, good.geo.lat_deg, good.geo.alt_amsl_m);
  const auto refused = (*engine)->submit(r);
  ASSERT_TRUE(refused.has_value());
  EXPECT_EQ(refused->code, PlanErrorCode::kOutsideMap);
  EXPECT_EQ(refused->field, "begin");
  EXPECT_NE(refused->message.find("latitude and longitude may be swapped"), std::string::npos) << refused->message;
}

// A DEM with a void too large to fill: a point over it has "no elevation data here".
TEST(MissionPointCheckVoid, NodataCellIsNotOutsideTheTerrain) {
  constexpr int kSize = 40;
  std::vector<float> heights(kSize * kSize, 500.0f);
  for (int row = 15; row < 27; ++row)
    for (int col = 15; col < 27; ++col) heights[static_cast<std::size_t>(row) * kSize + col] = std::nanf("");
  auto dem = Dem::fromArray(kSize, kSize, heights, {500000.0, 100.0, 0.0, 5200000.0, 0.0, -100.0},
                            testing::epsgWkt(32633), "void");
  ASSERT_TRUE(dem.ok()) << dem.error().describe();
  auto terrain = Heightfield::build(*dem);
  ASSERT_TRUE(terrain.ok()) << terrain.error().describe();
  const GeoPoint over_void = (*terrain)->frame().toGeo(Eigen::Vector3d(0.0, 0.0, 800.0));
  const MissionPointData point = MissionPointData::wgs84(over_void.lat_deg, over_void.lon_deg, 800.0);
  const auto e = checkPointOnTerrain(**terrain, point, "points[1]");
  ASSERT_TRUE(e.has_value());
  EXPECT_EQ(e->code, PlanErrorCode::kOutsideMap);
  EXPECT_NE(e->message.find("no elevation data here"), std::string::npos) << e->message;
  EXPECT_EQ(e->message.find("outside"), std::string::npos) << e->message;
  EXPECT_NE(e->message.find("800 m AMSL"), std::string::npos) << e->message;
}

}  // namespace
}  // namespace skyroute
