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

struct CliRun {
  int exit_code = -1;
  std::string output;  // stdout and stderr together
};

CliRun run(const std::string& args) {
  skyroute::testing::CliOutput r = skyroute::testing::runCli(args);
  return CliRun{r.exit_code, std::move(r.text)};
}

TEST(TerrainCli, InfoJsonOnDefaultTerrain) {
  const std::string png = ::testing::TempDir() + "/hillshade.png";
  std::filesystem::remove(png);
  const CliRun r = run("terrain info " + skyroute::testing::projectDataPath("default_terrain.tif") + " --json --png " + png);
  ASSERT_EQ(r.exit_code, 0) << r.output;
  const auto j = nlohmann::json::parse(r.output.substr(r.output.find('{')));
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
  ASSERT_EQ(r.exit_code, 0) << r.output;
  const auto j = nlohmann::json::parse(r.output.substr(r.output.find('{')));
  EXPECT_NEAR(j["max_height_m"].get<double>(), 1908.0, 0.5);
  EXPECT_TRUE(j["geographic"].get<bool>());
}

TEST(TerrainCli, UnusableFileExitsNonZeroNamingIt) {
  const CliRun missing = run("terrain info /nonexistent/dem.tif");
  EXPECT_NE(missing.exit_code, 0);
  EXPECT_NE(missing.output.find("/nonexistent/dem.tif"), std::string::npos) << missing.output;
  EXPECT_NE(missing.output.find("no such file"), std::string::npos) << missing.output;
  const std::string text = ::testing::TempDir() + "/notes.txt";
  FILE* f = fopen(text.c_str(), "w");
  fputs("not a raster", f);
  fclose(f);
  const CliRun bad = run("terrain info " + text);
  EXPECT_NE(bad.exit_code, 0);
  EXPECT_NE(bad.output.find(text), std::string::npos) << bad.output;
}

TEST(TerrainCli, InfoPrintsWgs84BoundsAndHeights) {
  const std::string dem = skyroute::testing::projectDataPath("default_terrain.tif");
  const CliRun json = run("terrain info " + dem + " --json");
  ASSERT_EQ(json.exit_code, 0) << json.output;
  const auto j = nlohmann::json::parse(json.output.substr(json.output.find('{')));
  const auto& b = j["bounds_wgs84"];
  // The embedded terrain: 12.8 km square around 46.94 N, 15.08 E.
  EXPECT_NEAR(b["south_deg"].get<double>(), 46.884, 0.002);
  EXPECT_NEAR(b["north_deg"].get<double>(), 46.998, 0.002);
  EXPECT_NEAR(b["west_deg"].get<double>(), 15.001, 0.002);
  EXPECT_NEAR(b["east_deg"].get<double>(), 15.167, 0.002);
  EXPECT_EQ(j["heights_amsl_m"]["min"], j["min_height_m"]);
  EXPECT_EQ(j["heights_amsl_m"]["max"], j["max_height_m"]);
  const CliRun text = run("terrain info " + dem);
  ASSERT_EQ(text.exit_code, 0) << text.output;
  EXPECT_NE(text.output.find("wgs84 bounds  lat 46.88"), std::string::npos) << text.output;
  EXPECT_NE(text.output.find("m AMSL"), std::string::npos) << text.output;
}

