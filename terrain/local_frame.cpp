#include "terrain/local_frame.hpp"

#include <cmath>
#include <cstdio>
#include <mutex>

#include <ogr_spatialref.h>

namespace skyroute {

// OGRCoordinateTransformation objects are not safe for concurrent use, so each frame keeps one pair
// behind a mutex; bulk calls amortise the lock.
struct LocalFrame::Impl {
  OGRSpatialReference wgs84;
  OGRSpatialReference local;
  std::unique_ptr<OGRCoordinateTransformation> to_local;
  std::unique_ptr<OGRCoordinateTransformation> to_wgs84;
  std::string wkt;
  std::mutex mutex;
};

Result<LocalFrame> LocalFrame::create(double anchor_lat_deg, double anchor_lon_deg, double anchor_alt_m) {
  if (!std::isfinite(anchor_lat_deg) || anchor_lat_deg < -89.0 || anchor_lat_deg > 89.0) {
    return make_error(ErrorCode::kInvalidArgument, "anchor_lat_deg", "must be a latitude in [-89, 89] degrees");
  }
  if (!std::isfinite(anchor_lon_deg) || anchor_lon_deg < -180.0 || anchor_lon_deg > 180.0) {
    return make_error(ErrorCode::kInvalidArgument, "anchor_lon_deg", "must be a longitude in [-180, 180] degrees");
  }
  if (!std::isfinite(anchor_alt_m)) {
    return make_error(ErrorCode::kInvalidArgument, "anchor_alt_m", "must be finite");
  }
  auto impl = std::make_shared<Impl>();
  impl->wgs84.SetWellKnownGeogCS("WGS84");
  impl->wgs84.SetAxisMappingStrategy(OAMS_TRADITIONAL_GIS_ORDER);
  char proj[256];
  std::snprintf(proj, sizeof(proj), "+proj=aeqd +lat_0=%.12f +lon_0=%.12f +x_0=0 +y_0=0 +datum=WGS84 +units=m +no_defs",
                anchor_lat_deg, anchor_lon_deg);
  if (impl->local.importFromProj4(proj) != OGRERR_NONE) {
    return make_error(ErrorCode::kInternal, "local_frame", "PROJ rejected the local projection");
  }
  impl->local.SetAxisMappingStrategy(OAMS_TRADITIONAL_GIS_ORDER);
  impl->to_local.reset(OGRCreateCoordinateTransformation(&impl->wgs84, &impl->local));
  impl->to_wgs84.reset(OGRCreateCoordinateTransformation(&impl->local, &impl->wgs84));
  if (!impl->to_local || !impl->to_wgs84) {
    return make_error(ErrorCode::kInternal, "local_frame", "cannot create WGS84 <-> local transforms");
  }
  char* wkt = nullptr;
  impl->local.exportToWkt(&wkt);
  impl->wkt = wkt ? wkt : "";
  CPLFree(wkt);
  LocalFrame frame;
  frame.impl_ = std::move(impl);
  frame.anchor_ = GeoPoint{anchor_lat_deg, anchor_lon_deg, anchor_alt_m};
  return frame;
}

const std::string& LocalFrame::projWkt() const { return impl_->wkt; }

void LocalFrame::lonLatToEastNorth(double* lon_x, double* lat_y, std::size_t n) const {
  std::lock_guard<std::mutex> lock(impl_->mutex);
  impl_->to_local->Transform(static_cast<int>(n), lon_x, lat_y);
}

void LocalFrame::eastNorthToLonLat(double* east_x, double* north_y, std::size_t n) const {
  std::lock_guard<std::mutex> lock(impl_->mutex);
  impl_->to_wgs84->Transform(static_cast<int>(n), east_x, north_y);
}

Eigen::Vector3d LocalFrame::toEnu(const GeoPoint& p) const {
  double x = p.lon_deg;
  double y = p.lat_deg;
  lonLatToEastNorth(&x, &y, 1);
  return {x, y, p.alt_amsl_m - anchor_.alt_amsl_m};
}

GeoPoint LocalFrame::toGeo(const Eigen::Vector3d& enu_m) const {
  double x = enu_m.x();
  double y = enu_m.y();
  eastNorthToLonLat(&x, &y, 1);
  return GeoPoint{y, x, enu_m.z() + anchor_.alt_amsl_m};
}

}  // namespace skyroute
