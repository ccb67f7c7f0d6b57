// Trajectory exports read back as a GIS reads them (GDAL/OGR): every attribute in its field, every
// vertex, the height datum each format promises (KML absolute = AMSL, GeoJSON z = ellipsoidal), one
// colour per vehicle in KML, the CSV's ellipsoidal column, and no file at all without the geoid grid.
#include "service/trajectory_export.hpp"
#include "tests/test_folder.hpp"
#include "tests/text_file.hpp"

#include <gdal.h>
#include <gtest/gtest.h>
#include <ogr_api.h>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <functional>
#include <memory>
#include <nlohmann/json.hpp>
#include <regex>
#include <set>
#include <sstream>

namespace skyroute {
namespace {

TrajectoryData trajectoryOf(const std::string& vehicle, std::uint32_t revision, int samples, double lat0) {
  TrajectoryData t;
  t.vehicle_id = vehicle;
  t.plan_id = "plan-" + vehicle;
  t.revision = revision;
  t.request_id = "req-" + vehicle + "-" + std::to_string(revision);
  for (int i = 0; i < samples; ++i) {
    TrajectorySampleData s;
    s.t_rel_s = 0.25 * i;
    s.position_enu_m = Eigen::Vector3d(12.5 * i, 3.0 * i, 850.0 + 2.0 * i);
    s.velocity_enu_mps = Eigen::Vector3d(50.0, 12.0, 8.0);
    s.heading_deg = 76.5;
    s.geo = GeoPoint{lat0 + 1.234567e-4 * i, 15.05 + 2.345678e-4 * i, 850.125 + 2.0 * i};
    t.samples.push_back(s);
  }
  return t;
}

std::string slurp(const std::string& path) { return skyroute::testing::readTextFile(path); }

struct DatasetCloser {
  void operator()(void* ds) const { GDALClose(ds); }
};
using Dataset = std::unique_ptr<void, DatasetCloser>;

Dataset openWith(const std::string& path, const char* driver) {
  GDALAllRegister();
  const char* const drivers[] = {driver, nullptr};
  return Dataset(GDALOpenEx(path.c_str(), GDAL_OF_VECTOR, drivers, nullptr, nullptr));
}

class TrajectoryExportTest : public testing::TestFolderTest {
 protected:
  TrajectoryExportTest() : TestFolderTest("skyroute_trajectory_export_test_") {}
  void SetUp() override {
    TestFolderTest::SetUp();
    std::filesystem::create_directories(dir_ / "empty");
    fleet_ = {trajectoryOf("alpha", 3, 13, 46.93), trajectoryOf("bravo", 1, 7, 46.94),
              trajectoryOf("charlie", 12, 9, 46.95)};
  }
  std::string path(const std::string& name) const { return (dir_ / name).string(); }

