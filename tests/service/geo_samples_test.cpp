// Trajectory samples in WGS84 through the local frame (round trip to ENU), and the CSV header and
// rows of `skyroute plan --out`.
#include "service/geo_samples.hpp"

#include <cstdio>
#include <fstream>
#include <sstream>

#include <gtest/gtest.h>

#include "terrain/local_frame.hpp"
#include "tests/trajectory/random_paths.hpp"
#include "trajectory/trajectory_builder.hpp"

namespace skyroute {
namespace {

Trajectory built(const std::vector<Eigen::Vector3d>& w) {
  auto b = buildTrajectory(w, VehicleLimits{});
  EXPECT_TRUE(b.ok());
  return b->trajectory;
}

TEST(GeoSamples, RoundTripThroughTheFrameAndCsv) {
  auto frame = LocalFrame::create(44.5, -71.5);
  ASSERT_TRUE(frame.ok()) << frame.error().describe();
  const auto w = testing::randomWalk(21, 6);
  const Trajectory t = built(w);
  const auto samples = t.sample(1.0);
  auto geo = toGeoSamples(samples, *frame);
  ASSERT_EQ(geo.size(), samples.size());
  for (const GeoSample& g : geo) {
    EXPECT_NEAR(g.alt_amsl_m, g.state.position_m.z(), 1e-9);  // default anchor: up == AMSL
    const Eigen::Vector3d back = frame->toEnu(GeoPoint{g.lat_deg, g.lon_deg, g.alt_amsl_m});
    EXPECT_LT((back - g.state.position_m).norm(), 1e-3);
    EXPECT_NEAR(g.lat_deg, 44.5, 0.2);
    EXPECT_NEAR(g.lon_deg, -71.5, 0.2);
  }
  // The ellipsoidal heights come from the service's geoid; unknown, nothing is written.
  std::ostringstream refused;
  const Status unknown = writeTrajectoryCsv(refused, geo);
  ASSERT_FALSE(unknown.ok());
  EXPECT_EQ(unknown.error().field, "samples[0].alt_ellipsoid_m");
  EXPECT_TRUE(refused.str().empty());
  for (GeoSample& g : geo) g.alt_ellipsoid_m = g.alt_amsl_m + 47.0;
  std::ostringstream csv;
  ASSERT_TRUE(writeTrajectoryCsv(csv, geo).ok());
  std::istringstream lines(csv.str());
  std::string header;
  std::getline(lines, header);
  EXPECT_EQ(header.rfind("time_s,lat_deg,lon_deg,alt_amsl_m,east_m,north_m,up_m,v_east_mps,v_north_mps,v_up_mps,"
                         "heading_deg",
                         0),
            0u);
  std::size_t rows = 0;
  std::string row;
  while (std::getline(lines, row)) {
    ++rows;
    double time = -1, lat = 0, lon = 0;
    ASSERT_EQ(std::sscanf(row.c_str(), "%lf,%lf,%lf", &time, &lat, &lon), 3);
    EXPECT_NEAR(time, geo[rows - 1].state.time_s, 1e-4);
    EXPECT_NEAR(lat, geo[rows - 1].lat_deg, 1e-9);
  }
  EXPECT_EQ(rows, geo.size());
  const std::string path = ::testing::TempDir() + "/geo_samples_test.csv";
  ASSERT_TRUE(writeTrajectoryCsv(path, geo).ok());
  std::ifstream file(path);
  std::string first;
  std::getline(file, first);
  EXPECT_EQ(first, header);
  const Status bad = writeTrajectoryCsv("/nonexistent-dir/x.csv", geo);
  ASSERT_FALSE(bad.ok());
  EXPECT_EQ(bad.error().field, "/nonexistent-dir/x.csv");
}

}  // namespace
}  // namespace skyroute
