// Map figures: the layout arithmetic (round steps, crop, ticks that fall where the frame crosses
// their latitude or longitude) against the local frame, and the saved picture read back with GDAL:
// markers, lines, hatched unknown cells and grid cells where the layout puts them.
#include "service/map_figure.hpp"

#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <filesystem>
#include <limits>

#include "tests/png_picture.hpp"
#include "tests/terrain_data.hpp"

namespace skyroute {
namespace {

using testing::nearRgb;
using testing::Picture;
using testing::readPng;

std::string scratchPng(const std::string& name) {
  return (std::filesystem::temp_directory_path() / ("skyroute_figure_" + name + ".png")).string();
}

TEST(FigureLayout, RoundStepsAndTicks) {
  EXPECT_DOUBLE_EQ(roundStepAtMost(740.0), 500.0);
  EXPECT_DOUBLE_EQ(roundStepAtMost(0.3), 0.2);
  EXPECT_DOUBLE_EQ(roundStepAtMost(1000.0), 1000.0);
  EXPECT_DOUBLE_EQ(roundStepAtLeast(0.031), 0.05);
  EXPECT_DOUBLE_EQ(roundStepAtLeast(1.2), 2.0);
  EXPECT_DOUBLE_EQ(roundStepAtLeast(6.0), 10.0);
  const std::vector<double> ticks = roundTicks(44.0123, 44.2871, 6);
  ASSERT_GE(ticks.size(), 3u);
  ASSERT_LE(ticks.size(), 12u);
  const double step = ticks[1] - ticks[0];
  for (double t : ticks) {
    EXPECT_GE(t, 44.0123);
    EXPECT_LE(t, 44.2871);
    EXPECT_NEAR(std::remainder(t, step), 0.0, 1e-9) << t;
  }
  EXPECT_GE(roundTicks(10.01, 10.02, 6).size(), 2u);  // a narrow span still gets two ticks
  EXPECT_TRUE(roundTicks(5.0, 5.0, 6).empty());
  EXPECT_EQ(formatLatitude(44.05, 0.05), "44.05\u00B0N");
  EXPECT_EQ(formatLongitude(-72.1, 0.1), "72.1\u00B0W");
  EXPECT_EQ(formatLongitude(0.0, 0.5), "0.0\u00B0");
  EXPECT_EQ(formatDistance(500.0), "500 m");
  EXPECT_EQ(formatDistance(2000.0), "2 km");
}

TEST(FigureLayout, CropGrowsByTheMarginAndStaysInside) {
  const Eigen::AlignedBox2d limits(Eigen::Vector2d(-5000, -5000), Eigen::Vector2d(5000, 5000));
  const Eigen::AlignedBox2d content(Eigen::Vector2d(-1000, 0), Eigen::Vector2d(1000, 500));
  const Eigen::AlignedBox2d crop = cropAround(content, limits, 0.15, 100.0);
  EXPECT_NEAR(crop.min().x(), -1300.0, 1e-9);  // 15 % of the 2000 m extent
  EXPECT_NEAR(crop.max().y(), 800.0, 1e-9);
  const Eigen::AlignedBox2d edge = cropAround(Eigen::AlignedBox2d(Eigen::Vector2d(4900, 4900), Eigen::Vector2d(4950, 4950)),
                                              limits, 0.15, 300.0);
  EXPECT_NEAR(edge.max().x(), 5000.0, 1e-9);
  EXPECT_NEAR(edge.min().x(), 4600.0, 1e-9);
  EXPECT_TRUE(cropAround(Eigen::AlignedBox2d(), limits, 0.15, 300.0).isApprox(limits));
  const MapViewport viewport(crop, 1000);
  EXPECT_EQ(viewport.widthPx(), 1000);
  EXPECT_EQ(viewport.heightPx(), 423);  // 1100 m of 2600 m
  const Eigen::Vector2d p(250.0, -120.0);
  EXPECT_TRUE(viewport.toEastNorth(viewport.toPixel(p)).isApprox(p));
}

TEST(MapFigure, TicksFallWhereTheFrameCrossesTheirLatitudeAndLongitude) {
  auto terrain = testing::defaultTerrainHeightfield();
  ASSERT_TRUE(terrain);
  const Eigen::AlignedBox2d b = terrain->boundsEn();
  MapFigureContent content;
  content.lines.push_back({"route", {b.center() - 0.3 * b.sizes(), b.center() + 0.2 * b.sizes()}, Rgb{220, 20, 20}});
  const TerrainFigureLayout layout = layoutTerrainFigure(*terrain, content);
  ASSERT_GE(layout.ticks.longitudes.size(), 2u);
  ASSERT_GE(layout.ticks.latitudes.size(), 2u);
  const MapViewport& v = layout.viewport;
  for (const FrameTick& t : layout.ticks.longitudes) {
    Eigen::Vector2d en = v.toEastNorth({t.at_px, v.heightPx()});
    terrain->frame().eastNorthToLonLat(&en.x(), &en.y(), 1);
    EXPECT_NEAR(en.x(), t.value, 1e-6) << t.label;
    EXPECT_GE(t.at_px, 0.0);
    EXPECT_LE(t.at_px, v.widthPx());
  }
  for (const FrameTick& t : layout.ticks.latitudes) {
    Eigen::Vector2d en = v.toEastNorth({0.0, t.at_px});
    terrain->frame().eastNorthToLonLat(&en.x(), &en.y(), 1);
    EXPECT_NEAR(en.y(), t.value, 1e-6) << t.label;
  }
  const double map_width_m = v.widthPx() * v.metresPerPixel();
  EXPECT_LE(layout.scale_bar_m, 0.25 * map_width_m);
  EXPECT_GE(layout.scale_bar_m, 0.1 * map_width_m);
  // Cropped: the map covers the route and its margin, not the whole terrain.
  EXPECT_LT(v.box().volume(), 0.95 * b.volume());
  EXPECT_TRUE(v.box().contains(b.center() - 0.3 * b.sizes()));
}

TEST(MapFigure, SavedPictureHasTheMarkersAndLinesWhereTheLayoutPutsThem) {
  auto terrain = testing::defaultTerrainHeightfield();
  ASSERT_TRUE(terrain);
  const Eigen::Vector2d c = terrain->boundsEn().center();
  const Eigen::Vector2d s = terrain->boundsEn().sizes();
  const Eigen::Vector2d start = c + Eigen::Vector2d(-0.3 * s.x(), -0.2 * s.y());
  const Eigen::Vector2d via = c + Eigen::Vector2d(0.0, 0.25 * s.y());
  const Eigen::Vector2d end = c + Eigen::Vector2d(0.3 * s.x(), -0.1 * s.y());
  MapFigureContent content;
  content.title = "test figure";
  content.lines.push_back({"trajectory", {start, via, end}, Rgb{230, 40, 200}, 4.0});
  content.markers.push_back({MarkerKind::kStart, start});
  content.markers.push_back({MarkerKind::kMissionPoint, via, 1, Rgb{30, 60, 200}});
  content.markers.push_back({MarkerKind::kEnd, end});
  FigureProfile profile;
  for (int i = 0; i <= 20; ++i) {
    profile.distance_m.push_back(100.0 * i);
    profile.altitude_m.push_back(500.0 + 3.0 * i);
    profile.ground_m.push_back(400.0 + 2.0 * i);
  }
  content.profile = profile;
  const std::string path = scratchPng("terrain");
  ASSERT_TRUE(saveTerrainFigure(*terrain, content, path).ok());
  const Picture picture = readPng(path);
  const TerrainFigureLayout layout = layoutTerrainFigure(*terrain, content);
  const Eigen::Vector2d origin = figureMapOrigin();
  ASSERT_GT(picture.width, layout.viewport.widthPx());
  ASSERT_GT(picture.height, layout.viewport.heightPx() + 150);  // the profile panel below
  auto pixelOf = [&](const Eigen::Vector2d& en) -> Eigen::Vector2d { return origin + layout.viewport.toPixel(en); };
  const Eigen::Vector2d start_px = pixelOf(start);
  EXPECT_TRUE(nearRgb(picture.at(start_px.x(), start_px.y() + 2), Rgb{20, 150, 40}));  // the green triangle
  const Eigen::Vector2d end_px = pixelOf(end);
  EXPECT_TRUE(nearRgb(picture.at(end_px.x(), end_px.y()), Rgb{200, 20, 20}));  // the red square
  const Eigen::Vector2d via_px = pixelOf(via);
  EXPECT_TRUE(nearRgb(picture.at(via_px.x() + 10, via_px.y()), Rgb{30, 60, 200}, 60));  // the numbered ring
  const Eigen::Vector2d mid_px = pixelOf(0.5 * (via + end));
  EXPECT_TRUE(nearRgb(picture.at(mid_px.x(), mid_px.y()), Rgb{230, 40, 200}));  // the line itself
  std::filesystem::remove(path);
}

TEST(MapFigure, UnknownTerrainIsHatchedNotColoured) {
  // A 60 x 60 DEM in UTM with a 20 x 20 block of unknown cells in the middle.
  std::vector<float> heights(60 * 60, 300.0f);
  for (int r = 20; r < 40; ++r) {
    for (int col = 20; col < 40; ++col) heights[static_cast<std::size_t>(r) * 60 + col] = std::numeric_limits<float>::quiet_NaN();
  }
  const std::array<double, 6> transform{500000.0, 30.0, 0.0, 4900000.0, 0.0, -30.0};
  auto dem = Dem::fromArray(60, 60, heights, transform, testing::epsgWkt(32618), "holes");
  ASSERT_TRUE(dem.ok()) << dem.error().describe();
  auto terrain = Heightfield::build(*dem);
  ASSERT_TRUE(terrain.ok()) << terrain.error().describe();
  MapFigureContent content;  // nothing drawn: the whole terrain is shown
  const std::string path = scratchPng("holes");
  ASSERT_TRUE(saveTerrainFigure(**terrain, content, path).ok());
  const Picture picture = readPng(path);
  const TerrainFigureLayout layout = layoutTerrainFigure(**terrain, content);
  const Eigen::Vector2d centre = figureMapOrigin() + layout.viewport.toPixel((*terrain)->boundsEn().center());
  int dark = 0, light = 0;
  for (int dy = -40; dy <= 40; ++dy) {
    for (int dx = -40; dx <= 40; ++dx) {
      const Rgb p = picture.at(centre.x() + dx, centre.y() + dy);
      dark += nearRgb(p, Rgb{150, 150, 150}, 2);
      light += nearRgb(p, Rgb{238, 238, 238}, 2);
    }
  }
  // Stripes: two pixels of eight dark, the rest light, and nothing else.
  EXPECT_EQ(dark + light, 81 * 81);
  EXPECT_NEAR(static_cast<double>(dark) / (dark + light), 0.25, 0.03);
  std::filesystem::remove(path);
}

TEST(MapFigure, GridCellsAndPathAreDrawnWhereTheyAre) {
  const GridLayer grid = GridLayer::fromRows({"..........", "..####....", "..####....", "..........", ".........."});
  MapFigureContent content;
  content.lines.push_back({"path", {{0, 0}, {1, 3}, {9, 4}}, Rgb{230, 40, 200}, 3.0});
  content.markers.push_back({MarkerKind::kStart, {0, 0}});
  content.markers.push_back({MarkerKind::kEnd, {9, 4}});
  MapFigureOptions options;
  options.min_margin_cells = 0.0;
  options.margin_fraction = 0.0;
  const std::string path = scratchPng("grid");
  ASSERT_TRUE(saveGridFigure(grid, false, content, path, options).ok());
  const Picture picture = readPng(path);
  // Without a margin the map is the path's box: cells 0..9 by rows 0..4, 100 pixels a cell.
  const double cell_px = 1000.0 / 9.0;
  const Eigen::Vector2d origin = figureMapOrigin();
  auto centreOf = [&](double x, double y) -> Eigen::Vector2d { return origin + cell_px * Eigen::Vector2d(x, y); };
  const Eigen::Vector2d blocked = centreOf(4.0, 1.5);  // inside the block, away from the path
  EXPECT_TRUE(nearRgb(picture.at(blocked.x(), blocked.y()), Rgb{90, 90, 90}, 2));
  const Eigen::Vector2d free = centreOf(7.0, 1.0);
  EXPECT_TRUE(nearRgb(picture.at(free.x(), free.y()), Rgb{255, 255, 255}, 2));
  const Eigen::Vector2d on_path = centreOf(5.5, 3.0 + (5.5 - 1.0) / 8.0);
  EXPECT_TRUE(nearRgb(picture.at(on_path.x(), on_path.y()), Rgb{230, 40, 200}));
  if (!::testing::Test::HasFailure()) std::filesystem::remove(path);
}

}  // namespace
}  // namespace skyroute
