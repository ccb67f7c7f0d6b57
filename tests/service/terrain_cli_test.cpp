// `skyroute terrain info` as a user runs it: JSON fields, hillshade PNG, clear errors.
#include <array>
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <memory>
#include <string>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "tests/cli_run.hpp"
#include "tests/test_data.hpp"

namespace {

using CliRun = skyroute::testing::CliOutput;  // exit code, and stdout with stderr as text

CliRun run(const std::string& args) { return skyroute::testing::runCli(args); }

TEST(TerrainCli, InfoJsonOnDefaultTerrain) {
  const std::string png = ::testing::TempDir() + "/hillshade.png";
  std::filesystem::remove(png);
  const CliRun r = run("terrain info " + skyroute::testing::projectDataPath("default_terrain.tif") + " --json --png " + png);
  ASSERT_EQ(r.exit_code, 0) << r.text;
  const auto j = nlohmann::json::parse(r.text.substr(r.text.find('{')));
  EXPECT_EQ(j["width"], 320);
  EXPECT_EQ(j["height"], 320);
  EXPECT_NE(j["crs"].get<std::string>().find("32633"), std::string::npos);
  EXPECT_NEAR(j["resolution_m"][0].get<double>(), 40.0, 0.5);
  EXPECT_LT(j["min_height_m"].get<double>(), j["max_height_m"].get<double>());
  EXPECT_EQ(j["voids"]["unknown_cells"], 0);
  ASSERT_TRUE(std::filesystem::exists(png));
  EXPECT_GT(std::filesystem::file_size(png), 10000u);
}

TEST(TerrainCli, InfoOnGeographicHgt) {
  SKYROUTE_REQUIRE_SHARED(path, "dem/N44W072.hgt");
  const CliRun r = run("terrain info " + path + " --json");
  ASSERT_EQ(r.exit_code, 0) << r.text;
  const auto j = nlohmann::json::parse(r.text.substr(r.text.find('{')));
  EXPECT_NEAR(j["max_height_m"].get<double>(), 1908.0, 0.5);
  EXPECT_TRUE(j["geographic"].get<bool>());
}

TEST(TerrainCli, UnusableFileExitsNonZeroNamingIt) {
  const CliRun missing = run("terrain info /nonexistent/dem.tif");
  EXPECT_NE(missing.exit_code, 0);
  EXPECT_NE(missing.text.find("/nonexistent/dem.tif"), std::string::npos) << missing.text;
  EXPECT_NE(missing.text.find("no such file"), std::string::npos) << missing.text;
  const std::string text = ::testing::TempDir() + "/notes.txt";
  FILE* f = fopen(text.c_str(), "w");
  fputs("not a raster", f);
  fclose(f);
  const CliRun bad = run("terrain info " + text);
  EXPECT_NE(bad.exit_code, 0);
  EXPECT_NE(bad.text.find(text), std::string::npos) << bad.text;
}

TEST(TerrainCli, InfoPrintsWgs84BoundsAndHeights) {
  const std::string dem = skyroute::testing::projectDataPath("default_terrain.tif");
  const CliRun json = run("terrain info " + dem + " --json");
  ASSERT_EQ(json.exit_code, 0) << json.text;
  const auto j = nlohmann::json::parse(json.text.substr(json.text.find('{')));
  const auto& b = j["bounds_wgs84"];
  // The embedded terrain: 12.8 km square around 46.94 N, 15.08 E.
  EXPECT_NEAR(b["south_deg"].get<double>(), 46.884, 0.002);
  EXPECT_NEAR(b["north_deg"].get<double>(), 46.998, 0.002);
  EXPECT_NEAR(b["west_deg"].get<double>(), 15.001, 0.002);
  EXPECT_NEAR(b["east_deg"].get<double>(), 15.167, 0.002);
  EXPECT_EQ(j["heights_amsl_m"]["min"], j["min_height_m"]);
  EXPECT_EQ(j["heights_amsl_m"]["max"], j["max_height_m"]);
  const CliRun text = run("terrain info " + dem);
  ASSERT_EQ(text.exit_code, 0) << text.text;
  EXPECT_NE(text.text.find("wgs84 bounds  lat 46.88"), std::string::npos) << text.text;
  EXPECT_NE(text.text.find("m AMSL"), std::string::npos) << text.text;
}

TEST(TerrainCli, HeightAtPointsAndErrorsNameThePointAsWritten) {
  const std::string dem = skyroute::testing::projectDataPath("default_terrain.tif");
  const CliRun ok = run("terrain height --dem " + dem + " 46.93,15.10 46.96,15.12 --json");
  ASSERT_EQ(ok.exit_code, 0) << ok.text;
  const auto rows = nlohmann::json::parse(ok.text.substr(ok.text.find('[')));
  ASSERT_EQ(rows.size(), 2u);
  EXPECT_EQ(rows[0]["point"], "46.93,15.10");
  const double h0 = rows[0]["ground_amsl_m"].get<double>();
  EXPECT_GE(h0, 135.0);  // within the DEM's height range (terrain info)
  EXPECT_LE(h0, 922.0);
  EXPECT_NE(rows[0]["ground_amsl_m"], rows[1]["ground_amsl_m"]);
  const CliRun text = run("terrain height --dem " + dem + " 46.93,15.10");
  ASSERT_EQ(text.exit_code, 0) << text.text;
  char expected[64];
  std::snprintf(expected, sizeof expected, "46.93,15.10 %.1f m AMSL", h0);
  EXPECT_NE(text.text.find(expected), std::string::npos) << text.text;

  const CliRun swapped = run("terrain height --dem " + dem + " 46.93,15.10 15.12,46.96");
  EXPECT_EQ(swapped.exit_code, 2) << swapped.text;
  EXPECT_NE(swapped.text.find("point '15.12,46.96'"), std::string::npos) << swapped.text;
  EXPECT_NE(swapped.text.find("latitude and longitude may be swapped"), std::string::npos) << swapped.text;
  const CliRun outside = run("terrain height --dem " + dem + " 47.5,15.1");
  EXPECT_EQ(outside.exit_code, 2) << outside.text;
  EXPECT_NE(outside.text.find("point '47.5,15.1' is outside the DEM (lat 46.88"), std::string::npos) << outside.text;
  const CliRun malformed = run("terrain height --dem " + dem + " '46.93;15.1'");
  EXPECT_EQ(malformed.exit_code, 2) << malformed.text;
  EXPECT_NE(malformed.text.find("point '46.93;15.1' must be LAT,LON"), std::string::npos) << malformed.text;
}

// An octree the memory cannot hold is refused at once, naming --octree-res and the estimate.
TEST(TerrainCli, OctreeBeyondTheMemoryLimitIsRefusedBeforeItIsBuilt) {
  const std::string dem = skyroute::testing::projectDataPath("default_terrain.tif");
  const auto started = std::chrono::steady_clock::now();
  // 0.5 m over 12.8 km: 650 million columns, about 90 GiB, over a 100 MiB limit.
  const CliRun limited = run("terrain info " + dem + " --octree-res 0.5 --max-memory-mb 100");
  EXPECT_EQ(limited.exit_code, 2) << limited.text;
  EXPECT_NE(limited.text.find("--octree-res: the octree at 0.5 m would take about "), std::string::npos)
      << limited.text;
  EXPECT_NE(limited.text.find("GiB, more than the 100 MiB"), std::string::npos) << limited.text;
  // The same against the machine's own free memory (no machine has 180 GiB to spare for it).
  const CliRun machine = run("terrain info " + dem + " --octree-res 0.35");
  EXPECT_EQ(machine.exit_code, 2) << machine.text;
  EXPECT_NE(machine.text.find("half of MemAvailable"), std::string::npos) << machine.text;
  EXPECT_LT(std::chrono::duration<double>(std::chrono::steady_clock::now() - started).count(), 10.0);
  // Within the limit it is built.
  EXPECT_EQ(run("terrain info " + dem + " --octree-res 90 --max-memory-mb 100").exit_code, 0);
}

TEST(TerrainCli, HelpShowsAnExampleAndTheDefaults) {
  const CliRun info = run("terrain info --help");
  EXPECT_NE(info.text.find("Example: skyroute terrain info data/default_terrain.tif"), std::string::npos) << info.text;
  EXPECT_NE(info.text.find("=90"), std::string::npos) << info.text;  // --octree-res
  EXPECT_NE(info.text.find("--max-memory-mb FLOAT:NONNEGATIVE=0"), std::string::npos) << info.text;
  const CliRun height = run("terrain height --help");
  EXPECT_NE(height.text.find("Example: skyroute terrain height --dem"), std::string::npos) << height.text;
  const CliRun gcs = run("gcs --help");
  if (gcs.text.find("gcs") != std::string::npos && gcs.exit_code == 0) {  // a build with the DDS tools
    EXPECT_NE(gcs.text.find("Example: skyroute gcs --domain 77"), std::string::npos) << gcs.text;
    EXPECT_NE(gcs.text.find("--timeout"), std::string::npos);
  }
}

}  // namespace
