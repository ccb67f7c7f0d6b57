// PX4's local frame: an azimuthal equidistant projection on a sphere of radius 6 371 000 m. Checked
// against the spherical great-circle distance and initial bearing (independent formulas: an
// azimuthal equidistant projection keeps both from its origin), and by the round trip.
#include <cmath>

#include <gtest/gtest.h>

#include "service/px4_projection.hpp"

namespace skyroute {
namespace {

constexpr double kRad = M_PI / 180.0;

double haversineM(const GeoPoint& a, const GeoPoint& b) {
  const double dlat = (b.lat_deg - a.lat_deg) * kRad, dlon = (b.lon_deg - a.lon_deg) * kRad;
  const double h = std::pow(std::sin(dlat / 2), 2) +
                   std::cos(a.lat_deg * kRad) * std::cos(b.lat_deg * kRad) * std::pow(std::sin(dlon / 2), 2);
  return 2.0 * Px4Projection::kEarthRadiusM * std::asin(std::sqrt(h));
}

double bearingRad(const GeoPoint& a, const GeoPoint& b) {
  const double dlon = (b.lon_deg - a.lon_deg) * kRad;
  return std::atan2(std::sin(dlon) * std::cos(b.lat_deg * kRad),
                    std::cos(a.lat_deg * kRad) * std::sin(b.lat_deg * kRad) -
                        std::sin(a.lat_deg * kRad) * std::cos(b.lat_deg * kRad) * std::cos(dlon));
}

TEST(Px4Projection, KeepsDistanceAndBearingFromTheOrigin) {
  const GeoPoint origin{47.3977, 8.5456, 488.0};
  const Px4Projection px4(origin);
  for (double bearing_deg : {0.0, 37.0, 90.0, 181.0, 270.0, 333.0}) {
    for (double lat_offset : {0.001, 0.05, 0.2}) {
      const GeoPoint p{origin.lat_deg + lat_offset * std::cos(bearing_deg * kRad),
                       origin.lon_deg + lat_offset * std::sin(bearing_deg * kRad), 700.0};
      const Eigen::Vector3d ned = px4.toNed(p);
      EXPECT_NEAR(std::hypot(ned.x(), ned.y()), haversineM(origin, p), 1e-6 * haversineM(origin, p) + 1e-6);
      EXPECT_NEAR(std::remainder(std::atan2(ned.y(), ned.x()) - bearingRad(origin, p), 2 * M_PI), 0.0, 1e-9);
      EXPECT_DOUBLE_EQ(ned.z(), origin.alt_amsl_m - 700.0);  // down: the origin's altitude minus the point's
      const GeoPoint back = px4.toGeo(ned);
      EXPECT_NEAR(back.lat_deg, p.lat_deg, 1e-10);
      EXPECT_NEAR(back.lon_deg, p.lon_deg, 1e-10);
      EXPECT_NEAR(back.alt_amsl_m, 700.0, 1e-9);
    }
  }
  EXPECT_EQ(px4.toNed(origin), Eigen::Vector3d::Zero());
}

}  // namespace
}  // namespace skyroute
