// `skyroute fleet` end to end. On a grid (--map): the JSON of --out in the documented shape and
// checked here on its own (one entry per step, legal moves, no two vehicles in one cell or
// swapping, every task on its vehicle's path), the PNG readable with one colour per vehicle. On the
// embedded DEM with lat/lon points: the trajectories the mission pipeline's fleet stage gives, in
// the formats of `skyroute gcs`. Bad input refused with a message naming the option and item, or
// the file and field, and the exit code of the one table.
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <memory>
#include <tuple>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <map>
#include <set>
#include <sstream>
#include <string>

#include <gdal_priv.h>
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>
#include <ogrsf_frmts.h>

#include "service/daemon_config.hpp"
#include "service/mission_json.hpp"
#include "service/mission_pipeline.hpp"
#include "service/trajectory_export.hpp"
#include "tests/test_data.hpp"

namespace {

namespace fs = std::filesystem;

std::string slurp(const fs::path& p) {
  std::ifstream f(p);
  std::stringstream s;
  s << f.rdbuf();
  return s.str();
}

struct CliRun {
  int code = -1;
  std::string out;
  std::string err;
};

class FleetCli : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() / ("skyroute_fleet_cli_" + std::to_string(::getpid()) + "_" +
                                        ::testing::UnitTest::GetInstance()->current_test_info()->name());
    fs::create_directories(dir_);
    // The paper's 5 x 5 example with its conflict at (C,1) (seed 002, Fig. 3).
    std::ofstream map(dir_ / "five.map");
    map << "type octile\nheight 5\nwidth 5\nmap\n"
        << "@@.@@\n.....\n@@.@.\n@@.@.\n@@.@@\n";
  }
  void TearDown() override { fs::remove_all(dir_); }

  CliRun run(const std::string& args) const {
    const fs::path out = dir_ / "stdout.txt";
    const fs::path err = dir_ / "stderr.txt";
    const std::string cmd = std::string(SKYROUTE_CLI) + " fleet " + args + " >" + out.string() + " 2>" + err.string();
    const int status = std::system(cmd.c_str());
    CliRun r;
    r.code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
    r.out = slurp(out);
    r.err = slurp(err);
    return r;
  }
  std::string map() const { return (dir_ / "five.map").string(); }

  fs::path dir_;
};

