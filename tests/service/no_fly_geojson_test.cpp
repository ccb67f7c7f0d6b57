// GeoJSON no-fly zones: features into ENU zones and back to WGS84, heights AMSL on the frame's up
// axis, time windows, and errors that name the feature.
#include <cmath>
#include <filesystem>
#include <fstream>
#include <string>

#include <gtest/gtest.h>

#include "service/no_fly_geojson.hpp"
#include "service/qgc_plan.hpp"

namespace skyroute {
namespace {

LocalFrame frame(double anchor_alt_m = 0.0) { return LocalFrame::create(46.5, 7.5, anchor_alt_m).value(); }

std::string collection(const std::string& features) {
  return R"({"type": "FeatureCollection", "features": [)" + features + "]}";
}

std::string polygonFeature(const std::string& id, const std::string& ring, const std::string& props) {
  return R"({"type": "Feature", "id": ")" + id + R"(", "properties": {)" + props +
         R"(}, "geometry": {"type": "Polygon", "coordinates": [)" + ring + "]}}";
}

const char* kSquareRing = "[[7.50, 46.50], [7.51, 46.50], [7.51, 46.51], [7.50, 46.51], [7.50, 46.50]]";

TEST(NoFlyGeoJson, PolygonsBecomeZonesThatRoundTripToWgs84) {
  const LocalFrame f = frame(100.0);
  const std::string multi = R"({"type": "Feature", "properties": {"name": "range", "floor_m": 0, "ceiling_m": 800},
      "geometry": {"type": "MultiPolygon", "coordinates": [
        [[[7.52, 46.52], [7.53, 46.52], [7.525, 46.53], [7.52, 46.52]]],
        [[[7.54, 46.52], [7.55, 46.52], [7.545, 46.53]]]]}})";
  auto zones = parseNoFlyGeoJson(
      collection(polygonFeature("tower", kSquareRing, R"("floor_m": 300, "ceiling_m": 1200)") + "," + multi), f);
  ASSERT_TRUE(zones.ok()) << zones.error().describe();
  ASSERT_EQ(zones->size(), 3u);
  const NoFlyZone& tower = (*zones)[0];
  EXPECT_EQ(tower.name, "tower");
  EXPECT_EQ(tower.ring_m.size(), 4u);  // the closing vertex is dropped
  EXPECT_DOUBLE_EQ(tower.floor_m, 200.0);  // AMSL less the anchor's 100 m
  EXPECT_DOUBLE_EQ(tower.ceiling_m, 1100.0);
  EXPECT_FALSE(tower.valid_from_s || tower.valid_until_s);
  // The anchor is the square's south-west corner; 0.01 degree east is about 766 m at 46.5 N.
  EXPECT_NEAR(tower.ring_m[0].norm(), 0.0, 1e-6);
  EXPECT_NEAR(tower.ring_m[1].x(), 0.01 * M_PI / 180.0 * 6388838.0 * std::cos(46.5 * M_PI / 180.0), 3.0);
  const auto back = geofencePolygons({tower}, f).front().ring;
  const double expected[4][2] = {{46.50, 7.50}, {46.50, 7.51}, {46.51, 7.51}, {46.51, 7.50}};
  for (int i = 0; i < 4; ++i) {
    EXPECT_NEAR(back[i].lat_deg, expected[i][0], 1e-7);
    EXPECT_NEAR(back[i].lon_deg, expected[i][1], 1e-7);
  }
  EXPECT_EQ((*zones)[1].name, "range polygon 0");
  EXPECT_EQ((*zones)[2].name, "range polygon 1");
  EXPECT_EQ((*zones)[2].ring_m.size(), 3u);  // an unclosed ring is taken as it is
}

