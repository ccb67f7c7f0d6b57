// `skyroute plan` with a bad point, as a user runs it: the message names the point as written on
// the command line (latitude, longitude, altitude AMSL) and says what is wrong with it.
#include <gtest/gtest.h>

#include "tests/cli_run.hpp"

namespace skyroute {
namespace {

using testing::runCli;

// The embedded terrain lies around 46.94 N, 15.10 E.
TEST(PointErrorsCli, SwappedLatitudeAndLongitudeAreNamed) {
  const auto out = runCli("plan --from 15.1,46.93,1200 --to 46.96,15.1,1200");
  EXPECT_EQ(out.exit_code, 2) << out.text;
  EXPECT_NE(out.text.find("begin (15.1, 46.93, 1200 m AMSL)"), std::string::npos) << out.text;
  EXPECT_NE(out.text.find("latitude and longitude may be swapped"), std::string::npos) << out.text;
  EXPECT_EQ(out.text.find("ENU"), std::string::npos) << out.text;
}

TEST(PointErrorsCli, UnderTheGroundGivesTheGroundHeight) {
  const auto out = runCli("plan --from 46.93,15.1,100 --to 46.96,15.1,1200");
  EXPECT_EQ(out.exit_code, 2) << out.text;
  EXPECT_NE(out.text.find("begin (46.93, 15.1, 100 m AMSL) is under the ground plus clearance: the ground here is "),
            std::string::npos)
      << out.text;
}

TEST(PointErrorsCli, OutsideTheDemGivesItsBounds) {
  const auto out = runCli("plan --from 46.93,15.1,1200 --to 47.5,15.1,1200");
  EXPECT_EQ(out.exit_code, 2) << out.text;
  EXPECT_NE(out.text.find("end (47.5, 15.1, 1200 m AMSL) is outside the DEM (lat 46.8"), std::string::npos) << out.text;
}

}  // namespace
}  // namespace skyroute
