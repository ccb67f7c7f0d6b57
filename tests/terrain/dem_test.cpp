// DEM loading, the local frame and the heightfield, on the real DEMs and the embedded terrain.
#include <chrono>
#include <cmath>
#include <cstdio>
#include <limits>
#include <random>

#include <cpl_conv.h>
#include <cpl_string.h>
#include <cpl_vsi.h>
#include <gdal.h>
#include <gtest/gtest.h>
#include <ogr_srs_api.h>

#include "terrain/dem.hpp"
#include "terrain/heightfield.hpp"
#include "terrain/local_frame.hpp"
#include "tests/terrain_data.hpp"
#include "tests/test_data.hpp"

namespace skyroute {
namespace {

constexpr double kMetresPerDegree = 111320.0;

std::string utmWkt() { return testing::epsgWkt(32633); }

// Writes a small GeoTIFF for the bad-input tests; `values` row-major.
std::string writeTiff(const std::string& name, int w, int h, int bands, const std::vector<float>& values,
                      bool with_crs, const char* unit = nullptr, std::optional<double> nodata = std::nullopt,
                      double scale = 1.0, double offset = 0.0) {
  GDALAllRegister();
  const std::string path = ::testing::TempDir() + "/" + name;
  GDALDatasetH ds = GDALCreate(GDALGetDriverByName("GTiff"), path.c_str(), w, h, bands, GDT_Float32, nullptr);
  double gt[6] = {500000.0, 30.0, 0.0, 5200000.0, 0.0, -30.0};
  GDALSetGeoTransform(ds, gt);
  if (with_crs) GDALSetProjection(ds, utmWkt().c_str());
  for (int b = 1; b <= bands; ++b) {
    GDALRasterBandH band = GDALGetRasterBand(ds, b);
    if (unit) GDALSetRasterUnitType(band, unit);
    if (nodata) GDALSetRasterNoDataValue(band, *nodata);
    if (scale != 1.0) GDALSetRasterScale(band, scale);
    if (offset != 0.0) GDALSetRasterOffset(band, offset);
    std::vector<float> copy = values;
    EXPECT_EQ(GDALRasterIO(band, GF_Write, 0, 0, w, h, copy.data(), w, h, GDT_Float32, 0, 0), CE_None);
  }
  GDALClose(ds);
  return path;
}

std::vector<float> ramp(int w, int h) {
  std::vector<float> v(static_cast<std::size_t>(w) * h);
  for (int r = 0; r < h; ++r)
    for (int c = 0; c < w; ++c) v[static_cast<std::size_t>(r) * w + c] = static_cast<float>(100 + 2 * c + 3 * r);
  return v;
}

TEST(Dem, MountWashingtonIsTheHighestGroundOfItsTile) {
  SKYROUTE_REQUIRE_SHARED(path, "dem/N44W072.hgt");
  auto dem = Dem::load(path);
  ASSERT_TRUE(dem.ok()) << dem.error().describe();
  EXPECT_TRUE((*dem)->isGeographic());
  EXPECT_EQ((*dem)->width(), 1201);
  EXPECT_NEAR((*dem)->maxHeightM(), 1908.0, 0.5);
  // Where is the highest cell? Within a few hundred metres of the summit's published position.
  const auto& cells = (*dem)->cells();
  const auto top = std::max_element(cells.begin(), cells.end());
  const int index = static_cast<int>(top - cells.begin());
  const Eigen::Vector2d lonlat = (*dem)->pixelToCrs(index % 1201 + 0.5, index / 1201 + 0.5);
  EXPECT_NEAR(lonlat.y(), 44.2706, 0.005);
  EXPECT_NEAR(lonlat.x(), -71.3033, 0.005);

  auto hf = Heightfield::build(*dem);
  ASSERT_TRUE(hf.ok()) << hf.error().describe();
  const Eigen::Vector3d summit = (*hf)->frame().toEnu(GeoPoint{44.2706, -71.3033, 0.0});
  const auto h = (*hf)->height(summit.head<2>());
  ASSERT_TRUE(h.has_value());
  EXPECT_NEAR(*h, 1900.0, 25.0);
}

TEST(Dem, ProjectedDavosHasItsCrsAndAlpineHeights) {
  SKYROUTE_REQUIRE_SHARED(path, "dem/davosdorf.tif");
  auto dem = Dem::load(path);
  ASSERT_TRUE(dem.ok()) << dem.error().describe();
  EXPECT_FALSE((*dem)->isGeographic());
  EXPECT_NE((*dem)->crsName().find("21781"), std::string::npos) << (*dem)->crsName();
  EXPECT_EQ((*dem)->width(), 559);
  EXPECT_EQ((*dem)->height(), 495);
  EXPECT_GT((*dem)->minHeightM(), 1000.0);
  EXPECT_LT((*dem)->maxHeightM(), 3500.0);
  EXPECT_NEAR((*dem)->resolutionM().x(), 10.0, 0.5);
}

TEST(Dem, EmbeddedDefaultTerrainLoads) {
  auto dem = Dem::load(testing::projectDataPath("default_terrain.tif"));
  ASSERT_TRUE(dem.ok()) << dem.error().describe();
  EXPECT_EQ((*dem)->unknownCells(), 0);
  EXPECT_GT((*dem)->maxHeightM() - (*dem)->minHeightM(), 400.0);  // mountains to climb or go around
}

TEST(Dem, LoadsFromGdalVirtualPaths) {
  // An in-memory copy of a file on disk: the same DEM through /vsimem/.
  const std::string disk = writeTiff("vsimem_source.tif", 4, 4, 1, ramp(4, 4), true);
  const std::string memory = "/vsimem/dem_test/ramp.tif";
  ASSERT_EQ(CPLCopyFile(memory.c_str(), disk.c_str()), 0);
  auto dem = Dem::load(memory);
  ASSERT_TRUE(dem.ok()) << dem.error().describe();
  EXPECT_EQ((*dem)->width(), 4);
  EXPECT_EQ((*dem)->maxHeightM(), 100 + 2 * 3 + 3 * 3);
  VSIUnlink(memory.c_str());
  EXPECT_EQ(Dem::load(memory).error().code, ErrorCode::kFileNotFound);
  VSIMkdir("/vsimem/dem_test_dir", 0755);
  EXPECT_EQ(Dem::load("/vsimem/dem_test_dir").error().code, ErrorCode::kNotARaster);
}

TEST(Dem, RefusesACrsWithoutHorizontalCoordinates) {
  OGRSpatialReferenceH geocentric = OSRNewSpatialReference(nullptr);
  ASSERT_EQ(OSRSetFromUserInput(geocentric, "EPSG:4978"), OGRERR_NONE);  // WGS 84 earth-centred X, Y, Z
  char* wkt = nullptr;
  OSRExportToWkt(geocentric, &wkt);
  const auto dem = Dem::fromArray(2, 2, {1, 2, 3, 4}, {0, 1, 0, 0, 0, -1}, wkt, "geocentric");
  CPLFree(wkt);
  OSRDestroySpatialReference(geocentric);
  ASSERT_FALSE(dem.ok());
  EXPECT_EQ(dem.error().code, ErrorCode::kNoCrs);
  EXPECT_NE(dem.error().message.find("neither geographic nor projected"), std::string::npos) << dem.error().message;
}

TEST(Dem, RefusesMoreCellsThanTheLimitBeforeReadingThem) {
  const std::string path = writeTiff("limit.tif", 4, 4, 1, ramp(4, 4), true);
  EXPECT_TRUE(Dem::load(path, DemLoadOptions{.max_cells = 16}).ok());
  const auto refused = Dem::load(path, DemLoadOptions{.max_cells = 15});
  ASSERT_FALSE(refused.ok());
  EXPECT_EQ(refused.error().code, ErrorCode::kInvalidArgument);
  EXPECT_NE(refused.error().message.find("4 x 4 cells"), std::string::npos) << refused.error().message;
}

// A 200 x 4 DEM of cells `width_deg` wide and 20 degrees tall, all at 300 m.
std::shared_ptr<const Dem> sliverDem(const std::string& name, double width_deg) {
  GDALAllRegister();
  const std::string path = ::testing::TempDir() + "/" + name;
  GDALDatasetH ds = GDALCreate(GDALGetDriverByName("GTiff"), path.c_str(), 200, 4, 1, GDT_Float32, nullptr);
  double gt[6] = {0.0, width_deg, 0.0, 45.0, 0.0, -20.0};
  GDALSetGeoTransform(ds, gt);
  GDALSetProjection(ds, testing::epsgWkt(4326).c_str());
  std::vector<float> heights(800, 300.f);
  EXPECT_EQ(GDALRasterIO(GDALGetRasterBand(ds, 1), GF_Write, 0, 0, 200, 4, heights.data(), 200, 4, GDT_Float32, 0, 0),
            CE_None);
  GDALClose(ds);
  auto dem = Dem::load(path);
  EXPECT_TRUE(dem.ok()) << dem.error().describe();
  return dem.ok() ? *dem : nullptr;
}

TEST(Heightfield, LatticeOfCellsFarLongerThanWideStaysSmall) {
  // At 8 of the narrow cells per node, the lattice of these 1e-6 degree cells would have about a
  // billion nodes.
  auto dem = sliverDem("sliver.tif", 1e-6);
  ASSERT_TRUE(dem);
  auto hf = Heightfield::build(dem);
  ASSERT_TRUE(hf.ok()) << hf.error().describe();
  EXPECT_LT((*hf)->memoryBytes(), std::size_t{4} << 20);
}

TEST(Heightfield, DilationMatchesTheWindowByBruteForce) {
  // Random heights on 30 m x 45 m cells, with a void too large to be filled (80 cells).
  constexpr int w = 23;
  constexpr int h = 17;
  std::mt19937 rng(7);
  std::uniform_real_distribution<float> height(0.f, 500.f);
  std::vector<float> heights(w * h);
  for (float& v : heights) v = height(rng);
  for (int r = 0; r < 8; ++r)
    for (int c = 0; c < 10; ++c) heights[r * w + c] = std::numeric_limits<float>::quiet_NaN();
  auto dem = Dem::fromArray(w, h, heights, {500000.0, 30.0, 0.0, 5200000.0, 0.0, -45.0}, utmWkt(), "random");
  ASSERT_TRUE(dem.ok()) << dem.error().describe();
  auto hf = Heightfield::build(*dem);
  ASSERT_TRUE(hf.ok()) << hf.error().describe();
  const Eigen::Vector2d res = (*dem)->resolutionM();
  for (const double radius_m : {10.0, 40.0, 100.0, 333.0, 2000.0}) {
    const auto dilated = (*hf)->dilated(radius_m);
    const int rx = static_cast<int>(std::ceil(radius_m / res.x()));
    const int ry = static_cast<int>(std::ceil(radius_m / res.y()));
    for (int row = 0; row < h; ++row) {
      for (int col = 0; col < w; ++col) {
        // The definition: the highest cell whose centre is within the radius plus half a diagonal.
        float expected = -std::numeric_limits<float>::infinity();
        for (int dy = -ry; dy <= ry; ++dy) {
          for (int dx = -rx; dx <= rx; ++dx) {
            const int c = col + dx;
            const int r = row + dy;
            if (c < 0 || r < 0 || c >= w || r >= h) continue;
            if (std::hypot(dx * res.x(), dy * res.y()) > radius_m + 0.5 * res.norm()) continue;
            const float v = (*hf)->heightCell(c, r);
            expected = std::isnan(v) || std::isnan(expected) ? std::numeric_limits<float>::quiet_NaN()
                                                             : std::max(expected, v);
          }
        }
        const float got = dilated->heightCell(col, row);
        if (std::isnan(expected)) {
          EXPECT_TRUE(std::isnan(got)) << radius_m << " m at " << col << "," << row;
        } else {
          EXPECT_EQ(got, expected) << radius_m << " m at " << col << "," << row;
        }
      }
    }
  }
}

TEST(Heightfield, DilationWindowStopsAtTheRasterEdge) {
  // 30 m spans 380,000 of these 1e-9 degree cells: a window that size for each of 800 cells never
  // finished; no offset past the raster's 200 columns can reach a cell anyway.
  auto dem = sliverDem("needle.tif", 1e-9);
  ASSERT_TRUE(dem);
  auto hf = Heightfield::build(dem);
  ASSERT_TRUE(hf.ok()) << hf.error().describe();
  const auto started = std::chrono::steady_clock::now();
  const auto dilated = (*hf)->dilated(30.0);
  EXPECT_LT(std::chrono::duration<double>(std::chrono::steady_clock::now() - started).count(), 5.0);
  EXPECT_EQ(dilated->maxHeightM(), 300.0);
}

TEST(Dem, BadInputGetsTypedErrorsNamingTheFile) {
  EXPECT_EQ(Dem::load("/nonexistent/x.tif").error().code, ErrorCode::kFileNotFound);
  const std::string text = ::testing::TempDir() + "/not_a_raster.tif";
  FILE* f = std::fopen(text.c_str(), "w");
  std::fputs("hello", f);
  std::fclose(f);
  const auto not_raster = Dem::load(text);
  ASSERT_FALSE(not_raster.ok());
  EXPECT_EQ(not_raster.error().code, ErrorCode::kNotARaster);
  EXPECT_EQ(not_raster.error().field, text);

  EXPECT_EQ(Dem::load(writeTiff("nocrs.tif", 4, 4, 1, ramp(4, 4), false)).error().code, ErrorCode::kNoCrs);
  const std::string two = writeTiff("two.tif", 4, 4, 2, ramp(4, 4), true);
  EXPECT_EQ(Dem::load(two).error().code, ErrorCode::kBandAmbiguous);
  EXPECT_TRUE(Dem::load(two, DemLoadOptions{.band = 2}).ok());
  EXPECT_EQ(Dem::load(two, DemLoadOptions{.band = 3}).error().code, ErrorCode::kInvalidArgument);
  EXPECT_EQ(Dem::load(writeTiff("nodata.tif", 4, 4, 1, std::vector<float>(16, -9999.f), true, nullptr, -9999.0))
                .error()
                .code,
            ErrorCode::kAllNodata);
  EXPECT_EQ(Dem::load(writeTiff("absurd.tif", 4, 4, 1, std::vector<float>(16, 60000.f), true)).error().code,
            ErrorCode::kAbsurdHeights);
  const auto bad_unit = Dem::load(writeTiff("unit.tif", 4, 4, 1, ramp(4, 4), true, "kg"));
  EXPECT_EQ(bad_unit.error().code, ErrorCode::kInvalidArgument);
  EXPECT_NE(bad_unit.error().message.find("kg"), std::string::npos);
}

TEST(Dem, HonoursUnitsScaleOffsetAndVoids) {
  auto feet = Dem::load(writeTiff("feet.tif", 4, 4, 1, ramp(4, 4), true, "ft"));
  ASSERT_TRUE(feet.ok());
  EXPECT_NEAR((*feet)->cell(0, 0), 100 * 0.3048, 1e-3);
  auto scaled = Dem::load(writeTiff("scaled.tif", 4, 4, 1, ramp(4, 4), true, "m", std::nullopt, 0.5, 10.0));
  ASSERT_TRUE(scaled.ok());
  EXPECT_NEAR((*scaled)->cell(1, 0), 102 * 0.5 + 10.0, 1e-4);

  // One small void (2 cells) is filled; one large void (an 8 x 8 block) stays unknown.
  const int w = 20;
  std::vector<float> v = ramp(w, w);
  v[5 * w + 5] = -1.f;
  v[5 * w + 6] = -1.f;
  for (int r = 10; r < 18; ++r)
    for (int c = 10; c < 18; ++c) v[r * w + c] = -1.f;
  auto voids = Dem::load(writeTiff("voids.tif", w, w, 1, v, true, "m", -1.0), DemLoadOptions{.max_filled_void_cells = 16});
  ASSERT_TRUE(voids.ok()) << voids.error().describe();
  EXPECT_EQ((*voids)->filledVoidCells(), 2);
  EXPECT_EQ((*voids)->unknownCells(), 64);
  EXPECT_NEAR((*voids)->cell(5, 5), 100 + 2 * 5 + 3 * 5, 2.0);  // a plane is filled almost exactly
  EXPECT_TRUE(std::isnan((*voids)->cell(12, 12)));
}

class FrameAndHeightfield : public ::testing::TestWithParam<std::string> {};

TEST_P(FrameAndHeightfield, RoundTripsAndLatticeAreExact) {
  std::string path = GetParam() == "default" ? testing::projectDataPath("default_terrain.tif")
                                             : testing::sharedDataPath("dem/" + GetParam());
  if (path.empty()) SKYROUTE_SKIP_OR_FAIL_MISSING("dem/" + GetParam());
  auto dem = Dem::load(path);
  ASSERT_TRUE(dem.ok()) << dem.error().describe();
  auto hf_result = Heightfield::build(*dem);
  ASSERT_TRUE(hf_result.ok()) << hf_result.error().describe();
  const Heightfield& hf = **hf_result;
  const LocalFrame& frame = hf.frame();
  std::mt19937 rng(42);
  const auto& box = hf.boundsEn();
  std::uniform_real_distribution<double> ue(box.min().x(), box.max().x());
  std::uniform_real_distribution<double> un(box.min().y(), box.max().y());
  std::uniform_real_distribution<double> ua(-100.0, 5000.0);
  double worst_round_trip_m = 0.0;
  double worst_lattice_px = 0.0;
  for (int i = 0; i < 2000; ++i) {
    const Eigen::Vector3d p(ue(rng), un(rng), ua(rng));
    const GeoPoint g = frame.toGeo(p);
    const Eigen::Vector3d back = frame.toEnu(g);
    worst_round_trip_m = std::max(worst_round_trip_m, (back - p).norm());
    // And geodetic -> ENU -> geodetic, measured on the ground.
    const GeoPoint g2 = frame.toGeo(frame.toEnu(g));
    const double dn = (g2.lat_deg - g.lat_deg) * kMetresPerDegree;
    const double de = (g2.lon_deg - g.lon_deg) * kMetresPerDegree * std::cos(g.lat_deg * M_PI / 180.0);
    worst_round_trip_m = std::max(worst_round_trip_m, std::hypot(dn, de));
    EXPECT_DOUBLE_EQ(g.alt_amsl_m, p.z());  // default anchor altitude is 0: up == AMSL
    const Eigen::Vector2d fast = hf.enToPixel(p.x(), p.y());
    const Eigen::Vector2d exact = hf.enToPixelExact(p.x(), p.y());
    worst_lattice_px = std::max(worst_lattice_px, (fast - exact).norm());
    EXPECT_TRUE(hf.inside(p.x(), p.y()));
  }
  EXPECT_LT(worst_round_trip_m, 1e-3);
  EXPECT_LT(worst_lattice_px, 1e-3) << "lattice error in pixels";

  // At a cell centre the interpolated height is the cell's own value (no resampling).
  std::uniform_int_distribution<int> uc(1, (*dem)->width() - 2);
  std::uniform_int_distribution<int> ur(1, (*dem)->height() - 2);
  for (int i = 0; i < 200; ++i) {
    const int col = uc(rng);
    const int row = ur(rng);
    const Eigen::Vector2d en = hf.pixelToEn(col, row);
    if (!box.contains(en)) continue;
    EXPECT_NEAR(hf.heightAt(en.x(), en.y()), (*dem)->cell(col, row), 0.05);
  }
  // Outside the DEM there is no height, never a made-up one.
  const Eigen::Vector2d far_away = box.max() + Eigen::Vector2d(1e6, 1e6);
  EXPECT_FALSE(hf.height(far_away).has_value());
  EXPECT_FALSE(hf.heightAboveGround(Eigen::Vector3d(far_away.x(), far_away.y(), 100.0)).has_value());
  EXPECT_TRUE(std::isnan(hf.minHeightAboveGround(Eigen::Vector3d(0, 0, 5000), Eigen::Vector3d(far_away.x(), 0, 5000))));
}

INSTANTIATE_TEST_SUITE_P(Dems, FrameAndHeightfield, ::testing::Values("N44W072.hgt", "davosdorf.tif", "default"));

TEST(LocalFrame, RejectsBadAnchors) {
  EXPECT_EQ(LocalFrame::create(95.0, 0.0).error().field, "anchor_lat_deg");
  EXPECT_EQ(LocalFrame::create(0.0, std::nan("")).error().field, "anchor_lon_deg");
}

}  // namespace
}  // namespace skyroute
