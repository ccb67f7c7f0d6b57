// `skyroute terrain info` as a user runs it: JSON fields, hillshade PNG, clear errors.
#include <array>
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <memory>
#include <string>
#include <vector>

#include <gdal.h>
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>
#include <ogr_srs_api.h>

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
  EXPECT_NE(swapped.text.find(expected), std::string::npos) << swapped.text;  // the first point's height
  EXPECT_NE(swapped.text.find("15.12,46.96 no height: the point is outside the DEM, but inside it with latitude and "
                              "longitude exchanged: latitude and longitude may be swapped"),
            std::string::npos)
      << swapped.text;
  const CliRun outside = run("terrain height --dem " + dem + " 47.5,15.1");
  EXPECT_EQ(outside.exit_code, 2) << outside.text;
  EXPECT_NE(outside.text.find("47.5,15.1 no height: the point is outside the DEM (lat 46.88"), std::string::npos)
      << outside.text;
  EXPECT_NE(outside.text.find("1 of 1 point has no height"), std::string::npos) << outside.text;
  const CliRun malformed = run("terrain height --dem " + dem + " '46.93;15.1'");
  EXPECT_EQ(malformed.exit_code, 2) << malformed.text;
  EXPECT_NE(malformed.text.find("46.93;15.1 no height: not LAT,LON (two numbers in degrees)"), std::string::npos)
      << malformed.text;
}

// A 40 x 40 DEM at 500 m with a void of 12 x 12 cells (too large to fill) in its middle.
std::string demWithVoid() {
  constexpr int kSize = 40;
  std::vector<float> heights(kSize * kSize, 500.0f);
  for (int row = 14; row < 26; ++row)
    for (int col = 14; col < 26; ++col) heights[static_cast<std::size_t>(row) * kSize + col] = -9999.0f;
  GDALAllRegister();
  const std::string path = ::testing::TempDir() + "/terrain_height_void.tif";
  GDALDatasetH ds = GDALCreate(GDALGetDriverByName("GTiff"), path.c_str(), kSize, kSize, 1, GDT_Float32, nullptr);
  double transform[6] = {500000.0, 100.0, 0.0, 5200000.0, 0.0, -100.0};  // UTM 33N, 100 m cells
  GDALSetGeoTransform(ds, transform);
  OGRSpatialReferenceH srs = OSRNewSpatialReference(nullptr);
  OSRImportFromEPSG(srs, 32633);
  GDALSetSpatialRef(ds, srs);
  OSRDestroySpatialReference(srs);
  GDALRasterBandH band = GDALGetRasterBand(ds, 1);
  GDALSetRasterNoDataValue(band, -9999.0);
  EXPECT_EQ(GDALRasterIO(band, GF_Write, 0, 0, kSize, kSize, heights.data(), kSize, kSize, GDT_Float32, 0, 0), CE_None);
  GDALClose(ds);
  return path;
}

// WGS84 "LAT,LON" of a UTM 33N position.
std::string latLonOf(double easting_m, double northing_m) {
  OGRSpatialReferenceH utm = OSRNewSpatialReference(nullptr);
  OGRSpatialReferenceH wgs84 = OSRNewSpatialReference(nullptr);
  OSRImportFromEPSG(utm, 32633);
  OSRImportFromEPSG(wgs84, 4326);
  OSRSetAxisMappingStrategy(wgs84, OAMS_TRADITIONAL_GIS_ORDER);
  OGRCoordinateTransformationH to_wgs84 = OCTNewCoordinateTransformation(utm, wgs84);
  double x = easting_m, y = northing_m;
  EXPECT_TRUE(OCTTransform(to_wgs84, 1, &x, &y, nullptr));
  OCTDestroyCoordinateTransformation(to_wgs84);
  OSRDestroySpatialReference(utm);
  OSRDestroySpatialReference(wgs84);
  char text[64];
  std::snprintf(text, sizeof text, "%.6f,%.6f", y, x);
  return text;
}

// One point over the void among points over ground: every point gets its line, the void one its
// reason, and the exit code says some failed (before: the void point ended the command with no
// height printed at all).
TEST(TerrainCli, HeightPrintsEveryPointsHeightOrItsReason) {
  const std::string dem = demWithVoid();
  const std::string ground = latLonOf(501000.0, 5199000.0);
  const std::string in_void = latLonOf(502000.0, 5198000.0);  // the middle of the void
  const std::string far_ground = latLonOf(503000.0, 5197000.0);
  const CliRun text = run("terrain height --dem " + dem + " " + ground + " " + in_void + " " + far_ground);
  EXPECT_EQ(text.exit_code, 2) << text.text;
  EXPECT_NE(text.text.find(ground + " 500.0 m AMSL\n" + in_void + " no height: the point lies on a DEM void: no "
                           "elevation data here"),
            std::string::npos)
      << text.text;
  EXPECT_NE(text.text.find(far_ground + " 500.0 m AMSL"), std::string::npos) << text.text;
  EXPECT_NE(text.text.find("1 of 3 points have no height"), std::string::npos) << text.text;

  const CliRun json = run("terrain height --json --dem " + dem + " " + ground + " " + in_void + " " + far_ground);
  EXPECT_EQ(json.exit_code, 2) << json.text;
  const auto rows = nlohmann::json::parse(json.text.substr(json.text.find('['), json.text.rfind(']') + 1 - json.text.find('[')));
  ASSERT_EQ(rows.size(), 3u) << json.text;
  EXPECT_NEAR(rows[0]["ground_amsl_m"].get<double>(), 500.0, 0.01);
  EXPECT_TRUE(rows[1]["ground_amsl_m"].is_null());
  EXPECT_NE(rows[1]["error"].get<std::string>().find("no elevation data here"), std::string::npos) << json.text;
  EXPECT_EQ(rows[1]["point"], in_void);
  EXPECT_NEAR(rows[2]["ground_amsl_m"].get<double>(), 500.0, 0.01);
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
