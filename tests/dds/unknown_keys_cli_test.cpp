// A misspelt key in any JSON a user gives the CLI is refused, naming the key, where it is and the
// known key it most likely misspells, with the exit code of an invalid input file (3): mission
// files (`skyroute plan --mission`), fleet files (`skyroute fleet --file`), no-fly zones
// (`--nofly`, GeoJSON: GeoJSON's own members and bbox, id, a CRS84 crs and a layer name are
// accepted) and obstacle feeds (`skyroute replay`, DDS domain 81: a data line with an unknown key
// is skipped and reported like any malformed line; one in the header is fatal). Before, each of
// these keys was ignored: "point" for "points" flew straight from begin to end with exit 0.
#include <filesystem>
#include <functional>
#include <fstream>
#include <string>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "service/dds/loopback.hpp"
#include "tests/cli_run.hpp"
#include "tests/test_data.hpp"

namespace skyroute {
namespace {

namespace fs = std::filesystem;
using nlohmann::json;

constexpr int kReplayDomain = 81;

class UnknownKeysCli : public ::testing::Test {
 protected:
  void SetUp() override {
    dds::useLoopbackOnly();  // inherited by `skyroute replay`
    dir_ = fs::temp_directory_path() / ("skyroute_unknown_keys_" + std::to_string(::getpid()) + "_" +
                                        ::testing::UnitTest::GetInstance()->current_test_info()->name());
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }

  std::string write(const std::string& name, const std::string& text) const {
    const std::string path = (dir_ / name).string();
    std::ofstream(path) << text;
    return path;
  }
  static json readJson(const std::string& path) {
    std::ifstream in(path);
    return json::parse(in);
  }
  // The shipped demo mission with one change.
  std::string demoMissionWith(const std::string& name, const std::function<void(json&)>& change) const {
    json mission = readJson(testing::projectDataPath("missions/demo_mission.json"));
    change(mission);
    return write(name, mission.dump(2));
  }
  static void expectRefused(const testing::CliOutput& out, const std::string& message) {
    EXPECT_EQ(out.exit_code, 3) << out.text;
    EXPECT_NE(out.text.find(message), std::string::npos) << out.text;
  }

