// The shipped data is found in share/skyroute beside the binary's folder, wherever the prefix is;
// without it the error names the terrain setting and the folder searched.
#include "service/shipped_data.hpp"

#include <unistd.h>

#include <filesystem>
#include <fstream>

#include <gtest/gtest.h>

namespace skyroute {
namespace {

class ShippedData : public ::testing::Test {
 protected:
  void SetUp() override {
    prefix_ = std::filesystem::path(::testing::TempDir()) / ("skyroute_shipped_data_" + std::to_string(::getpid()));
    std::filesystem::remove_all(prefix_);
    std::filesystem::create_directories(prefix_ / "bin");
    exe_ = (prefix_ / "bin" / "skyroute").string();
  }
  void TearDown() override { std::filesystem::remove_all(prefix_); }
  std::filesystem::path prefix_;
  std::string exe_;
};

TEST_F(ShippedData, FoundInShareBesideTheBinarysFolder) {
  ASSERT_EQ(shippedDataDirs(exe_), std::vector<std::string>{(prefix_ / "share" / "skyroute").string()});
  std::filesystem::create_directories(prefix_ / "share" / "skyroute" / "missions");
  std::ofstream(prefix_ / "share" / "skyroute" / kDefaultTerrainFile) << "dem";
  std::ofstream(prefix_ / "share" / "skyroute" / "missions" / "m.json") << "{}";

  auto terrain = defaultTerrainPath(exe_);
  ASSERT_TRUE(terrain.ok()) << terrain.error().describe();
  EXPECT_EQ(*terrain, (prefix_ / "share" / "skyroute" / kDefaultTerrainFile).string());
  auto mission = findShippedData("missions/m.json", exe_);
  ASSERT_TRUE(mission.ok());
  EXPECT_EQ(*mission, (prefix_ / "share" / "skyroute" / "missions" / "m.json").string());
}

TEST_F(ShippedData, MissingDataNamesTheFolderSearched) {
  std::filesystem::create_directories(prefix_ / "share" / "skyroute");  // a folder, but no terrain in it
  auto terrain = defaultTerrainPath(exe_);
  ASSERT_FALSE(terrain.ok());
  EXPECT_EQ(terrain.error().code, ErrorCode::kFileNotFound);
  EXPECT_EQ(terrain.error().field, "terrain.dem");
  EXPECT_NE(terrain.error().message.find("searched " + (prefix_ / "share" / "skyroute").string()), std::string::npos)
      << terrain.error().message;
  EXPECT_NE(terrain.error().message.find("--dem"), std::string::npos) << terrain.error().message;

  auto other = findShippedData("feeds/none.jsonl", exe_);
  ASSERT_FALSE(other.ok());
  EXPECT_EQ(other.error().field, "feeds/none.jsonl");
}

TEST(ShippedDataOfThisProcess, TheTestBinaryResolvesFromProcSelfExe) {
  // This test runs from build/tests/, so its share/skyroute is build/share/skyroute.
  const auto dirs = shippedDataDirs();
  ASSERT_EQ(dirs.size(), 1u);
  const std::filesystem::path exe = std::filesystem::read_symlink("/proc/self/exe");
  EXPECT_EQ(dirs[0], (exe.parent_path().parent_path() / "share" / "skyroute").string());
}

}  // namespace
}  // namespace skyroute
