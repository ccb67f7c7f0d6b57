#include "service/px4_projection.hpp"

#include <algorithm>
#include <cmath>

namespace skyroute {

namespace {
constexpr double kDegToRad = M_PI / 180.0;
}  // namespace

Px4Projection::Px4Projection(const GeoPoint& origin)
    : origin_(origin),
      lat0_rad_(origin.lat_deg * kDegToRad),
      lon0_rad_(origin.lon_deg * kDegToRad),
      sin_lat0_(std::sin(lat0_rad_)),
      cos_lat0_(std::cos(lat0_rad_)) {}

// Spherical azimuthal equidistant projection (Snyder, "Map Projections: A Working Manual", §25):
// c is the angular distance from the origin, and the planar distance R c keeps it exact.
Eigen::Vector3d Px4Projection::toNed(const GeoPoint& point) const {
  const double lat = point.lat_deg * kDegToRad;
  const double dlon = point.lon_deg * kDegToRad - lon0_rad_;
  const double sin_lat = std::sin(lat), cos_lat = std::cos(lat), cos_dlon = std::cos(dlon);
  const double cos_c = std::clamp(sin_lat0_ * sin_lat + cos_lat0_ * cos_lat * cos_dlon, -1.0, 1.0);
  const double c = std::acos(cos_c);
  const double k = c > 0.0 ? c / std::sin(c) : 1.0;
  return {k * (cos_lat0_ * sin_lat - sin_lat0_ * cos_lat * cos_dlon) * kEarthRadiusM,
          k * cos_lat * std::sin(dlon) * kEarthRadiusM, origin_.alt_amsl_m - point.alt_amsl_m};
}

GeoPoint Px4Projection::toGeo(const Eigen::Vector3d& ned_m) const {
  const double x = ned_m.x() / kEarthRadiusM, y = ned_m.y() / kEarthRadiusM;
  const double c = std::hypot(x, y);
  GeoPoint out{origin_.lat_deg, origin_.lon_deg, origin_.alt_amsl_m - ned_m.z()};
  if (c <= 0.0) return out;
  const double sin_c = std::sin(c), cos_c = std::cos(c);
  const double lat = std::asin(std::clamp(cos_c * sin_lat0_ + x * sin_c * cos_lat0_ / c, -1.0, 1.0));
  const double lon = lon0_rad_ + std::atan2(y * sin_c, c * cos_lat0_ * cos_c - x * sin_lat0_ * sin_c);
  out.lat_deg = lat / kDegToRad;
  out.lon_deg = lon / kDegToRad;
  return out;
}

}  // namespace skyroute
