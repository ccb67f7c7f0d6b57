#include "service/mission_point_check.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>

#include "service/number_text.hpp"

namespace skyroute {
namespace {

// Points sampled along each edge of the ENU rectangle: its image in latitude and longitude bulges
// by well under a cell between them on any DEM up to a few hundred kilometres.
constexpr int kEdgeSamples = 64;

std::string metresText(double m) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.1f", m);
  return buf;
}

std::string degreesText(double deg) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.5f", deg);
  return buf;
}

PlanError pointError(PlanErrorCode code, const std::string& name, const MissionPointData& point,
                     const std::string& what) {
  return PlanError{code, name, name + " " + pointText(point) + " " + what};
}

bool onTerrain(const Heightfield& terrain, const Eigen::Vector3d& p_m) {
  return p_m.allFinite() && terrain.inside(p_m.x(), p_m.y()) && terrain.boundsEn().contains(p_m.head<2>());
}

// The ground under an ENU point, as altitude AMSL.
double groundAmslM(const Heightfield& terrain, const Eigen::Vector3d& p_m) {
  return terrain.frame().toGeo(Eigen::Vector3d(p_m.x(), p_m.y(), terrain.heightAt(p_m.x(), p_m.y()))).alt_amsl_m;
}

// The point's altitude as the user gave it: AMSL for WGS84, up for ENU.
std::string altitudeText(const MissionPointData& point) {
  if (point.frame == MissionPointData::Frame::kWgs84) return numberText(point.geo.alt_amsl_m, 7) + " m AMSL";
  return "up " + numberText(point.enu_m.z(), 7) + " m";
}

}  // namespace

GeoBoundsDeg terrainGeoBounds(const Heightfield& terrain) {
  const Eigen::AlignedBox2d& box = terrain.boundsEn();
  GeoBoundsDeg out{std::numeric_limits<double>::infinity(), -std::numeric_limits<double>::infinity(),
                   std::numeric_limits<double>::infinity(), -std::numeric_limits<double>::infinity()};
  auto add = [&](double east_m, double north_m) {
    const GeoPoint g = terrain.frame().toGeo(Eigen::Vector3d(east_m, north_m, 0.0));
    out.south_deg = std::min(out.south_deg, g.lat_deg);
    out.north_deg = std::max(out.north_deg, g.lat_deg);
    out.west_deg = std::min(out.west_deg, g.lon_deg);
    out.east_deg = std::max(out.east_deg, g.lon_deg);
  };
  for (int i = 0; i <= kEdgeSamples; ++i) {
    const double f = static_cast<double>(i) / kEdgeSamples;
    const double east_m = box.min().x() + f * box.sizes().x();
    const double north_m = box.min().y() + f * box.sizes().y();
    add(east_m, box.min().y());
    add(east_m, box.max().y());
    add(box.min().x(), north_m);
    add(box.max().x(), north_m);
  }
  return out;
}

std::string describe(const GeoBoundsDeg& b) {
  return "lat " + degreesText(b.south_deg) + ".." + degreesText(b.north_deg) + ", lon " + degreesText(b.west_deg) +
         ".." + degreesText(b.east_deg);
}

std::string pointText(const MissionPointData& point) {
  if (point.frame == MissionPointData::Frame::kWgs84) {
    return "(" + numberText(point.geo.lat_deg, 9) + ", " + numberText(point.geo.lon_deg, 9) + ", " +
           numberText(point.geo.alt_amsl_m, 7) + " m AMSL)";
  }
  return "(east " + numberText(point.enu_m.x(), 7) + ", north " + numberText(point.enu_m.y(), 7) + ", up " +
         numberText(point.enu_m.z(), 7) + " m ENU)";
}

std::optional<std::string> offTerrainReason(const Heightfield& terrain, const MissionPointData& point) {
  const Eigen::Vector3d p_m = point.toEnu(terrain.frame());
  if (!p_m.allFinite()) return "is not a finite position";
  if (!onTerrain(terrain, p_m)) {
    if (point.frame == MissionPointData::Frame::kWgs84) {
      MissionPointData swapped = point;
      std::swap(swapped.geo.lat_deg, swapped.geo.lon_deg);
      if (std::abs(swapped.geo.lat_deg) <= 90.0 && onTerrain(terrain, swapped.toEnu(terrain.frame()))) {
        return std::string("is outside the DEM, but inside it with latitude and longitude exchanged: latitude and "
                           "longitude may be swapped (write LAT,LON)");
      }
    }
    return "is outside the DEM (" + describe(terrainGeoBounds(terrain)) + ")";
  }
  if (std::isnan(terrain.heightAt(p_m.x(), p_m.y()))) {
    return std::string("lies on a DEM void: no elevation data here (the DEM has a nodata cell there)");
  }
  return std::nullopt;
}

std::optional<PlanError> checkPointOnTerrain(const Heightfield& terrain, const MissionPointData& point,
                                             const std::string& name) {
  const auto reason = offTerrainReason(terrain, point);
  if (!reason) return std::nullopt;
  const bool finite = point.toEnu(terrain.frame()).allFinite();
  return pointError(finite ? PlanErrorCode::kOutsideMap : PlanErrorCode::kInvalidArgument, name, point, *reason);
}

std::optional<double> groundHeightAmslM(const Heightfield& terrain, double lat_deg, double lon_deg) {
  const Eigen::Vector3d p_m = terrain.frame().toEnu(GeoPoint{lat_deg, lon_deg, 0.0});
  if (!onTerrain(terrain, p_m) || std::isnan(terrain.heightAt(p_m.x(), p_m.y()))) return std::nullopt;
  return groundAmslM(terrain, p_m);
}

std::optional<PlanError> checkMissionPoint(const CollisionWorld& world, const MissionPointData& point,
                                           const std::string& name, std::optional<ObstacleSnapshot> snapshot) {
  const Heightfield& terrain = world.terrain();
  if (auto off = checkPointOnTerrain(terrain, point, name)) return off;
  const Eigen::Vector3d p_m = point.toEnu(terrain.frame());
  const CollisionWorldOptions& o = world.options();
  const double ceiling_amsl_m = terrain.frame().toGeo(Eigen::Vector3d(p_m.x(), p_m.y(), o.ceiling_m)).alt_amsl_m;
  if (p_m.z() > o.ceiling_m) {
    return pointError(PlanErrorCode::kInvalidArgument, name, point,
                      "is above the ceiling: altitude " + altitudeText(point) + ", ceiling " +
                          metresText(ceiling_amsl_m) + " m AMSL");
  }
  if (!world.isTerrainValid(p_m)) {
    const double ground_m = groundAmslM(terrain, p_m);
    return pointError(PlanErrorCode::kUnderGround, name, point,
                      "is under the ground plus clearance: the ground here is " + metresText(ground_m) +
                          " m AMSL, so the point must be at least " + metresText(ground_m + o.min_clearance_m) +
                          " m AMSL (clearance " + numberText(o.min_clearance_m) + " m)");
  }
  if (auto zone = world.noFlyZoneAt(p_m, snapshot ? std::optional<double>(snapshot->time_s) : std::nullopt)) {
    return pointError(PlanErrorCode::kUnderGround, name, point,
                      "is inside no-fly zone '" + *zone + "' (or within the vehicle radius, " +
                          numberText(o.vehicle_radius_m) + " m, of it)");
  }
  const bool clear = snapshot ? world.isPointValid(p_m, *snapshot) : world.isPointValid(p_m);
  if (!clear) return pointError(PlanErrorCode::kUnderGround, name, point, "is inside an obstacle");
  return std::nullopt;
}

}  // namespace skyroute