TEST(NoFlyGeoJson, ValidityWindowFromNumbersOrIsoTimes) {
  auto zones = parseNoFlyGeoJson(
      collection(polygonFeature("a", kSquareRing,
                                R"("ceiling_m": 500, "valid_from": "2026-11-25T14:00:00Z",
                                   "valid_until": "2026-11-25T15:30:30.5Z")") +
                 "," + polygonFeature("b", kSquareRing, R"("ceiling_m": 500, "valid_until": 1800000000)")),
      frame());
  ASSERT_TRUE(zones.ok()) << zones.error().describe();
  EXPECT_DOUBLE_EQ(*(*zones)[0].valid_from_s, 1795615200.0);  // date -u -d 2026-11-25T14:00:00Z +%s
  EXPECT_DOUBLE_EQ(*(*zones)[0].valid_until_s, 1795615200.0 + 5430.5);
  EXPECT_DOUBLE_EQ((*zones)[0].floor_m, -1000.0);  // no floor: from the ground up
  EXPECT_FALSE((*zones)[1].valid_from_s);
  EXPECT_DOUBLE_EQ(*(*zones)[1].valid_until_s, 1800000000.0);
}

// The error for a collection whose second feature is `bad`.
Error secondFeatureError(const std::string& bad) {
  auto zones = parseNoFlyGeoJson(
      collection(polygonFeature("fine", kSquareRing, R"("ceiling_m": 500)") + "," + bad), frame());
  EXPECT_FALSE(zones.ok());
  return zones.ok() ? Error{} : zones.error();
}

TEST(NoFlyGeoJson, BadGeometryNamesTheFeature) {
  Error e = secondFeatureError(polygonFeature("two", "[[7.5, 46.5], [7.51, 46.5], [7.5, 46.5]]", R"("ceiling_m": 5)"));
  EXPECT_EQ(e.field, "features[1] 'two'");
  EXPECT_NE(e.message.find("at least 3"), std::string::npos) << e.message;

  e = secondFeatureError(
      polygonFeature("bow", "[[7.5, 46.5], [7.51, 46.51], [7.51, 46.5], [7.5, 46.51], [7.5, 46.5]]", R"("ceiling_m": 5)"));
  EXPECT_EQ(e.field, "features[1] 'bow'");
  EXPECT_NE(e.message.find("self-intersection"), std::string::npos) << e.message;

  e = secondFeatureError(polygonFeature("nan", R"([[7.5, 46.5], ["NaN", 46.5], [7.5, 46.51]])", R"("ceiling_m": 5)"));
  EXPECT_EQ(e.field, "features[1] 'nan'");
  EXPECT_NE(e.message.find("vertex 1 is not a finite longitude, latitude (NaN)"), std::string::npos) << e.message;

  e = secondFeatureError(polygonFeature("null", "[[7.5, 46.5], [7.51, null], [7.5, 46.51]]", R"("ceiling_m": 5)"));
  EXPECT_NE(e.message.find("NaN"), std::string::npos) << e.message;

  e = secondFeatureError(polygonFeature("swapped", "[[46.5, 7.5], [46.5, 97.51], [46.51, 7.5]]", R"("ceiling_m": 5)"));
  EXPECT_NE(e.message.find("out of range"), std::string::npos) << e.message;

  e = secondFeatureError(polygonFeature("upside", kSquareRing, R"("floor_m": 900, "ceiling_m": 500)"));
  EXPECT_EQ(e.field, "features[1] 'upside'");
  EXPECT_NE(e.message.find("above ceiling_m"), std::string::npos) << e.message;

  e = secondFeatureError(polygonFeature("open", kSquareRing, R"("floor_m": 0)"));
  EXPECT_NE(e.message.find("ceiling_m"), std::string::npos) << e.message;

  e = secondFeatureError(R"({"type": "Feature", "properties": {"ceiling_m": 5},
                             "geometry": {"type": "LineString", "coordinates": [[7.5, 46.5], [7.6, 46.6]]}})");
  EXPECT_EQ(e.field, "features[1]");
  EXPECT_NE(e.message.find("LineString"), std::string::npos) << e.message;
}

TEST(NoFlyGeoJson, FileErrorsNameTheFile) {
  EXPECT_EQ(loadNoFlyGeoJson("/nonexistent/zones.geojson", frame()).error().code, ErrorCode::kFileNotFound);
  const std::string path = (std::filesystem::path(::testing::TempDir()) / "skyroute_no_fly_bad.geojson").string();
  std::ofstream(path) << R"({"type": "FeatureCollection")";
  auto zones = loadNoFlyGeoJson(path, frame());
  ASSERT_FALSE(zones.ok());
  EXPECT_NE(zones.error().describe().find(path), std::string::npos) << zones.error().describe();
  std::filesystem::remove(path);
}

}  // namespace
}  // namespace skyroute
