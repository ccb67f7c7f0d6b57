// LocalFrame: the metric frame every algorithm works in. East and north come from an azimuthal
// equidistant projection on WGS84 centred at the anchor (PX4's choice for local positions: exact
// distances from the anchor, negligible distortion over a DEM tile); up is altitude above mean
// sea level minus the anchor altitude (0 by default, so up_m == altitude AMSL).
// Conversions go through GDAL's OSR and are safe to call from several threads.
#pragma once

#include <memory>
#include <string>

#include <Eigen/Core>

#include "planning/core/result.hpp"

namespace skyroute {

struct GeoPoint {
  double lat_deg = 0.0;
  double lon_deg = 0.0;
  double alt_amsl_m = 0.0;
};

class LocalFrame {
 public:
  static Result<LocalFrame> create(double anchor_lat_deg, double anchor_lon_deg, double anchor_alt_m = 0.0);

  Eigen::Vector3d toEnu(const GeoPoint& p) const;
  GeoPoint toGeo(const Eigen::Vector3d& enu_m) const;
  // Horizontal only, in bulk (one lock for many points): lon/lat in degrees <-> east/north metres.
  void lonLatToEastNorth(double* lon_x, double* lat_y, std::size_t n) const;
  void eastNorthToLonLat(double* east_x, double* north_y, std::size_t n) const;

  const GeoPoint& anchor() const { return anchor_; }
  const std::string& projWkt() const;

 private:
  struct Impl;
  std::shared_ptr<Impl> impl_;
  GeoPoint anchor_;
};

}  // namespace skyroute
