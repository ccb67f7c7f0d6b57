// `--nofly FILE.geojson` and the configuration's terrain.nofly, run as a user would on the embedded
// terrain: the plan flies round the zone, its QGroundControl .plan carries the zone as an exclusion
// polygon, a point inside a zone and a bad file are refused naming the point, zone, file and feature;
// a ring beyond the vertex bound is refused at once by `plan` and `nofly` alike, one at the bound
// is planned round; zones off the DEM, written [lat, lon], or of zero area are refused.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <string>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "tests/cli_run.hpp"
#include "tests/test_data.hpp"
#include "tests/test_folder.hpp"
#include "tests/text_file.hpp"

namespace {

using skyroute::testing::runCli;

// The CLI as runCli runs it, ended by coreutils' timeout after `limit_s` (exit 124): a check that
// never ends fails the test instead of hanging it. The limit is far beyond what the commands take.
skyroute::testing::CliOutput runCliWithin(double limit_s, const std::string& args) {
  return skyroute::testing::runCommand("timeout " + std::to_string(limit_s) + " " + std::string(SKYROUTE_CLI) + " " +
                                       args);
}

// A ring of n positions (closed: the first repeated) on a circle round (lon, lat), radius in
// degrees of latitude.
std::string circleRing(std::size_t n, double lon, double lat, double radius_deg) {
  std::string ring = "[";
  for (std::size_t i = 0; i <= n; ++i) {
    const double a = 2.0 * M_PI * static_cast<double>(i % n) / static_cast<double>(n);
    const double x = lon + radius_deg * std::cos(a) / std::cos(lat * M_PI / 180.0);
    const double y = lat + radius_deg * std::sin(a);
    char buf[64];
    std::snprintf(buf, sizeof buf, "%s[%.9f, %.9f]", i == 0 ? "" : ", ", x, y);
    ring += buf;
  }
  return ring + "]";
}

// The zone: a latitude/longitude box across the straight line from --from to --to.
constexpr double kSouth = 46.930, kNorth = 46.940, kWest = 15.068, kEast = 15.082;

std::string zonesGeoJson(const std::string& ring) {
  return R"({"type": "FeatureCollection", "features": [{"type": "Feature", "id": "tower",
    "properties": {"floor_m": 0, "ceiling_m": 4000}, "geometry": {"type": "Polygon", "coordinates": [)" +
         ring + "]}}]}";
}

std::string boxRing() {
  auto v = [](double lon, double lat) { return "[" + std::to_string(lon) + ", " + std::to_string(lat) + "]"; };
  return "[" + v(kWest, kSouth) + ", " + v(kEast, kSouth) + ", " + v(kEast, kNorth) + ", " + v(kWest, kNorth) + ", " +
         v(kWest, kSouth) + "]";
}

class NoFlyCli : public skyroute::testing::TestFolderTest {
 protected:
  NoFlyCli() : TestFolderTest("skyroute_no_fly_cli_test_") {}

  std::string write(const std::string& name, const std::string& text) const {
    const std::string path = (dir_ / name).string();
    std::ofstream(path) << text;
    return path;
  }
  static std::string planArgs(const std::string& via = "") {
    return "plan --dem " + skyroute::testing::projectDataPath("default_terrain.tif") +
           " --from 46.90,15.03,1100 --to 46.97,15.12,1100" + (via.empty() ? "" : " --via " + via) +
           " --iterations 1500 --budget-s 0";
  }
};

TEST_F(NoFlyCli, PlanGoesRoundTheZoneAndItsPlanExcludesIt) {
  const std::string zones = write("zones.geojson", zonesGeoJson(boxRing()));
  const std::string plan_path = (dir_ / "mission.plan").string();
  const auto r = runCli(planArgs() + " --nofly " + zones + " --out " + plan_path);
  ASSERT_EQ(r.exit_code, 0) << r.text;
  EXPECT_NE(r.text.find("no-fly zones: 1 in force"), std::string::npos) << r.text;
  // The daemon's audit ran on what was written, in the same pipeline (docs/dds.md).
  EXPECT_NE(r.text.find("audit: passed (1 trajectory audited: samples every 0.05 s against the DEM, the ceiling, 1 "
                        "no-fly zones"),
            std::string::npos)
      << r.text;
  const nlohmann::json plan = nlohmann::json::parse(skyroute::testing::readTextFile(plan_path), nullptr, false);
  ASSERT_FALSE(plan.is_discarded());
  const auto& polygons = plan["geoFence"]["polygons"];
  ASSERT_EQ(polygons.size(), 1u);
  EXPECT_EQ(polygons[0]["inclusion"], false);
  const auto& ring = polygons[0]["polygon"];
  ASSERT_EQ(ring.size(), 4u);  // open, as QGroundControl writes them
  const double expected[4][2] = {{kSouth, kWest}, {kSouth, kEast}, {kNorth, kEast}, {kNorth, kWest}};
  for (int i = 0; i < 4; ++i) {
    EXPECT_NEAR(ring[i][0].get<double>(), expected[i][0], 1e-7) << i;
    EXPECT_NEAR(ring[i][1].get<double>(), expected[i][1], 1e-7) << i;
  }
  // The lines the autopilot flies between items stay out of the box (they are within 5 m of the
  // trajectory, which keeps the 5 m vehicle sphere out): sampled every ~0.5 m.
  const auto& items = plan["mission"]["items"];
  ASSERT_GE(items.size(), 2u);
  bool went_round = false;
  for (std::size_t k = 1; k < items.size(); ++k) {
    const double lat0 = items[k - 1]["params"][4], lon0 = items[k - 1]["params"][5];
    const double lat1 = items[k]["params"][4], lon1 = items[k]["params"][5];
    const int steps = 20000;
    for (int s = 0; s <= steps; ++s) {
      const double f = static_cast<double>(s) / steps;
      const double lat = lat0 + f * (lat1 - lat0), lon = lon0 + f * (lon1 - lon0);
      ASSERT_FALSE(lat > kSouth && lat < kNorth && lon > kWest && lon < kEast)
          << "item line " << k << " enters the zone at " << lat << ", " << lon;
    }
    went_round = went_round || items.size() > 2;
  }
  EXPECT_TRUE(went_round) << "a straight --from/--to line crosses the zone: the plan needs a detour vertex";
}

TEST_F(NoFlyCli, PointInsideAZoneNamesThePointAndTheZone) {
  const std::string zones = write("zones.geojson", zonesGeoJson(boxRing()));
  const auto r = runCli(planArgs("46.935,15.075,1150") + " --nofly " + zones);
  EXPECT_EQ(r.exit_code, 2) << r.text;  // a point of the command line, as one under the ground
  EXPECT_NE(r.text.find("--via[0]: points[0] (46.935, 15.075, 1150 m AMSL)"), std::string::npos) << r.text;
  EXPECT_NE(r.text.find("is inside no-fly zone 'tower'"), std::string::npos) << r.text;

  // The same from the configuration's terrain.nofly.
  const std::string config = write("skyrouted.toml", "[terrain]\nnofly = \"" + zones + "\"\n");
  const auto c = runCli(planArgs("46.935,15.075,1150") + " --config " + config);
  EXPECT_EQ(c.exit_code, 2) << c.text;
  EXPECT_NE(c.text.find("is inside no-fly zone 'tower'"), std::string::npos) << c.text;
  const auto printed = runCli("plan --config " + config + " --print-config");
  EXPECT_NE(printed.text.find("nofly = \"" + zones + "\""), std::string::npos) << printed.text;
}

TEST_F(NoFlyCli, BadZoneFileNamesTheFileAndTheFeature) {
  const std::string bow = write("bow.geojson", zonesGeoJson("[[15.07, 46.93], [15.08, 46.94], [15.08, 46.93], [15.07, 46.94]]"));
  const auto r = runCli(planArgs() + " --nofly " + bow);
  EXPECT_EQ(r.exit_code, 3) << r.text;
  EXPECT_NE(r.text.find("--nofly " + bow + ": features[0] 'tower'"), std::string::npos) << r.text;
  EXPECT_NE(r.text.find("self-intersection"), std::string::npos) << r.text;
  const auto missing = runCli("mission --nofly " + (dir_ / "none.geojson").string() +
                              " --from 46.90,15.03,1100 --to 46.97,15.12,1100");
  EXPECT_EQ(missing.exit_code, 3) << missing.text;
  EXPECT_NE(missing.text.find("none.geojson"), std::string::npos) << missing.text;
}

TEST_F(NoFlyCli, PublisherAndGroundStationCheckTheFileBeforeAnyDds) {
  const std::string upside = write("upside.geojson", zonesGeoJson(boxRing()).replace(
      zonesGeoJson(boxRing()).find(R"("floor_m": 0)"), 12, R"("floor_m": 5000)"));
  // Domain 0 is never opened: both fail on the file first.
  const auto nofly = runCli("nofly " + upside + " --domain 0 --hold 1");
  EXPECT_EQ(nofly.exit_code, 3) << nofly.text;
  EXPECT_NE(nofly.text.find("FILE " + upside + ": features[0] 'tower': floor_m 5000 is above ceiling_m 4000"),
            std::string::npos)
      << nofly.text;
  const auto gcs = runCli("gcs --domain 0 --timeout 1 --plan " + (dir_ / "plans").string() + " --nofly " + upside);
  EXPECT_EQ(gcs.exit_code, 3) << gcs.text;
  EXPECT_NE(gcs.text.find("--nofly " + upside + ": features[0] 'tower'"), std::string::npos) << gcs.text;
  EXPECT_EQ(runCli("nofly --domain 0").exit_code, 2);
  EXPECT_EQ(runCli("nofly --lift tower --domain 0 --hold -1").exit_code, 2);
  EXPECT_EQ(runCli("nofly --lift tower --domain 0 --hold soon").exit_code, 2);
  EXPECT_EQ(runCli("gcs --domain 0 --timeout 1 --nofly " + upside).exit_code, 2);  // no --plan to write it into
}

TEST_F(NoFlyCli, RingBeyondTheVertexBoundIsRefusedAtOnceByPlanAndNofly) {
  // 150,000 vertices: counted before anything else (the ring was checked pair by pair, for more
  // than 300 s, before it was published or planned round).
  const std::string huge = write("huge.geojson", zonesGeoJson(circleRing(150000, 15.075, 46.935, 0.004)));
  const auto plan = runCliWithin(120, planArgs() + " --nofly " + huge);
  EXPECT_EQ(plan.exit_code, 3) << plan.text.substr(0, 2000);
  EXPECT_NE(plan.text.find("--nofly " + huge + ": features[0] 'tower': ring has 150000 vertices, more than the 10000 "
                           "a zone may have"),
            std::string::npos)
      << plan.text.substr(0, 2000);
  const auto nofly = runCliWithin(120, "nofly " + huge + " --domain 0");  // domain 0 is never opened
  EXPECT_EQ(nofly.exit_code, 3) << nofly.text.substr(0, 2000);
  EXPECT_NE(nofly.text.find("FILE " + huge + ": features[0] 'tower': ring has 150000 vertices"), std::string::npos)
      << nofly.text.substr(0, 2000);
}

TEST_F(NoFlyCli, RingAtTheVertexBoundIsPlannedRound) {
  // 10,000 vertices on a circle round the middle of the straight line from --from to --to.
  const std::string round = write("round.geojson", zonesGeoJson(circleRing(10000, 15.075, 46.935, 0.003)));
  const auto r = runCliWithin(600, planArgs() + " --nofly " + round);
  ASSERT_EQ(r.exit_code, 0) << r.text;
  EXPECT_NE(r.text.find("no-fly zones: 1 in force"), std::string::npos) << r.text;
}

TEST_F(NoFlyCli, ZonesOffTheDemSwappedOrFlatAreRefusedNamingTheFeature) {
  auto v = [](double lon, double lat) { return "[" + std::to_string(lon) + ", " + std::to_string(lat) + "]"; };
  // The box of the other tests written [lat, lon]: on the DEM only with the two exchanged.
  const std::string swapped = write("swapped.geojson", zonesGeoJson("[" + v(kSouth, kWest) + ", " + v(kSouth, kEast) +
                                                                    ", " + v(kNorth, kEast) + ", " + v(kNorth, kWest) +
                                                                    ", " + v(kSouth, kWest) + "]"));
  auto r = runCli(planArgs() + " --nofly " + swapped);
  EXPECT_EQ(r.exit_code, 3) << r.text;
  EXPECT_NE(r.text.find("--nofly " + swapped + ": features[0] 'tower': lies outside the DEM, but on it with latitude "
                        "and longitude exchanged: latitude and longitude may be swapped"),
            std::string::npos)
      << r.text;
  EXPECT_EQ(r.text.find("in force"), std::string::npos) << r.text;
  // A box a degree east of the DEM.
  const std::string off = write("off.geojson", zonesGeoJson("[" + v(16.0, 46.93) + ", " + v(16.01, 46.93) + ", " +
                                                            v(16.01, 46.94) + ", " + v(16.0, 46.94) + "]"));
  r = runCli(planArgs() + " --nofly " + off);
  EXPECT_EQ(r.exit_code, 3) << r.text;
  EXPECT_NE(r.text.find("--nofly " + off + ": features[0] 'tower': lies entirely outside the DEM (lat "),
            std::string::npos)
      << r.text;
  // Three vertices on one parallel: collinear in latitude and longitude, a sliver in metres.
  const std::string flat = write("flat.geojson", zonesGeoJson("[" + v(15.07, 46.93) + ", " + v(15.08, 46.93) + ", " +
                                                              v(15.09, 46.93) + "]"));
  r = runCli(planArgs() + " --nofly " + flat);
  EXPECT_EQ(r.exit_code, 3) << r.text;
  EXPECT_NE(r.text.find("--nofly " + flat + ": features[0] 'tower': has (nearly) zero area"), std::string::npos)
      << r.text;
  // The same refusals from the configuration's terrain.nofly.
  const std::string config = write("swapped.toml", "[terrain]\nnofly = \"" + swapped + "\"\n");
  r = runCli("mission --config " + config + " --from 46.90,15.03,1100 --to 46.97,15.12,1100");
  EXPECT_EQ(r.exit_code, 3) << r.text;
  EXPECT_NE(r.text.find("latitude and longitude may be swapped"), std::string::npos) << r.text;
}

}  // namespace
