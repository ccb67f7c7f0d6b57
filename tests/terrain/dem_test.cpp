// DEM loading, the local frame and the heightfield, on the real DEMs and the embedded terrain.
#include <cmath>
#include <cstdio>
#include <random>

#include <cpl_string.h>
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