TEST_F(FleetCli, WritesAConflictFreePlanAsJsonAndPng) {
  const std::string json_path = (dir_ / "plan.json").string();
  const std::string png_path = (dir_ / "plan.png").string();
  const CliRun r = run("--map " + map() + " --vehicles '1,1;2,0' --tasks '4,1;4,3;2,3;2,4' --out " + json_path +
                    " --png " + png_path);
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_NE(r.out.find("makespan 10"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("conflict-free: yes"), std::string::npos) << r.out;

  std::ifstream f(json_path);
  const nlohmann::json doc = nlohmann::json::parse(f);
  const int makespan = doc.at("makespan").get<int>();
  EXPECT_EQ(makespan, 10);
  const auto& vehicles = doc.at("vehicles");
  ASSERT_EQ(vehicles.size(), 2u);
  std::set<std::pair<int, int>> tasks_done;
  std::vector<std::vector<std::pair<int, int>>> paths;
  for (const auto& v : vehicles) {
    const auto& path = v.at("path");
    ASSERT_EQ(static_cast<int>(path.size()), makespan + 1);
    std::vector<std::pair<int, int>> cells;
    for (int t = 0; t <= makespan; ++t) {
      ASSERT_EQ(path[t].size(), 3u);
      EXPECT_EQ(path[t][0].get<int>(), t);
      cells.emplace_back(path[t][1].get<int>(), path[t][2].get<int>());
      if (t > 0) {
        EXPECT_LE(std::abs(cells[t].first - cells[t - 1].first) + std::abs(cells[t].second - cells[t - 1].second), 1);
      }
    }
    const std::pair<int, int> depot{v.at("depot")[0].get<int>(), v.at("depot")[1].get<int>()};
    EXPECT_EQ(cells.front(), depot);
    EXPECT_EQ(cells.back(), depot);
    for (const auto& task : v.at("tasks")) {
      const std::pair<int, int> c{task[0].get<int>(), task[1].get<int>()};
      EXPECT_NE(std::find(cells.begin(), cells.end(), c), cells.end());
      EXPECT_TRUE(tasks_done.insert(c).second);
    }
    paths.push_back(cells);
  }
  EXPECT_EQ(tasks_done.size(), 4u);
  for (int t = 0; t <= makespan; ++t) {
    EXPECT_NE(paths[0][t], paths[1][t]) << "step " << t;
    if (t > 0) {
      EXPECT_FALSE(paths[0][t] == paths[1][t - 1] && paths[1][t] == paths[0][t - 1]) << "swap at " << t;
    }
  }
  // Vehicle 1 (depot (2, 0)) waits at (C,0) while vehicle 0 passes (C,1).
  EXPECT_EQ(paths[1][1], (std::pair<int, int>{2, 0}));

  GDALAllRegister();
  std::unique_ptr<GDALDataset> png(static_cast<GDALDataset*>(GDALOpen(png_path.c_str(), GA_ReadOnly)));
  ASSERT_TRUE(png);
  ASSERT_EQ(png->GetRasterCount(), 3);
  const int w = png->GetRasterXSize();
  const int h = png->GetRasterYSize();
  EXPECT_GE(w, 1000);  // the figure: a map 1000 pixels on its long side, cropped to the fleet, in its frame
  EXPECT_GT(h, 300);
  std::vector<std::uint8_t> rgb(static_cast<std::size_t>(w) * h * 3);
  ASSERT_EQ(png->RasterIO(GF_Read, 0, 0, w, h, rgb.data(), w, h, GDT_Byte, 3, nullptr, 3, 3 * w, 1, nullptr), CE_None);
  std::set<std::tuple<int, int, int>> colours;
  for (std::size_t i = 0; i < rgb.size(); i += 3) colours.insert({rgb[i], rgb[i + 1], rgb[i + 2]});
  // White free cells, grey walls and at least one colour per vehicle.
  EXPECT_GE(colours.size(), 4u);
  EXPECT_TRUE(colours.count({255, 255, 255}));
}

TEST_F(FleetCli, AllAllocatorsAgreeOnTheObviousInstance) {
  for (const char* algo : {"greedy", "ga", "exact"}) {
    const CliRun r = run("--map " + map() + " --vehicles '1,1;2,0' --tasks '4,1;4,3;2,3;2,4' --algo " + algo + " --seed 3");
    ASSERT_EQ(r.code, 0) << algo << ": " << r.err;
    EXPECT_NE(r.out.find("makespan 10"), std::string::npos) << algo << ": " << r.out;
  }
}

TEST_F(FleetCli, BadInputIsRefusedWithTheItemNamed) {
  CliRun r = run("--map " + map() + " --vehicles '1,1;2,0' --tasks '4,1;0,0'");  // (0,0) is a wall
  EXPECT_EQ(r.code, 2);
  EXPECT_NE(r.err.find("--tasks"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("task 1"), std::string::npos) << r.err;

  struct Refused {
    std::string args;
    int code;
    std::string named;  // what the message must name
  };
  const Refused cases[] = {
      {"--map " + map() + " --vehicles '1,1;2' --tasks '4,1'", 2, "--vehicles[1]"},
      {"--map " + map() + " --vehicles '1,1;1,1' --tasks '4,1'", 2, "vehicle 1"},
      {"--map " + map() + " --vehicles '1,1' --tasks '4,1;4,3;2,3' --capacity 2", 2, "capacity"},
      {"--map " + map() + " --vehicles '1,1' --tasks '4,1' --algo magic", 2, "--algo"},
      {"--map " + (dir_ / "missing.map").string() + " --vehicles '1,1' --tasks '4,1'", 3, "missing.map"},
      {"--map " + map() + " --vehicles '1,1' --tasks '4,1' --out /nonexistent-dir/plan.json", 2, "--out"},
      {"--map " + map() + " --vehicles '1,1' --tasks '4,1' --ends '2,0'", 2, "--ends"},  // lat/lon fleets only
  };
  for (const Refused& c : cases) {
    r = run(c.args);
    EXPECT_EQ(r.code, c.code) << c.args;
    EXPECT_NE(r.err.find(c.named), std::string::npos) << c.args << ": " << r.err;
  }

  // Without --map or --cells the points are latitude, longitude, altitude.
  r = run("--vehicles '1,1' --tasks '4,1'");
  EXPECT_EQ(r.code, 2);
  EXPECT_NE(r.err.find("--vehicles[0]"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("LAT,LON,ALT"), std::string::npos) << r.err;
}

// The old grid spellings still work for one release.
TEST_F(FleetCli, OldGridOptionNamesStillWork) {
  const CliRun r = run("--map " + map() + " --vehicles '1,1;2,0' --tasks '4,1;4,3;2,3;2,4' --cell-size 50 --clearance 20");
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_NE(r.out.find("makespan 10"), std::string::npos) << r.out;
}

const std::string kDemoFleet = skyroute::testing::projectDataPath("missions/demo_fleet.json");

// `fleet --file` on the embedded terrain writes, byte for byte, what the pipeline's fleet stage
// plans with the daemon's default configuration, through the writer `skyroute gcs` uses.
TEST_F(FleetCli, FileOnTheEmbeddedDemGivesThePipelinesTrajectories) {
  const fs::path csv = dir_ / "fleet.csv";
  const CliRun r = run("--file " + kDemoFleet + " --out " + csv.string());
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_NE(r.out.find("fleet demo-fleet: 3 vehicles, 6 tasks"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("makespan"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("separation"), std::string::npos) << r.out;

  const skyroute::DaemonConfig config;
  auto world = skyroute::WorldModel::load(skyroute::testing::projectDataPath("default_terrain.tif"), config.world);
  ASSERT_TRUE(world.ok()) << world.error().describe();
  std::ifstream file(kDemoFleet);
  auto request = skyroute::fleetFromJson(nlohmann::json::parse(file));
  ASSERT_TRUE(request.ok()) << request.error().describe();
  const skyroute::MissionPipeline pipeline(*world, config.engine.pipeline);
  const skyroute::FleetPlanOutput plan = pipeline.planFleet(*request, skyroute::utcNowNs());
  ASSERT_TRUE(plan.ok()) << plan.status.message;
  const fs::path reference = dir_ / "reference.csv";
  ASSERT_TRUE(skyroute::writeTrajectoriesCsv(reference.string(), plan.trajectories).ok());
  const std::string got = slurp(csv);
  EXPECT_GT(std::count(got.begin(), got.end(), '\n'), 1000);
  EXPECT_TRUE(got == slurp(reference)) << "skyroute fleet and the pipeline's fleet stage differ";
  for (const auto& a : plan.status.allocation) {
    std::string tasks;
    for (std::uint32_t t : a.tasks) tasks += (tasks.empty() ? "" : ", ") + std::to_string(t);
    EXPECT_NE(r.out.find(a.vehicle_id + ": tasks " + tasks), std::string::npos) << r.out;
  }
}

TEST_F(FleetCli, GeoJsonKmlAndPngOfTheFleet) {
  const fs::path geojson = dir_ / "fleet.geojson", kml = dir_ / "fleet.kml", png = dir_ / "fleet.png";
  ASSERT_EQ(run("--file " + kDemoFleet + " --out " + geojson.string() + " --png " + png.string()).code, 0);
  ASSERT_EQ(run("--file " + kDemoFleet + " --out " + kml.string()).code, 0);
  GDALAllRegister();
  for (const fs::path& path : {geojson, kml}) {
    std::unique_ptr<GDALDataset> ds(static_cast<GDALDataset*>(GDALOpenEx(path.c_str(), GDAL_OF_VECTOR, nullptr, nullptr, nullptr)));
    ASSERT_TRUE(ds) << path;
    OGRLayer* layer = ds->GetLayer(0);
    ASSERT_NE(layer, nullptr);
    std::set<std::string> vehicles;
    for (auto& feature : *layer) {
      vehicles.insert(feature->GetFieldAsString("vehicle_id"));
      const OGRGeometry* g = feature->GetGeometryRef();
      ASSERT_NE(g, nullptr);
      EXPECT_EQ(wkbFlatten(g->getGeometryType()), wkbLineString);
      EXPECT_GT(g->toLineString()->getNumPoints(), 100);
    }
    EXPECT_EQ(vehicles, (std::set<std::string>{"uav-1", "uav-2", "uav-3"})) << path;
  }
  std::unique_ptr<GDALDataset> image(static_cast<GDALDataset*>(GDALOpen(png.c_str(), GA_ReadOnly)));
  ASSERT_TRUE(image);
  EXPECT_EQ(image->GetRasterCount(), 3);
  EXPECT_GE(image->GetRasterXSize(), 1000);  // a map 1000 pixels on its long side, in its frame
}

// A fleet's points are checked as a mission's: each error quotes the point as written (latitude,
// longitude, altitude AMSL) and says what is wrong, with the DEM's bounds or the ground height.
TEST_F(FleetCli, PointErrorsQuoteThePointAsWritten) {
  const std::string tasks = " --tasks '46.95,15.06,1000'";
  CliRun r = run("--vehicles 'a@47.90,15.03,900;b@46.90,15.15,900'" + tasks);
  EXPECT_EQ(r.code, 2) << r.err;
  EXPECT_NE(r.err.find("--vehicles[0]: begins[0] (47.9, 15.03, 900 m AMSL) is outside the DEM (lat "), std::string::npos)
      << r.err;
  r = run("--vehicles 'a@15.03,46.90,900;b@46.90,15.15,900'" + tasks);
  EXPECT_NE(r.err.find("latitude and longitude may be swapped"), std::string::npos) << r.err;
  r = run("--vehicles 'a@46.90,15.03,100;b@46.90,15.15,900'" + tasks);
  EXPECT_NE(r.err.find("(46.9, 15.03, 100 m AMSL) is under the ground plus clearance: the ground here is "),
            std::string::npos)
      << r.err;
  r = run("--vehicles 'a@46.90,15.03,900;b@46.90,15.15,900' --tasks '46.95,15.06,1000;46.95,16.06,1000'");
  EXPECT_NE(r.err.find("--tasks[1]: tasks[1] (46.95, 16.06, 1000 m AMSL) is outside the DEM"), std::string::npos) << r.err;
}

TEST_F(FleetCli, VehiclesAndTasksFromTheCommandLine) {
  CliRun r = run("--vehicles 'north@46.97,15.04,1000;south@46.91,15.13,1000' --tasks '46.95,15.07,1050;46.93,15.11,1050'");
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_NE(r.out.find("  north: tasks"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("  south: tasks"), std::string::npos) << r.out;
  r = run("--vehicles '46.97,15.04,1000;46.91,15.13,1000' --tasks '46.95,15.07,1050' --ends '46.96,15.05,1000;46.92,15.12,1000'");
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_NE(r.out.find("  uav-1: tasks"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("  uav-2: tasks"), std::string::npos) << r.out;
}

TEST_F(FleetCli, GeoBadInputIsNamedWithItsOptionOrField) {
  std::ofstream(dir_ / "bad.json") << R"({"begins": [{"lat_deg": 46.91, "lon_deg": 15.04, "alt_amsl_m": 1000}],
    "tasks": [{"lat_deg": 46.93, "lon_deg": 15.06, "alt_amsl_m": 1050}, {"lat_deg": 46.95, "lon_deg": 15.07}]})";
  std::ofstream(dir_ / "under.json") << R"({"begins": [{"lat_deg": 46.91, "lon_deg": 15.04, "alt_amsl_m": 1000}],
    "tasks": [{"lat_deg": 46.93, "lon_deg": 15.06, "alt_amsl_m": 100}]})";
  const std::string two = " --vehicles 'a@46.97,15.04,1000;b@46.91,15.13,1000'";
  struct Case {
    std::string args;
    int code;
    std::vector<std::string> named;
  };
  const std::vector<Case> cases{
      {"--file " + (dir_ / "bad.json").string(), 3, {"bad.json", "tasks[1].alt_amsl_m"}},
      {"--file " + (dir_ / "missing.json").string(), 3, {"--file", "missing.json"}},
      {"--file " + (dir_ / "under.json").string(), 3, {"under.json", "tasks[0]", "ground"}},
      {two + " --tasks '46.95,15.07,100'", 2, {"--tasks[0]", "ground"}},
      {two + " --tasks '46.95,15.07'", 2, {"--tasks[0]", "LAT,LON,ALT"}},
      {" --vehicles 'a@46.97,15.04,1000;a@46.91,15.13,1000' --tasks '46.95,15.07,1050'", 2, {"--vehicles[1]", "duplicate"}},
      {two + " --tasks '46.95,15.07,1050' --ends '46.96,15.05,1000'", 2, {"--ends", "1 points for 2 vehicles"}},
      {two + " --tasks '46.95,15.07,1050' --vref-mps 50", 2, {"--vref-mps"}},
      {two + " --tasks '46.95,15.07,1050' --algo ga", 2, {"--algo"}},
      {two + " --tasks '46.95,15.07,1050' --wait 3", 2, {"--wait"}},
      {"--file " + kDemoFleet + two, 2, {"--file", "--vehicles"}},
      {"--file " + kDemoFleet + " --out " + (dir_ / "fleet.txt").string(), 2, {"--out", ".txt"}},
      {"--file " + kDemoFleet + " --domain 212 --png " + (dir_ / "f.png").string(), 2, {"--png"}},
      {"--file " + kDemoFleet + " --dem " + (dir_ / "missing.tif").string(), 3, {"--dem", "missing.tif"}},
  };
  for (const Case& c : cases) {
    SCOPED_TRACE(c.args);
    const CliRun r = run(c.args);
    EXPECT_EQ(r.code, c.code) << r.err;
    for (const std::string& name : c.named) EXPECT_NE(r.err.find(name), std::string::npos) << r.err;
  }
}

}  // namespace
