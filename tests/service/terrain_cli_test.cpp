// `skyroute terrain info` as a user runs it: JSON fields, hillshade PNG, clear errors.
#include <array>
#include <cstdio>
#include <filesystem>
#include <memory>
#include <string>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "tests/test_data.hpp"

namespace {

struct CliRun {
  int exit_code = -1;
  std::string output;  // stdout and stderr together
};

CliRun run(const std::string& args) {
  const std::string command = std::string(SKYROUTE_CLI) + " " + args + " 2>&1";
  CliRun r;
  FILE* pipe = popen(command.c_str(), "r");
  std::array<char, 4096> buffer{};
  while (pipe && fgets(buffer.data(), buffer.size(), pipe)) r.output += buffer.data();
  const int status = pipe ? pclose(pipe) : -1;
  r.exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  return r;
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

}  // namespace
