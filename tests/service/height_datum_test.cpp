// The EGM96 geoid through PROJ: undulations against published values, conversions both ways, and
// the missing-grid path, which must be an error and never a silent N = 0.
#include "service/height_datum.hpp"

#include <cmath>
#include <filesystem>
#include <string>

#include <gtest/gtest.h>

namespace skyroute {
namespace {

struct Reference {
  double lat_deg, lon_deg, undulation_m;
};

TEST(HeightDatum, UndulationMatchesPublishedEgm96Values) {
  auto geoid = Egm96Geoid::load();
  ASSERT_TRUE(geoid.ok()) << geoid.error().describe();
  EXPECT_NE(geoid->gridPath().find("egm96"), std::string::npos) << geoid->gridPath();
  const Reference references[] = {
      // PX4's default SITL home (Zurich), observed with this grid.
      {47.3977, 8.5456, 47.34},
      // NGA's EGM96 geoid calculator at 15' grid nodes.
      {42.0, -76.0, -32.894},
      {-42.0, 76.0, 20.927},
      {0.0, 0.0, 17.162},
      // NGA's EGM96 test points (spherical harmonics to degree 360; the grid's bilinear
      // interpolation stays within a few centimetres of them).
      {38.6281550, 269.7791550 - 360.0, -31.628},
      {-14.6212170, 305.0211140 - 360.0, -2.969},
      {46.8743190, 102.4487290, -43.575},
      {-23.6174460, 133.8747120, 15.871},
      {38.6254730, 359.9995000 - 360.0, 50.066},
      {-0.4667440, 0.0023000, 17.329},
  };
  for (const Reference& r : references) {
    auto n = geoid->undulationM(r.lat_deg, r.lon_deg);
    ASSERT_TRUE(n.ok()) << n.error().describe();
    EXPECT_NEAR(*n, r.undulation_m, 0.1) << r.lat_deg << ", " << r.lon_deg;
  }
}

TEST(HeightDatum, ConvertsBothWaysAndInBulk) {
  auto geoid = Egm96Geoid::load();
  ASSERT_TRUE(geoid.ok()) << geoid.error().describe();
  const double n = *geoid->undulationM(46.93, 15.08);
  auto h = geoid->ellipsoidFromAmslM(46.93, 15.08, 812.5);
  ASSERT_TRUE(h.ok());
  EXPECT_NEAR(*h, 812.5 + n, 1e-6);  // h = H + N
  auto back = geoid->amslFromEllipsoidM(46.93, 15.08, *h);
  ASSERT_TRUE(back.ok());
  EXPECT_NEAR(*back, 812.5, 1e-6);

  const std::vector<GeoPoint> points = {{47.3977, 8.5456, 500.0}, {42.0, -76.0, 100.0}, {-42.0, 76.0, 0.0}};
  auto bulk = geoid->ellipsoidHeightsM(points);
  ASSERT_TRUE(bulk.ok());
  ASSERT_EQ(bulk->size(), 3u);
  for (std::size_t i = 0; i < points.size(); ++i)
    EXPECT_NEAR((*bulk)[i], *geoid->ellipsoidFromAmslM(points[i].lat_deg, points[i].lon_deg, points[i].alt_amsl_m),
                1e-9);
}

TEST(HeightDatum, BadCoordinatesNameTheField) {
  auto geoid = Egm96Geoid::load();
  ASSERT_TRUE(geoid.ok());
  auto lat = geoid->undulationM(91.0, 0.0);
  ASSERT_FALSE(lat.ok());
  EXPECT_EQ(lat.error().code, ErrorCode::kInvalidArgument);
  EXPECT_EQ(lat.error().field, "point.lat_deg");
  auto bulk = geoid->ellipsoidHeightsM({{10.0, 10.0, 0.0}, {10.0, 200.0, 0.0}});
  ASSERT_FALSE(bulk.ok());
  EXPECT_EQ(bulk.error().field, "points[1].lon_deg");
  auto nan = geoid->ellipsoidFromAmslM(10.0, 10.0, std::nan(""));
  ASSERT_FALSE(nan.ok());
  EXPECT_EQ(nan.error().code, ErrorCode::kInvalidArgument);
}

class TempDir {
 public:
  explicit TempDir(const std::string& name)
      : path_(std::filesystem::path(::testing::TempDir()) / ("skyroute_" + name)) {
    std::filesystem::remove_all(path_);
    std::filesystem::create_directories(path_);
  }
  ~TempDir() { std::filesystem::remove_all(path_); }
  std::string str() const { return path_.string(); }
  const std::filesystem::path& path() const { return path_; }

