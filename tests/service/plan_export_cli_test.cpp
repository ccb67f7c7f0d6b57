// `skyroute plan --out` into the ground-station formats, run as a user would on the embedded terrain:
// a QGroundControl .plan whose first and last items are --from and --to at their AMSL altitudes, the
// same mission as QGC WPL 110, and the CSV's ellipsoidal column.
#include <sys/wait.h>

#include <array>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "tests/cli_run.hpp"
#include "tests/test_data.hpp"
#include "tests/test_folder.hpp"
#include "tests/text_file.hpp"

namespace {

using CliRun = skyroute::testing::CliOutput;  // exit code, and stdout with stderr as text

CliRun run(const std::string& args) { return skyroute::testing::runCli(args); }

std::string slurp(const std::string& path) { return skyroute::testing::readTextFile(path); }

// A short reproducible plan across the embedded terrain (ground below 922 m AMSL).
std::string planArgs(const std::string& out) {
  return "plan --dem " + skyroute::testing::projectDataPath("default_terrain.tif") +
         " --from 46.90,15.03,1100 --via 46.95,15.06,1150 --to 46.97,15.12,1100 --iterations 1500 --budget-s 0"
         " --out " + out;
}

class PlanExportCli : public skyroute::testing::TestFolderTest {
 protected:
  PlanExportCli() : TestFolderTest("skyroute_plan_export_cli_test_") {}
};

TEST_F(PlanExportCli, QgroundcontrolPlanHasTheMissionPointsAtAmslAltitudes) {
  const std::string plan_path = (dir_ / "mission.plan").string();
  const CliRun r = run(planArgs(plan_path));
  ASSERT_EQ(r.exit_code, 0) << r.text;
  const nlohmann::json plan = nlohmann::json::parse(slurp(plan_path), nullptr, false);
  ASSERT_FALSE(plan.is_discarded()) << slurp(plan_path);
  EXPECT_EQ(plan["fileType"], "Plan");
  const auto& mission = plan["mission"];
  EXPECT_EQ(mission["globalPlanAltitudeMode"], 2);
  const auto& home = mission["plannedHomePosition"];
  EXPECT_NEAR(home[0].get<double>(), 46.90, 1e-7);
  EXPECT_NEAR(home[1].get<double>(), 15.03, 1e-7);
  const auto& items = mission["items"];
  ASSERT_GE(items.size(), 3u);
  for (const auto& item : items) {
    EXPECT_EQ(item["AltitudeMode"], 2);
    EXPECT_EQ(item["frame"], 0);
    EXPECT_GT(item["Altitude"].get<double>(), 922.0);  // above the highest ground: AMSL, not relative
  }
  const auto& first = items.front()["params"];
  EXPECT_NEAR(first[4].get<double>(), 46.90, 1e-7);
  EXPECT_NEAR(first[5].get<double>(), 15.03, 1e-7);
  EXPECT_NEAR(first[6].get<double>(), 1100.0, 1e-6);
  const auto& last = items.back()["params"];
  EXPECT_NEAR(last[4].get<double>(), 46.97, 1e-7);
  EXPECT_NEAR(last[5].get<double>(), 15.12, 1e-7);
  EXPECT_NEAR(last[6].get<double>(), 1100.0, 1e-6);
}

TEST_F(PlanExportCli, WaypointsAndCsv) {
  const std::string waypoints = (dir_ / "mission.waypoints").string();
  CliRun r = run(planArgs(waypoints));
  ASSERT_EQ(r.exit_code, 0) << r.text;
  std::istringstream lines(slurp(waypoints));
  std::string line;
  std::getline(lines, line);
  EXPECT_EQ(line, "QGC WPL 110");
  std::size_t rows = 0;
  while (std::getline(lines, line)) ++rows;
  EXPECT_GE(rows, 4u);  // home and at least begin, via and end

  const std::string csv = (dir_ / "trajectory.csv").string();
  r = run(planArgs(csv));
  ASSERT_EQ(r.exit_code, 0) << r.text;
  std::istringstream csv_lines(slurp(csv));
  std::getline(csv_lines, line);
  // The columns of `skyroute gcs --csv`: one writer for both.
  EXPECT_EQ(line.rfind("vehicle_id,time_s,lat_deg,lon_deg,alt_amsl_m,", 0), 0u) << line;
  EXPECT_EQ(line.substr(line.rfind(',') + 1), "alt_ellipsoid_m");
  std::getline(csv_lines, line);
  // Here the geoid is about 47 m above the ellipsoid: the first row is --from at 1100 m AMSL.
  const double ellipsoid = std::stod(line.substr(line.rfind(',') + 1));
  EXPECT_NEAR(ellipsoid - 1100.0, 47.0, 3.0) << line;
}

}  // namespace
