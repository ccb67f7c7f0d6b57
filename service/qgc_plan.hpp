// QGroundControl mission files for a planned trajectory: the JSON `.plan` (mission, geofence, rally
// points) and the plain-text `QGC WPL 110` (`.waypoints`, mission only).
// Every item is a MAV_CMD_NAV_WAYPOINT (16) with an absolute altitude above mean sea level
// (AltitudeMode 2, MAV_FRAME_GLOBAL 0): the trajectory follows the terrain, so altitudes relative to
// home would be wrong everywhere but at home. The items are one per mission point plus the vertices
// of a 3D Douglas-Peucker simplification of the sampled trajectory, so the straight lines the
// autopilot flies between items stay within a corridor of the given half-width around the trajectory.
#pragma once

#include <cstddef>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "service/mission_types.hpp"
#include "service/no_fly_zone_data.hpp"
#include "terrain/local_frame.hpp"
#include "terrain/no_fly_zone.hpp"
#include "planning/core/result.hpp"

namespace skyroute {

struct LatLonDeg {
  double lat_deg = 0.0;
  double lon_deg = 0.0;
};

// A keep-out area: its boundary as latitude/longitude vertices (closed or not; at least 3 distinct).
struct GeofencePolygon {
  std::vector<LatLonDeg> ring;
};

// The planner's no-fly zones (their horizontal rings, from the frame's east/north back to WGS84)
// as exclusion polygons: QGroundControl's geofence has no floor, ceiling or time, so each zone
// excludes its whole column whenever it is given.
std::vector<GeofencePolygon> geofencePolygons(const std::vector<NoFlyZone>& zones, const LocalFrame& frame);
GeofencePolygon geofencePolygon(const NoFlyZoneData& zone);

struct QgcPlanOptions {
  double corridor_m = 5.0;            // largest distance between the trajectory and the lines between items
  double cruise_speed_mps = 0.0;      // 0 = the trajectory's mean speed (length / duration)
  double hover_speed_mps = 5.0;       // QGroundControl's estimate for multicopters
  int firmware_type = 12;             // MAV_AUTOPILOT: 12 PX4, 3 ArduPilot
  int vehicle_type = 2;               // MAV_TYPE: 2 quadrotor, 1 fixed wing
  double hold_s = 0.0;                // param1 at every item
  double acceptance_radius_m = 0.0;   // param2; 0 = the autopilot's own (PX4: NAV_ACC_RAD)
};

struct QgcMissionItem {
  GeoPoint point;                 // latitude, longitude, altitude AMSL
  bool mission_point = false;     // a point of the request (begin, via, end), not only a route vertex
  double time_s = 0.0;            // when the trajectory passes it, relative to its start
};

struct QgcMission {
  GeoPoint home;                  // the trajectory's begin point
  std::vector<QgcMissionItem> items;
  std::vector<GeofencePolygon> no_fly_zones;  // open rings (a closing vertex is dropped)
  double cruise_speed_mps = 0.0;
  double hover_speed_mps = 0.0;
  int firmware_type = 12;
  int vehicle_type = 2;
  double hold_s = 0.0;
  double acceptance_radius_m = 0.0;
};

// The mission points are where the trajectory is at its leg boundaries (its first and last sample
// when it has no legs); between two samples, on the straight line between them, which is within
// a*dt^2/8 of the flown curve (a few centimetres at the daemon's 0.2 s).
// Errors (kInvalidArgument) name the field: fewer than 2 samples, a non-finite sample, options out of
// range, a no-fly zone with fewer than 3 distinct vertices or a vertex outside -90..90 / -180..180.
Result<QgcMission> qgcMissionFromTrajectory(const TrajectoryData& trajectory,
                                            const std::vector<GeofencePolygon>& no_fly_zones = {},
                                            const QgcPlanOptions& options = {});

nlohmann::json qgcPlanJson(const QgcMission& mission);
// Line 0 is the home position (as QGroundControl and ArduPilot read this format), then the items.
// The format has no geofence: no-fly zones are only in the .plan.
std::string qgcWaypointsText(const QgcMission& mission);

// Errors kFileNotFound naming the path when it cannot be written.
Status writeQgcPlan(const std::string& path, const QgcMission& mission);
Status writeQgcWaypoints(const std::string& path, const QgcMission& mission);

// `skyroute gcs --plan DIR`: one <vehicle>.plan per trajectory in dir (created if missing). Returns
// the paths written. Characters other than letters, digits, '-', '_' and '.' in a vehicle id become
// '_' in its file name.
Result<std::vector<std::string>> writeQgcPlanPerVehicle(const std::string& dir,
                                                        const std::vector<TrajectoryData>& trajectories,
                                                        const std::vector<GeofencePolygon>& no_fly_zones = {},
                                                        const QgcPlanOptions& options = {});

}  // namespace skyroute
