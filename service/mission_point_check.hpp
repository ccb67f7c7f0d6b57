// Where a mission point may lie, said in the user's own terms: every error names the point as it
// was written (latitude, longitude, altitude AMSL; or ENU metres when it was given in ENU) and says
// what is wrong with it: outside the DEM (with the DEM's bounds), over a DEM void, under the
// ground (with the ground height), above the ceiling, inside an obstacle, or latitude and
// longitude swapped. The mission pipeline's validate stage and the engine's submit check both use
// it, so the CLI and the daemon answer the same.
#pragma once

#include <optional>
#include <string>

#include "service/mission_types.hpp"
#include "terrain/collision_world.hpp"
#include "terrain/heightfield.hpp"

namespace skyroute {

// A WGS84 bounding box in degrees.
struct GeoBoundsDeg {
  double south_deg = 0.0;
  double north_deg = 0.0;
  double west_deg = 0.0;
  double east_deg = 0.0;
  bool contains(double lat_deg, double lon_deg) const {
    return lat_deg >= south_deg && lat_deg <= north_deg && lon_deg >= west_deg && lon_deg <= east_deg;
  }
};

// The bounding box, in WGS84, of the area of the terrain where points may lie (the heightfield's
// ENU rectangle; its edges are curved in latitude and longitude, so they are sampled).
GeoBoundsDeg terrainGeoBounds(const Heightfield& terrain);
// "lat 44.00000..45.00000, lon -72.00000..-71.00000"
std::string describe(const GeoBoundsDeg& bounds);

// The point as the user wrote it: "(44.2, -71.3, 1000 m AMSL)" or "(east 10, north 20, up 30 m ENU)".
std::string pointText(const MissionPointData& point);

// Why a point cannot lie on this terrain ("is outside the DEM (lat ..)", "... may be swapped",
// "lies on a DEM void: no elevation data here"); nullopt when it is inside and over known ground.
std::optional<std::string> offTerrainReason(const Heightfield& terrain, const MissionPointData& point);

// The ground height AMSL at a WGS84 position; nullopt where offTerrainReason has a reason.
std::optional<double> groundHeightAmslM(const Heightfield& terrain, double lat_deg, double lon_deg);

// Inside the terrain and over known ground; otherwise kOutsideMap naming the point (`name`, e.g.
// "begin" or "points[2]") and what is wrong.
std::optional<PlanError> checkPointOnTerrain(const Heightfield& terrain, const MissionPointData& point,
                                             const std::string& name);

// Everything a mission point must be before any search: on the terrain (checkPointOnTerrain),
// under the ceiling, above the ground by the clearance (kUnderGround, with the ground height),
// clear of no-fly zones (kUnderGround naming the zone) and obstacles (at the snapshot's time when
// given).
std::optional<PlanError> checkMissionPoint(const CollisionWorld& world, const MissionPointData& point,
                                           const std::string& name,
                                           std::optional<ObstacleSnapshot> snapshot = std::nullopt);

}  // namespace skyroute
