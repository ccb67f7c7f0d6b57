// `--png` of `plan`, `fleet` and `grid path`, run as a user would: the picture is written, and what
// it should show is there in the colours the figure uses (read back with GDAL, not with the
// drawing library).
#include <filesystem>
#include <fstream>
#include <string>

#include <gtest/gtest.h>

#include "tests/cli_run.hpp"
#include "tests/png_picture.hpp"
#include "tests/test_data.hpp"
#include "tests/test_folder.hpp"

namespace {

using skyroute::Rgb;
using skyroute::testing::readPng;

constexpr Rgb kStartGreen{20, 150, 40};
constexpr Rgb kEndRed{200, 20, 20};
constexpr Rgb kBlockedGrey{90, 90, 90};

class FigureCli : public skyroute::testing::TestFolderTest {
 protected:
  FigureCli() : TestFolderTest("skyroute_figure_cli_test_") {}
};

TEST_F(FigureCli, PlanPictureShowsTheRouteMarkersAndProfile) {
  const std::string png = (dir_ / "plan.png").string();
  const auto r = skyroute::testing::runCli(
      "plan --dem " + skyroute::testing::projectDataPath("default_terrain.tif") +
      " --from 46.90,15.03,1100 --via 46.95,15.06,1150 --to 46.97,15.12,1100 --iterations 800 --budget-s 0 --png " + png);
  ASSERT_EQ(r.exit_code, 0) << r.text;
  const auto picture = readPng(png);
  ASSERT_GT(picture.width, 900);
  // The map (about as tall as the route's box plus margins) and the profile panel below it.
  ASSERT_GT(picture.height, 600);
  EXPECT_GT(picture.count(kStartGreen, 10), 60);  // the start triangle
  EXPECT_GT(picture.count(kEndRed, 10), 100);     // the end square
  EXPECT_GT(picture.count(Rgb{220, 20, 20}, 10), 1500);  // the trajectory and the flight profile
  EXPECT_GT(picture.count(Rgb{160, 120, 80}, 4), 5000);  // the ground in the profile
  EXPECT_GT(picture.count(Rgb{250, 217, 168}, 6), 1000);  // the clearance band over it (orange at 45 %)
}

TEST_F(FigureCli, FleetPictureShowsEveryVehicle) {
  const std::string png = (dir_ / "fleet.png").string();
  const auto r = skyroute::testing::runCli("fleet --file " +
                                           skyroute::testing::projectDataPath("missions/demo_fleet.json") +
                                           " --png " + png);
  ASSERT_EQ(r.exit_code, 0) << r.text;
  const auto picture = readPng(png);
  ASSERT_GT(picture.width, 900);
  // The demo fleet's three vehicles draw in three distinct colours; each shows up in quantity.
  int coloured_kinds = 0;
  for (const Rgb c : {Rgb{230, 25, 75}, Rgb{60, 180, 75}, Rgb{67, 99, 216}}) {
    coloured_kinds += picture.count(c, 6) > 300 ? 1 : 0;
  }
  EXPECT_EQ(coloured_kinds, 3) << r.text;
}

TEST_F(FigureCli, GridPathPictureShowsTheMapAndThePath) {
  const std::string map = (dir_ / "walls.map").string();
  {
    std::ofstream f(map);
    f << "type octile\nheight 12\nwidth 16\nmap\n";
    for (int y = 0; y < 12; ++y) f << (y >= 2 && y <= 9 ? "......@@@......." : "................") << "\n";
  }
  const std::string png = (dir_ / "path.png").string();
  const auto r = skyroute::testing::runCli("grid path --map " + map + " --from 1,6 --to 14,6 --algo theta --png " + png);
  ASSERT_EQ(r.exit_code, 0) << r.text;
  const auto picture = readPng(png);
  ASSERT_GT(picture.width, 900);
  EXPECT_GT(picture.count(kBlockedGrey, 2), 10000);  // the wall, cells about 60 pixels wide
  EXPECT_GT(picture.count(Rgb{220, 20, 20}, 10), 500);  // the path around it
  EXPECT_GT(picture.count(kStartGreen, 10), 60);
  const auto wrong = skyroute::testing::runCli("grid path --map " + map + " --from 1,6 --to 14,6 --algo theta --png " +
                                               (dir_ / "path.jpg").string());
  EXPECT_EQ(wrong.exit_code, 2);
  EXPECT_NE(wrong.text.find("--png"), std::string::npos) << wrong.text;
}

}  // namespace