 private:
  std::filesystem::path path_;
};

TEST(HeightDatum, MissingGridIsAnErrorNotZero) {
  TempDir empty("no_geoid_grid");
  auto geoid = Egm96Geoid::load(GeoidOptions{{empty.str()}});
  ASSERT_FALSE(geoid.ok()) << "loaded " << geoid->operationName() << " without a grid";
  EXPECT_EQ(geoid.error().code, ErrorCode::kFileNotFound);
  EXPECT_EQ(geoid.error().field, "egm96_15.gtx");
  EXPECT_NE(geoid.error().message.find("proj-data"), std::string::npos) << geoid.error().message;
  EXPECT_NE(geoid.error().message.find(empty.str()), std::string::npos) << geoid.error().message;

  // An ellipsoidal input needs the grid, and says so when it is created; an AMSL one does not.
  auto ellipsoid = InputHeightConverter::create(HeightReference::kEllipsoid, GeoidOptions{{empty.str()}});
  ASSERT_FALSE(ellipsoid.ok());
  EXPECT_EQ(ellipsoid.error().field, "egm96_15.gtx");
  auto amsl = InputHeightConverter::create(HeightReference::kAmsl, GeoidOptions{{empty.str()}});
  ASSERT_TRUE(amsl.ok()) << amsl.error().describe();
  auto same = amsl->toAmslM(46.9, 15.1, 1000.0, "--from");
  ASSERT_TRUE(same.ok());
  EXPECT_EQ(*same, 1000.0);
}

TEST(HeightDatum, GridFolderOptionFindsTheGrid) {
  auto installed = Egm96Geoid::load();
  ASSERT_TRUE(installed.ok()) << installed.error().describe();
  TempDir folder("geoid_grid_copy");
  const std::filesystem::path grid = installed->gridPath();
  std::filesystem::create_symlink(grid, folder.path() / grid.filename());
  auto geoid = Egm96Geoid::load(GeoidOptions{{folder.str()}});
  ASSERT_TRUE(geoid.ok()) << geoid.error().describe();
  EXPECT_EQ(std::filesystem::path(geoid->gridPath()).parent_path(), folder.path());
  EXPECT_NEAR(*geoid->undulationM(47.3977, 8.5456), *installed->undulationM(47.3977, 8.5456), 1e-9);
}

TEST(HeightDatum, InputHeightConverterTurnsEllipsoidalHeightsIntoAmsl) {
  auto geoid = Egm96Geoid::load();
  ASSERT_TRUE(geoid.ok());
  auto converter = InputHeightConverter::create(HeightReference::kEllipsoid);
  ASSERT_TRUE(converter.ok()) << converter.error().describe();
  auto amsl = converter->toAmslM(47.3977, 8.5456, 547.34, "--to");
  ASSERT_TRUE(amsl.ok());
  EXPECT_NEAR(*amsl, 547.34 - *geoid->undulationM(47.3977, 8.5456), 1e-6);
  auto bad = converter->toAmslM(47.0, 190.0, 500.0, "--via[1]");
  ASSERT_FALSE(bad.ok());
  EXPECT_EQ(bad.error().field, "--via[1].lon_deg");
}

TEST(HeightDatum, ParsesHeightReferenceNames) {
  EXPECT_EQ(parseHeightReference("amsl"), HeightReference::kAmsl);
  EXPECT_EQ(parseHeightReference("ellipsoid"), HeightReference::kEllipsoid);
  EXPECT_FALSE(parseHeightReference("AMSL").has_value());
  EXPECT_FALSE(parseHeightReference("wgs84").has_value());
  for (HeightReference r : {HeightReference::kAmsl, HeightReference::kEllipsoid})
    EXPECT_EQ(parseHeightReference(to_string(r)), r);
}

}  // namespace
}  // namespace skyroute
