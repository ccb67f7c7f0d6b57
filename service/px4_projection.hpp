// PX4's local frame: NED metres from the EKF origin (VehicleLocalPosition ref_lat, ref_lon,
// ref_alt; ref_alt AMSL). North and east come from an azimuthal equidistant projection on a
// sphere of radius 6 371 000 m (the projection PX4's EKF uses between its global and local
// positions), down is ref_alt minus the altitude AMSL. A setpoint computed this way puts the
// vehicle where PX4 itself places a latitude and longitude, which matters: the ellipsoidal frame
// of the daemon and PX4's spherical one differ by up to 0.3 % in scale, 30 m at 10 km.
#pragma once

#include <Eigen/Core>

#include "terrain/local_frame.hpp"

namespace skyroute {

class Px4Projection {
 public:
  static constexpr double kEarthRadiusM = 6371000.0;

  explicit Px4Projection(const GeoPoint& origin);

  Eigen::Vector3d toNed(const GeoPoint& point) const;    // x north, y east, z down (metres)
  GeoPoint toGeo(const Eigen::Vector3d& ned_m) const;    // the inverse
  const GeoPoint& origin() const { return origin_; }

 private:
  GeoPoint origin_;
  double lat0_rad_, lon0_rad_, sin_lat0_, cos_lat0_;
};

}  // namespace skyroute