  std::vector<TrajectoryData> fleet_;
};

// Reads every feature back and checks each attribute against the trajectory it came from, and
// each vertex against its sample (z through expected_z).
void expectFeatures(OGRLayerH layer, const std::vector<TrajectoryData>& fleet, const std::string& datum,
                    const std::function<double(const TrajectorySampleData&)>& expected_z, double xy_tol) {
  ASSERT_EQ(OGR_L_GetFeatureCount(layer, TRUE), static_cast<GIntBig>(fleet.size()));
  OGR_L_ResetReading(layer);
  for (const TrajectoryData& t : fleet) {
    OGRFeatureH f = OGR_L_GetNextFeature(layer);
    ASSERT_NE(f, nullptr);
    auto text = [f](const char* name) {
      const int i = OGR_F_GetFieldIndex(f, name);
      return i < 0 ? std::string("<no field ") + name + ">" : std::string(OGR_F_GetFieldAsString(f, i));
    };
    auto number = [f](const char* name) { return OGR_F_GetFieldAsDouble(f, OGR_F_GetFieldIndex(f, name)); };
    EXPECT_EQ(text("vehicle_id"), t.vehicle_id);
    EXPECT_EQ(text("plan_id"), t.plan_id);
    EXPECT_EQ(OGR_F_GetFieldAsInteger(f, OGR_F_GetFieldIndex(f, "revision")), static_cast<int>(t.revision));
    EXPECT_EQ(text("request_id"), t.request_id);
    EXPECT_NEAR(number("duration_s"), t.samples.back().t_rel_s, 1e-9);
    EXPECT_EQ(OGR_F_GetFieldAsInteger(f, OGR_F_GetFieldIndex(f, "samples")), static_cast<int>(t.samples.size()));
    EXPECT_EQ(text("height_datum"), datum);
    OGRGeometryH line = OGR_F_GetGeometryRef(f);
    ASSERT_NE(line, nullptr);
    ASSERT_EQ(OGR_G_GetPointCount(line), static_cast<int>(t.samples.size()));
    for (int i = 0; i < OGR_G_GetPointCount(line); ++i) {
      const auto& s = t.samples[static_cast<std::size_t>(i)];
      EXPECT_NEAR(OGR_G_GetX(line, i), s.geo.lon_deg, xy_tol);
      EXPECT_NEAR(OGR_G_GetY(line, i), s.geo.lat_deg, xy_tol);
      EXPECT_NEAR(OGR_G_GetZ(line, i), expected_z(s), 1e-6);
    }
    OGR_F_Destroy(f);
  }
}

TEST_F(TrajectoryExportTest, KmlHasEveryFieldAbsoluteAltitudesAndOneColourPerVehicle) {
  const std::string kml = path("fleet.kml");
  // No geoid needed for KML (AMSL): a folder without the grid must not matter.
  ASSERT_TRUE(writeTrajectoriesOgr(kml, "KML", fleet_, GeoidOptions{{(dir_ / "empty").string()}}).ok());
  // LIBKML reads the ExtendedData fields (the plain KML reader keeps only name and description).
  Dataset ds = openWith(kml, "LIBKML");
  ASSERT_TRUE(ds) << CPLGetLastErrorMsg();
  ASSERT_EQ(GDALDatasetGetLayerCount(ds.get()), 1);
  OGRLayerH layer = GDALDatasetGetLayer(ds.get(), 0);
  expectFeatures(
      layer, fleet_, kAmslDatumName, [](const TrajectorySampleData& s) { return s.geo.alt_amsl_m; }, 1e-12);
  OGR_L_ResetReading(layer);
  for (const TrajectoryData& t : fleet_) {
    OGRFeatureH f = OGR_L_GetNextFeature(layer);
    EXPECT_EQ(std::string(OGR_F_GetFieldAsString(f, OGR_F_GetFieldIndex(f, "Name"))), t.vehicle_id);
    EXPECT_EQ(std::string(OGR_F_GetFieldAsString(f, OGR_F_GetFieldIndex(f, "altitudeMode"))), "absolute");
    OGR_F_Destroy(f);
  }

  // In the text: an absolute altitude mode and a distinct line colour on every placemark.
  const std::string text = slurp(kml);
  std::size_t absolute = 0;
  for (std::size_t at = text.find("<altitudeMode>absolute</altitudeMode>"); at != std::string::npos;
       at = text.find("<altitudeMode>absolute</altitudeMode>", at + 1))
    ++absolute;
  EXPECT_EQ(absolute, fleet_.size());
  std::set<std::string> colours;
  const std::regex colour("<LineStyle><color>([0-9A-Fa-f]{8})</color>");
  for (auto it = std::sregex_iterator(text.begin(), text.end(), colour); it != std::sregex_iterator(); ++it)
    colours.insert((*it)[1]);
  EXPECT_EQ(colours.size(), fleet_.size()) << text;
  // KML writes aabbggrr: the first vehicle's palette red #E6194B.
  EXPECT_TRUE(colours.count("FF4B19E6")) << text;
}

TEST_F(TrajectoryExportTest, GeoJsonZIsEllipsoidalAndNamedSo) {
  auto geoid = Egm96Geoid::load();
  ASSERT_TRUE(geoid.ok()) << geoid.error().describe();
  const std::string file = path("fleet.geojson");
  ASSERT_TRUE(writeTrajectoriesOgr(file, "GeoJSON", fleet_).ok());
  Dataset ds = openWith(file, "GeoJSON");
  ASSERT_TRUE(ds) << CPLGetLastErrorMsg();
  expectFeatures(
      GDALDatasetGetLayer(ds.get(), 0), fleet_, kEllipsoidDatumName,
      [&](const TrajectorySampleData& s) {
        return *geoid->ellipsoidFromAmslM(s.geo.lat_deg, s.geo.lon_deg, s.geo.alt_amsl_m);
      },
      1e-9);
  // The undulation here is about +47 m: the z really moved.
  const double n = *geoid->undulationM(46.93, 15.05);
  EXPECT_GT(n, 40.0);
  const nlohmann::json j = nlohmann::json::parse(slurp(file));
  EXPECT_FALSE(j.contains("crs"));  // RFC 7946: WGS84 only, no crs member
  EXPECT_NEAR(j["features"][0]["geometry"]["coordinates"][0][2].get<double>(), 850.125 + n, 1e-6);
}

TEST_F(TrajectoryExportTest, WithoutTheGridNoGeoJsonOrCsvIsWritten) {
  const GeoidOptions no_grid{{(dir_ / "empty").string()}};
  const std::string geojson = path("nogrid.geojson"), csv = path("nogrid.csv"), samples = path("nogrid_samples.csv");
  Status s = writeTrajectoriesOgr(geojson, "GeoJSON", fleet_, no_grid);
  ASSERT_FALSE(s.ok());
  EXPECT_EQ(s.error().code, ErrorCode::kFileNotFound);
  EXPECT_EQ(s.error().field, "egm96_15.gtx");
  EXPECT_FALSE(std::filesystem::exists(geojson));
  s = writeTrajectoriesCsv(csv, fleet_, no_grid);
  ASSERT_FALSE(s.ok());
  EXPECT_EQ(s.error().field, "egm96_15.gtx");
  EXPECT_FALSE(std::filesystem::exists(csv));
  s = writeGeoSamplesCsv(samples, {GeoSample{}}, no_grid);
  ASSERT_FALSE(s.ok());
  EXPECT_FALSE(std::filesystem::exists(samples));
}

TEST_F(TrajectoryExportTest, OtherDriversAreRefused) {
  Status s = writeTrajectoriesOgr(path("fleet.gpkg"), "GPKG", fleet_);
  ASSERT_FALSE(s.ok());
  EXPECT_EQ(s.error().code, ErrorCode::kInvalidArgument);
  EXPECT_NE(s.error().message.find("GeoJSON or KML"), std::string::npos);
}

TEST_F(TrajectoryExportTest, CsvNamesBothDatumsAndFillsTheEllipsoidalColumn) {
  auto geoid = Egm96Geoid::load();
  ASSERT_TRUE(geoid.ok()) << geoid.error().describe();
  const std::string file = path("fleet.csv");
  ASSERT_TRUE(writeTrajectoriesCsv(file, fleet_).ok());
  std::istringstream lines(slurp(file));
  std::string header, row;
  std::getline(lines, header);
  EXPECT_EQ(header, std::string("vehicle_id,") + kTrajectoryDataCsvHeader);
  EXPECT_EQ(header.substr(header.rfind(',') + 1), "alt_ellipsoid_m");
  std::size_t rows = 0;
  while (std::getline(lines, row)) {
    const std::string vehicle = row.substr(0, row.find(','));
    double time = 0, lat = 0, lon = 0, amsl = 0;
    ASSERT_EQ(std::sscanf(row.c_str() + vehicle.size() + 1, "%lf,%lf,%lf,%lf", &time, &lat, &lon, &amsl), 4) << row;
    const double ellipsoid = std::stod(row.substr(row.rfind(',') + 1));
    EXPECT_NEAR(ellipsoid, *geoid->ellipsoidFromAmslM(lat, lon, amsl), 1e-3) << row;
    ++rows;
  }
  EXPECT_EQ(rows, 13u + 7u + 9u);
}

TEST_F(TrajectoryExportTest, PlanCsvGainsTheEllipsoidalColumnLast) {
  auto geoid = Egm96Geoid::load();
  ASSERT_TRUE(geoid.ok()) << geoid.error().describe();
  std::vector<GeoSample> samples(3);
  for (std::size_t i = 0; i < samples.size(); ++i) {
    samples[i].state.time_s = static_cast<double>(i);
    samples[i].lat_deg = 46.93 + 0.001 * static_cast<double>(i);
    samples[i].lon_deg = 15.05;
    samples[i].alt_amsl_m = 900.0 + static_cast<double>(i);
  }
  const std::string file = path("plan.csv");
  ASSERT_TRUE(writeGeoSamplesCsv(file, samples).ok());
  std::istringstream lines(slurp(file));
  std::string header, row;
  std::getline(lines, header);
  EXPECT_EQ(header, kTrajectoryCsvHeader);
  for (const GeoSample& g : samples) {
    ASSERT_TRUE(std::getline(lines, row));
    EXPECT_NEAR(std::stod(row.substr(row.rfind(',') + 1)),
                *geoid->ellipsoidFromAmslM(g.lat_deg, g.lon_deg, g.alt_amsl_m), 1e-3);
  }
}

TEST(VehicleColour, DistinctForManyVehicles) {
  std::set<std::string> seen;
  for (std::size_t i = 0; i < 64; ++i) {
    const std::string c = vehicleColourHex(i);
    EXPECT_TRUE(std::regex_match(c, std::regex("#[0-9A-F]{6}"))) << c;
    seen.insert(c);
  }
  EXPECT_EQ(seen.size(), 64u);
}

}  // namespace
}  // namespace skyroute
