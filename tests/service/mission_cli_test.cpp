// `skyroute mission` on a DEM with latitude/longitude points, run as a user would: the visiting
// order is the mission pipeline's order stage (called here directly with the daemon's default
// configuration), the cost matrix is in metres, the legs name their end points, --out files read
// back through OGR, and bad input is named with its option or file field and the table's code.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <memory>

#include <gdal_priv.h>
#include <nlohmann/json.hpp>
#include <ogrsf_frmts.h>

#include "service/daemon_config.hpp"
#include "service/mission_pipeline.hpp"
#include "tests/cli_run.hpp"
#include "tests/test_data.hpp"

namespace skyroute {
namespace {

namespace fs = std::filesystem;
using testing::runCli;

// Begin, three points and end over the embedded terrain (ground below 922 m AMSL).
const std::string kPoints =
    "--from 46.90,15.03,1100 --via '46.95,15.06,1150;46.92,15.10,1100;46.96,15.04,1200' --to 46.97,15.12,1100";

MissionRequestData demoMission() {
  MissionRequestData m;
  m.request_id = "uav-1-mission";
  m.vehicle_id = "uav-1";
  m.begin = MissionPointData::wgs84(46.90, 15.03, 1100);
  m.points = {MissionPointData::wgs84(46.95, 15.06, 1150), MissionPointData::wgs84(46.92, 15.10, 1100),
              MissionPointData::wgs84(46.96, 15.04, 1200)};
  m.end = MissionPointData::wgs84(46.97, 15.12, 1100);
  return m;
}

nlohmann::json lastJson(const std::string& text) { return nlohmann::json::parse(text.substr(text.rfind("\n{") + 1)); }

class MissionCli : public ::testing::Test {
 protected:
  void SetUp() override {
    const std::string test = ::testing::UnitTest::GetInstance()->current_test_info()->name();
    dir_ = fs::temp_directory_path() / ("skyroute_mission_cli_" + std::to_string(::getpid()) + "_" + test);
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }
  fs::path dir_;
};

TEST_F(MissionCli, OrderIsThePipelinesOrderStage) {
  const auto r = runCli("mission " + kPoints + " --json");
  ASSERT_EQ(r.exit_code, 0) << r.text;
  const nlohmann::json j = lastJson(r.text);

  const DaemonConfig config;
  auto world = WorldModel::load(testing::projectDataPath("default_terrain.tif"), config.world);
  ASSERT_TRUE(world.ok()) << world.error().describe();
  const MissionPipeline pipeline(*world, config.engine.pipeline);
  auto ordered = pipeline.order(demoMission(), static_cast<double>(utcNowNs()) * 1e-9);
  ASSERT_TRUE(ordered.ok()) << ordered.error().describe();
  EXPECT_EQ(j["order"].get<std::vector<int>>(), ordered->order);
  EXPECT_EQ(j["method"], ordered->ordering.method);
  EXPECT_EQ(j["method"], "mmdstar");
  EXPECT_NEAR(j["cost_m"].get<double>(), ordered->ordering.cost_m, 1e-6);
  EXPECT_EQ(j["expansions"].get<std::uint64_t>(), ordered->ordering.expansions);

  // The matrix in metres, and every leg: its end points as given, its cost from the matrix.
  const auto& matrix = j["cost_matrix_m"];
  ASSERT_EQ(matrix.size(), 5u);
  double sum = 0.0;
  ASSERT_EQ(j["legs"].size(), 4u);
  for (std::size_t k = 0; k < 4; ++k) {
    const auto& leg = j["legs"][k];
    const int from = leg["from_point"], to = leg["to_point"];
    EXPECT_EQ(from, ordered->order[k]);
    EXPECT_EQ(to, ordered->order[k + 1]);
    EXPECT_DOUBLE_EQ(leg["cost_m"].get<double>(), matrix[from][to].get<double>());
    EXPECT_DOUBLE_EQ(leg["cost_m"].get<double>(), ordered->ordering.cost_matrix_m[from][to]);
    EXPECT_GE(leg["cost_m"].get<double>(), 0.9 * leg["straight_m"].get<double>());
    sum += leg["cost_m"].get<double>();
  }
  EXPECT_NEAR(sum, j["cost_m"].get<double>(), 1e-6);
  EXPECT_DOUBLE_EQ(j["legs"][0]["from"]["lat_deg"].get<double>(), 46.90);
  EXPECT_DOUBLE_EQ(j["legs"][3]["to"]["alt_amsl_m"].get<double>(), 1100.0);

  // The text form says the same.
  const auto text = runCli("mission " + kPoints);
  ASSERT_EQ(text.exit_code, 0) << text.text;
  for (const char* shown : {"order       begin -> ", "method      mmdstar", "cost matrix, m", "leg 3 ", "46.970000,15.120000,1100.0"}) {
    EXPECT_NE(text.text.find(shown), std::string::npos) << shown << "\n" << text.text;
  }
}

TEST_F(MissionCli, FixedOrderAndTheMissionFile) {
  auto r = runCli("mission " + kPoints + " --fixed-order --json");
  ASSERT_EQ(r.exit_code, 0) << r.text;
  nlohmann::json j = lastJson(r.text);
  EXPECT_EQ(j["order"].get<std::vector<int>>(), (std::vector<int>{0, 1, 2, 3, 4}));
  EXPECT_EQ(j["method"], "fixed");
  EXPECT_TRUE(j["cost_matrix_m"].empty());
  // The demo mission (ENU points, its own limits): the order the daemon's order stage finds.
  r = runCli("mission --mission " + testing::projectDataPath("missions/demo_mission.json") + " --json");
  ASSERT_EQ(r.exit_code, 0) << r.text;
  j = lastJson(r.text);
  EXPECT_EQ(j["order"].size(), 4u);
  EXPECT_EQ(j["order"].front(), 0);
  EXPECT_EQ(j["order"].back(), 3);
}

TEST_F(MissionCli, OutWritesLegsOrPointsThatOgrReadsBack) {
  const auto reference = lastJson(runCli("mission " + kPoints + " --json").text);
  for (const std::string ext : {"csv", "geojson", "kml"}) {
    SCOPED_TRACE(ext);
    const fs::path legs = dir_ / ("legs." + ext), points = dir_ / ("points." + ext);
    ASSERT_EQ(runCli("mission " + kPoints + " --out " + legs.string()).exit_code, 0);
    ASSERT_EQ(runCli("mission " + kPoints + " --out " + points.string() + " --out-geometry points").exit_code, 0);
    GDALAllRegister();
    std::unique_ptr<GDALDataset> ds(static_cast<GDALDataset*>(GDALOpenEx(legs.c_str(), GDAL_OF_VECTOR, nullptr, nullptr, nullptr)));
    ASSERT_TRUE(ds);
    OGRLayer* layer = ds->GetLayer(0);
    ASSERT_EQ(layer->GetFeatureCount(), 4);
    int k = 0;
    for (auto& f : *layer) {
      const auto& leg = reference["legs"][k++];
      EXPECT_EQ(f->GetFieldAsInteger("from_point"), leg["from_point"].get<int>());
      EXPECT_EQ(f->GetFieldAsInteger("to_point"), leg["to_point"].get<int>());
      EXPECT_NEAR(f->GetFieldAsDouble("cost_m"), leg["cost_m"].get<double>(), 1e-6);
      EXPECT_NEAR(f->GetFieldAsDouble("to_lat_deg"), leg["to"]["lat_deg"].get<double>(), 1e-9);
      if (ext != "csv") {  // the CSV carries its geometry as WKT text
        const OGRLineString* line = f->GetGeometryRef()->toLineString();
        ASSERT_EQ(line->getNumPoints(), 2);
        EXPECT_NEAR(line->getX(0), leg["from"]["lon_deg"].get<double>(), 1e-8);
        EXPECT_NEAR(line->getY(1), leg["to"]["lat_deg"].get<double>(), 1e-8);
        // GeoJSON heights are above the ellipsoid (about 47 m above the geoid here), KML's AMSL.
        const double z = line->getZ(0) - leg["from"]["alt_amsl_m"].get<double>();
        EXPECT_NEAR(z, ext == "geojson" ? 47.0 : 0.0, 3.0);
      }
    }
    std::unique_ptr<GDALDataset> pts(static_cast<GDALDataset*>(GDALOpenEx(points.c_str(), GDAL_OF_VECTOR, nullptr, nullptr, nullptr)));
    ASSERT_TRUE(pts);
    EXPECT_EQ(pts->GetLayer(0)->GetFeatureCount(), 5);
  }
}

TEST_F(MissionCli, GridCellsOnTheDem) {
  const auto r = runCli("mission --cells --from 10,10 --via '60,20;20,60' --to 120,120 --json");
  ASSERT_EQ(r.exit_code, 0) << r.text;
  const nlohmann::json j = lastJson(r.text);
  EXPECT_EQ(j["order"].front(), "B");
  EXPECT_EQ(j["order"].back(), "E");
  EXPECT_DOUBLE_EQ(j["grid"]["cell_size_m"].get<double>(), 90.0);
}

TEST_F(MissionCli, BadInputIsNamedWithTheTablesCode) {
  std::ofstream(dir_ / "bad.json") << R"({"begin": {"lat_deg": 46.9, "lon_deg": 15.03, "alt_amsl_m": 1100},
                                          "end": {"lat_deg": 46.97, "lon_deg": 15.12}})";
  std::ofstream(dir_ / "under.json") << R"({"begin": {"lat_deg": 46.9, "lon_deg": 15.03, "alt_amsl_m": 1100},
                                            "points": [{"lat_deg": 46.95, "lon_deg": 15.06, "alt_amsl_m": 100}],
                                            "end": {"lat_deg": 46.97, "lon_deg": 15.12, "alt_amsl_m": 1100}})";
  struct Case {
    std::string args;
    int code;
    std::vector<std::string> named;
  };
  const std::vector<Case> cases{
      {"--from 46.90,15.03,1100 --via 46.95,15.06,100 --to 46.97,15.12,1100", 2, {"--via[0]", "ground"}},
      {"--from 46.90,15.03 --to 46.97,15.12,1100", 2, {"--from", "LAT,LON,ALT"}},
      {"--from 46.90,15.03,1100 --to 56.97,15.12,1100", 2, {"--to"}},
      {"--from 46.90,15.03,1100", 2, {"--from", "--to"}},
      {"--mission " + (dir_ / "bad.json").string(), 3, {"bad.json", "end.alt_amsl_m"}},
      {"--mission " + (dir_ / "under.json").string(), 3, {"under.json", "points[0]"}},
      {"--mission " + (dir_ / "under.json").string() + " --via 46.95,15.06,1150", 0, {}},
      {"--mission " + (dir_ / "missing.json").string(), 3, {"--mission", "missing.json"}},
      {kPoints + " --clearance-m -5", 2, {"--clearance-m"}},
      {kPoints + " --algo dstar-lite", 2, {"--algo", "cells"}},
      {kPoints + " --out " + (dir_ / "order.png").string(), 2, {"--out", ".png"}},
      {kPoints + " --out " + (dir_ / "nowhere" / "order.kml").string(), 2, {"--out", "does not exist"}},
      {kPoints + " --dem " + (dir_ / "missing.tif").string(), 3, {"--dem", "missing.tif"}},
      {"--cells --from 10,10 --to 20,20 --out " + (dir_ / "o.kml").string(), 2, {"--out"}},
  };
  for (const Case& c : cases) {
    SCOPED_TRACE(c.args);
    const auto r = runCli("mission " + c.args);
    EXPECT_EQ(r.exit_code, c.code) << r.text;
    for (const std::string& name : c.named) EXPECT_NE(r.text.find(name), std::string::npos) << r.text;
  }
}

}  // namespace
}  // namespace skyroute