  fs::path dir_;
};

// The issue's case: "point" for "points". It used to plan begin -> end and exit 0.
TEST_F(UnknownKeysCli, AMissionFileWithPointForPointsIsRefused) {
  const std::string file = demoMissionWith("point.json", [](json& m) {
    m["point"] = m["points"];
    m.erase("points");
  });
  const auto out = testing::runCli("plan --mission " + file);
  expectRefused(out, "--mission " + file + ": unknown key \"point\" in mission (did you mean \"points\"?)");
  EXPECT_EQ(out.text.find("trajectory"), std::string::npos) << out.text;  // refused before any planning
}

TEST_F(UnknownKeysCli, EveryLevelOfAMissionFileNamesTheKeyWhereItIsAndTheClosestKnownKey) {
  struct Case {
    const char* file;
    std::function<void(json&)> change;
    const char* message;
  };
  const Case cases[] = {
      {"vehicle_id.json", [](json& m) { m["vehicleId"] = "uav-x"; m.erase("vehicle_id"); },
       "unknown key \"vehicleId\" in mission (did you mean \"vehicle_id\"?)"},
      {"fixed_order.json", [](json& m) { m["fixed_ordr"] = true; m.erase("fixed_order"); },
       "unknown key \"fixed_ordr\" in mission (did you mean \"fixed_order\"?)"},
      {"limits.json", [](json& m) { m["limits"]["max_sped_mps"] = 30; },
       "unknown key \"max_sped_mps\" in limits (did you mean \"max_speed_mps\"?)"},
      {"point_key.json", [](json& m) { m["points"][1]["up"] = 800; },
       "unknown key \"up\" in points[1] (did you mean \"up_m\"?)"},
      {"begin_key.json", [](json& m) { m["begin"]["nrth_m"] = 1; },
       "unknown key \"nrth_m\" in begin (did you mean \"north_m\"?)"},
      // Nothing close: the known keys are listed instead.
      {"far.json", [](json& m) { m["comment"] = "mine"; },
       "unknown key \"comment\" in mission (known keys: request_id, vehicle_id, begin, points, end, limits, "
       "planner, fixed_order, height_ref)"},
      // Both frames in one point: one of them would be ignored.
      {"mixed.json", [](json& m) { m["end"]["lat_deg"] = 46.9; },
       "end mixes lat_deg/lon_deg/alt_amsl_m with east_m/north_m/up_m (give one of the two)"},
  };
  for (const Case& c : cases) {
    const std::string file = demoMissionWith(c.file, c.change);
    expectRefused(testing::runCli("mission --mission " + file), c.message);
  }
  // The mission file's own height_ref is a known key.
  const std::string with_height_ref = demoMissionWith("height_ref.json", [](json& m) { m["height_ref"] = "amsl"; });
  const auto ordered = testing::runCli("mission --mission " + with_height_ref);
  EXPECT_EQ(ordered.exit_code, 0) << ordered.text;
}

TEST_F(UnknownKeysCli, AFleetFileWithAMisspeltKeyIsRefused) {
  json fleet = readJson(testing::projectDataPath("missions/demo_fleet.json"));
  fleet["vehicle_id"] = fleet["vehicle_ids"];
  fleet.erase("vehicle_ids");
  const std::string file = write("fleet.json", fleet.dump());
  expectRefused(testing::runCli("fleet --file " + file),
                "--file " + file + ": unknown key \"vehicle_id\" in fleet (did you mean \"vehicle_ids\"?)");
  // A fleet file has no height_ref: it was ignored, and the heights read as AMSL whatever it said.
  json with_height_ref = readJson(testing::projectDataPath("missions/demo_fleet.json"));
  with_height_ref["height_ref"] = "ellipsoid";
  const std::string ellipsoid = write("fleet_height_ref.json", with_height_ref.dump());
  expectRefused(testing::runCli("fleet --file " + ellipsoid), "unknown key \"height_ref\" in fleet");
}

// A zone file: our properties, GeoJSON's members; a zone away from the route.
json zoneFile() {
  return json::parse(R"({"type": "FeatureCollection", "features": [{"type": "Feature", "id": "tower",
    "bbox": [15.14, 46.89, 15.15, 46.90],
    "geometry": {"type": "Polygon", "bbox": [15.14, 46.89, 15.15, 46.90],
                 "coordinates": [[[15.14, 46.89], [15.15, 46.89], [15.15, 46.90], [15.14, 46.90], [15.14, 46.89]]]},
    "properties": {"name": "tower", "floor_m": 0, "ceiling_m": 3000, "valid_until": "2100-01-01T00:00:00Z"}}]})");
}