TEST(TerrainCli, HeightAtPointsAndErrorsNameThePointAsWritten) {
  const std::string dem = skyroute::testing::projectDataPath("default_terrain.tif");
  const CliRun ok = run("terrain height --dem " + dem + " 46.93,15.10 46.96,15.12 --json");
  ASSERT_EQ(ok.exit_code, 0) << ok.output;
  const auto rows = nlohmann::json::parse(ok.output.substr(ok.output.find('[')));
  ASSERT_EQ(rows.size(), 2u);
  EXPECT_EQ(rows[0]["point"], "46.93,15.10");
  const double h0 = rows[0]["ground_amsl_m"].get<double>();
  EXPECT_GE(h0, 135.0);  // within the DEM's height range (terrain info)
  EXPECT_LE(h0, 922.0);
  EXPECT_NE(rows[0]["ground_amsl_m"], rows[1]["ground_amsl_m"]);
  const CliRun text = run("terrain height --dem " + dem + " 46.93,15.10");
  ASSERT_EQ(text.exit_code, 0) << text.output;
  char expected[64];
  std::snprintf(expected, sizeof expected, "46.93,15.10 %.1f m AMSL", h0);
  EXPECT_NE(text.output.find(expected), std::string::npos) << text.output;

  const CliRun swapped = run("terrain height --dem " + dem + " 46.93,15.10 15.12,46.96");
  EXPECT_EQ(swapped.exit_code, 2) << swapped.output;
  EXPECT_NE(swapped.output.find("point '15.12,46.96'"), std::string::npos) << swapped.output;
  EXPECT_NE(swapped.output.find("latitude and longitude may be swapped"), std::string::npos) << swapped.output;
  const CliRun outside = run("terrain height --dem " + dem + " 47.5,15.1");
  EXPECT_EQ(outside.exit_code, 2) << outside.output;
  EXPECT_NE(outside.output.find("point '47.5,15.1' is outside the DEM (lat 46.88"), std::string::npos) << outside.output;
  const CliRun malformed = run("terrain height --dem " + dem + " '46.93;15.1'");
  EXPECT_EQ(malformed.exit_code, 2) << malformed.output;
  EXPECT_NE(malformed.output.find("point '46.93;15.1' must be LAT,LON"), std::string::npos) << malformed.output;
}

// An octree the memory cannot hold is refused at once, naming --octree-res and the estimate.
TEST(TerrainCli, OctreeBeyondTheMemoryLimitIsRefusedBeforeItIsBuilt) {
  const std::string dem = skyroute::testing::projectDataPath("default_terrain.tif");
  const auto started = std::chrono::steady_clock::now();
  // 0.5 m over 12.8 km: 650 million columns, about 90 GiB, over a 100 MiB limit.
  const CliRun limited = run("terrain info " + dem + " --octree-res 0.5 --max-memory-mb 100");
  EXPECT_EQ(limited.exit_code, 2) << limited.output;
  EXPECT_NE(limited.output.find("--octree-res: the octree at 0.5 m would take about "), std::string::npos)
      << limited.output;
  EXPECT_NE(limited.output.find("GiB, more than the 100 MiB"), std::string::npos) << limited.output;
  // The same against the machine's own free memory (no machine has 180 GiB to spare for it).
  const CliRun machine = run("terrain info " + dem + " --octree-res 0.35");
  EXPECT_EQ(machine.exit_code, 2) << machine.output;
  EXPECT_NE(machine.output.find("half of MemAvailable"), std::string::npos) << machine.output;
  EXPECT_LT(std::chrono::duration<double>(std::chrono::steady_clock::now() - started).count(), 10.0);
  // Within the limit it is built.
  EXPECT_EQ(run("terrain info " + dem + " --octree-res 90 --max-memory-mb 100").exit_code, 0);
}

TEST(TerrainCli, HelpShowsAnExampleAndTheDefaults) {
  const CliRun info = run("terrain info --help");
  EXPECT_NE(info.output.find("Example: skyroute terrain info data/default_terrain.tif"), std::string::npos) << info.output;
  EXPECT_NE(info.output.find("=90"), std::string::npos) << info.output;  // --octree-res
  EXPECT_NE(info.output.find("--max-memory-mb FLOAT:NONNEGATIVE=0"), std::string::npos) << info.output;
  const CliRun height = run("terrain height --help");
  EXPECT_NE(height.output.find("Example: skyroute terrain height --dem"), std::string::npos) << height.output;
  const CliRun gcs = run("gcs --help");
  if (gcs.output.find("gcs") != std::string::npos && gcs.exit_code == 0) {  // a build with the DDS tools
    EXPECT_NE(gcs.output.find("Example: skyroute gcs --domain 77"), std::string::npos) << gcs.output;
    EXPECT_NE(gcs.output.find("--timeout"), std::string::npos);
  }
}

}  // namespace
