// The memory guard: MemAvailable read from /proc/meminfo's text, and the refusal's words.
#include <gtest/gtest.h>

#include "service/memory_guard.hpp"
#include "terrain/terrain_octree.hpp"
#include "tests/terrain_data.hpp"

namespace skyroute {
namespace {

TEST(MemoryGuard, ReadsMemAvailable) {
  const std::string meminfo = "MemTotal:       24576000 kB\nMemFree:         1000000 kB\nMemAvailable:   16000000 kB\n";
  ASSERT_TRUE(parseMemAvailable(meminfo).has_value());
  EXPECT_EQ(*parseMemAvailable(meminfo), 16000000ull * 1024);
  EXPECT_FALSE(parseMemAvailable("MemTotal: 1 kB\n").has_value());
  const auto here = availableMemoryBytes();
  ASSERT_TRUE(here.has_value()) << "/proc/meminfo has no MemAvailable";
  EXPECT_GT(*here, 0u);
}

TEST(MemoryGuard, RefusalNamesTheOptionAndBothAmounts) {
  EXPECT_TRUE(checkMemoryEstimate(100, 200, "a limit", "--octree-res", "the octree").ok());
  const Status refused =
      checkMemoryEstimate(std::size_t{13} << 30, std::size_t{8} << 30, "half of MemAvailable", "--octree-res", "the octree at 10 m");
  ASSERT_FALSE(refused.ok());
  EXPECT_EQ(refused.error().field, "--octree-res");
  EXPECT_NE(refused.error().message.find("the octree at 10 m would take about 13.0 GiB, more than the 8.0 GiB"),
            std::string::npos)
      << refused.error().message;
  EXPECT_EQ(bytesText(std::size_t{512} << 20), "512 MiB");
}

// The estimate grows with the number of columns: halving the resolution quadruples it.
TEST(MemoryGuard, OctreeEstimateScalesWithTheColumns) {
  const auto terrain = testing::defaultTerrainHeightfield();
  ASSERT_TRUE(terrain);
  const double coarse = static_cast<double>(estimateOctreePeakBytes(*terrain, 20.0));
  const double fine = static_cast<double>(estimateOctreePeakBytes(*terrain, 10.0));
  EXPECT_NEAR(fine / coarse, 4.0, 0.1);
  // Above what the built octree takes (15 MB at 20 m on this terrain), below ten times that.
  EXPECT_GT(coarse, 15.0e6);
  EXPECT_LT(coarse, 150.0e6);
}

}  // namespace
}  // namespace skyroute