TEST_F(UnknownKeysCli, ANoFlyZoneFileRefusesAnUnknownMemberAndTakesGeoJsonsOwn) {
  const std::string plan = "plan --from 46.93,15.10,1000 --to 46.935,15.105,1000 --nofly ";
  // GeoJSON's bbox and id, a layer name and a CRS84 crs (as GDAL and QGIS write them) are taken.
  json accepted = zoneFile();
  accepted["bbox"] = {15.14, 46.89, 15.15, 46.90};
  accepted["name"] = "zones";
  accepted["crs"] = {{"type", "name"}, {"properties", {{"name", "urn:ogc:def:crs:OGC:1.3:CRS84"}}}};
  const auto ok = testing::runCli(plan + write("accepted.geojson", accepted.dump()));
  EXPECT_EQ(ok.exit_code, 0) << ok.text;
  EXPECT_NE(ok.text.find("no-fly zones: 1 in force"), std::string::npos) << ok.text;

  struct Case {
    const char* file;
    std::function<void(json&)> change;
    const char* message;
  };
  const Case cases[] = {
      // A zone meant to lapse: it was in force for ever.
      {"valid_until.geojson",
       [](json& z) {
         auto& p = z["features"][0]["properties"];
         p["valid_untill"] = p["valid_until"];
         p.erase("valid_until");
       },
       "features[0] 'tower': unknown key \"valid_untill\" in features[0].properties (did you mean \"valid_until\"?)"},
      // A floor: the zone reached down to the ground.
      {"floor.geojson", [](json& z) { z["features"][0]["properties"]["floor"] = 900; },
       "unknown key \"floor\" in features[0].properties (did you mean \"floor_m\"?)"},
      {"feature.geojson", [](json& z) { z["features"][0]["geometri"] = z["features"][0]["geometry"]; },
       "unknown key \"geometri\" in features[0] (did you mean \"geometry\"?)"},
      {"geometry.geojson", [](json& z) { z["features"][0]["geometry"]["crs"] = "EPSG:4326"; },
       "unknown key \"crs\" in features[0].geometry (known keys: type, coordinates, bbox)"},
      {"collection.geojson", [](json& z) { z["featuress"] = json::array(); },
       "geojson: unknown key \"featuress\" in the FeatureCollection (did you mean \"features\"?)"},
      // GeoJSON's type members that are not text (each ended the CLI with an uncaught exception).
      {"type.geojson", [](json& z) { z["type"] = 1; },
       "geojson: must be a FeatureCollection with a features array (or a single Feature)"},
      {"geometry_type.geojson", [](json& z) { z["features"][0]["geometry"]["type"] = 7; },
       "features[0] 'tower': geometry type '7' is not a Polygon or MultiPolygon"},
      // Coordinates in another CRS would be read as degrees.
      {"crs.geojson",
       [](json& z) { z["crs"] = {{"type", "name"}, {"properties", {{"name", "urn:ogc:def:crs:EPSG::32633"}}}}; },
       "is not WGS84 longitude, latitude (CRS84)"},
  };
  for (const Case& c : cases) {
    json zones = zoneFile();
    c.change(zones);
    const std::string file = write(c.file, zones.dump());
    const auto out = testing::runCli(plan + file);
    expectRefused(out, c.message);
    EXPECT_NE(out.text.find("--nofly " + file + ": "), std::string::npos) << out.text;
  }
}

TEST_F(UnknownKeysCli, AFeedLineWithAnUnknownKeyIsSkippedNamingItAndAnUnknownHeaderKeyIsFatal) {
  const std::string header = R"({"format":"skyroute-obstacle-feed","version":1})";
  const std::string good = R"({"t_s":0,"obstacle":{"id":1,"shape":"sphere","size_m":[100,0,0],"position_m":[0,0,900]}})";
  // Meant to lapse after a minute: it stayed until removed.
  const std::string valid_for =
      R"({"t_s":0,"obstacle":{"id":2,"shape":"sphere","size_m":[100,0,0],"position_m":[0,0,900]},"valid_for":60})";
  // Meant to move: it stood still.
  const std::string motion =
      R"({"t_s":0,"obstacle":{"id":3,"shape":"sphere","size_m":[100,0,0],"position_m":[0,0,900],"moton":"constant_velocity","velocity_mps":[5,0,0]}})";
  const std::string velocity_without_motion =
      R"({"t_s":0,"obstacle":{"id":4,"shape":"sphere","size_m":[100,0,0],"position_m":[0,0,900],"velocity_mps":[5,0,0]}})";
  const std::string feed = write("feed.jsonl", header + "\n" + good + "\n" + valid_for + "\n" + motion + "\n" +
                                                   velocity_without_motion + "\n");
  const auto out = testing::runCli("replay " + feed + " --domain " + std::to_string(kReplayDomain));
  EXPECT_EQ(out.exit_code, 0) << out.text;  // the valid line is published
  EXPECT_NE(out.text.find("published 1 obstacle updates"), std::string::npos) << out.text;
  for (const std::string& line :
       {feed + ":3: unknown key \"valid_for\" in update (did you mean \"valid_for_s\"?) (line skipped)",
        feed + ":4: unknown key \"moton\" in obstacle (did you mean \"motion\"?) (line skipped)",
        feed + ":5: obstacle.velocity_mps applies to motion constant_velocity only (motion is static) (line skipped)"}) {
    EXPECT_NE(out.text.find(line), std::string::npos) << line << "\n" << out.text;
  }

  const std::string bad_header = write("header.jsonl", R"({"format":"skyroute-obstacle-feed","version":1,"verison":2})"
                                                       "\n" + good + "\n");
  expectRefused(testing::runCli("replay " + bad_header + " --domain " + std::to_string(kReplayDomain)),
                bad_header + ":1: unknown key \"verison\" in header (did you mean \"version\"?)");
}

}  // namespace
}  // namespace skyroute
