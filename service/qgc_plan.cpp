#include "service/qgc_plan.hpp"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <map>
#include <system_error>

#include "service/polyline_simplify.hpp"

namespace skyroute {

namespace {

// MAVLink and QGroundControl numbers the files carry.
constexpr int kMavCmdNavWaypoint = 16;
constexpr int kMavFrameGlobal = 0;           // altitude AMSL
constexpr int kQgcAltitudeModeAbsolute = 2;  // QGroundControl's "AMSL" altitude mode

bool finite(const GeoPoint& p) {
  return std::isfinite(p.lat_deg) && std::isfinite(p.lon_deg) && std::isfinite(p.alt_amsl_m);
}

// A trajectory vertex for the simplification: a sample, or a point inserted at a leg boundary.
struct RouteVertex {
  double time_s = 0.0;
  Eigen::Vector3d enu_m;
  GeoPoint geo;
  bool mission_point = false;
};

// The samples, plus a vertex at every boundary time that falls between two samples. An inserted
// vertex lies on the segment between its neighbours (ENU and WGS84 interpolated alike; over one
// sample step the two agree to well under a millimetre), so the polyline keeps its shape.
std::vector<RouteVertex> routeVertices(const std::vector<TrajectorySampleData>& samples,
                                       std::vector<double> boundaries) {
  const double t0 = samples.front().t_rel_s, t1 = samples.back().t_rel_s;
  for (double& b : boundaries) b = std::clamp(b, t0, t1);
  constexpr double kSameTimeS = 1e-6;
  // One leg ends where the next starts: one vertex for both.
  std::sort(boundaries.begin(), boundaries.end());
  boundaries.erase(
      std::unique(boundaries.begin(), boundaries.end(), [](double a, double b) { return b - a < kSameTimeS; }),
      boundaries.end());
  std::vector<RouteVertex> out;
  std::size_t next = 0;  // the first boundary not yet placed
  for (std::size_t i = 0; i < samples.size(); ++i) {
    const TrajectorySampleData& s = samples[i];
    while (next < boundaries.size() && boundaries[next] < s.t_rel_s - kSameTimeS) {
      const TrajectorySampleData& a = samples[i - 1];  // boundaries >= t0, so i > 0 here
      const double f = (boundaries[next] - a.t_rel_s) / (s.t_rel_s - a.t_rel_s);
      const GeoPoint geo{a.geo.lat_deg + f * (s.geo.lat_deg - a.geo.lat_deg),
                         a.geo.lon_deg + f * (s.geo.lon_deg - a.geo.lon_deg),
                         a.geo.alt_amsl_m + f * (s.geo.alt_amsl_m - a.geo.alt_amsl_m)};
      out.push_back({boundaries[next], a.position_enu_m + f * (s.position_enu_m - a.position_enu_m), geo, true});
      ++next;
    }
    RouteVertex v{s.t_rel_s, s.position_enu_m, s.geo, false};
    while (next < boundaries.size() && boundaries[next] <= s.t_rel_s + kSameTimeS) {
      v.mission_point = true;
      ++next;
    }
    out.push_back(v);
  }
  return out;
}

Result<std::vector<GeofencePolygon>> checkedZones(const std::vector<GeofencePolygon>& zones) {
  std::vector<GeofencePolygon> out;
  for (std::size_t z = 0; z < zones.size(); ++z) {
    const std::string field = "no_fly_zones[" + std::to_string(z) + "]";
    GeofencePolygon zone = zones[z];
    for (std::size_t v = 0; v < zone.ring.size(); ++v) {
      const LatLonDeg& p = zone.ring[v];
      const std::string vertex = field + ".ring[" + std::to_string(v) + "]";
      if (!std::isfinite(p.lat_deg) || std::abs(p.lat_deg) > 90.0)
        return make_error(ErrorCode::kInvalidArgument, vertex + ".lat_deg", "latitude not within -90..90 degrees");
      if (!std::isfinite(p.lon_deg) || std::abs(p.lon_deg) > 180.0)
        return make_error(ErrorCode::kInvalidArgument, vertex + ".lon_deg", "longitude not within -180..180 degrees");
    }
    // QGroundControl's polygons are open: the first vertex is not repeated at the end.
    if (zone.ring.size() >= 2 && zone.ring.front().lat_deg == zone.ring.back().lat_deg &&
        zone.ring.front().lon_deg == zone.ring.back().lon_deg)
      zone.ring.pop_back();
    std::size_t distinct = zone.ring.empty() ? 0 : 1;
    for (std::size_t v = 1; v < zone.ring.size(); ++v)
      if (zone.ring[v].lat_deg != zone.ring[v - 1].lat_deg || zone.ring[v].lon_deg != zone.ring[v - 1].lon_deg)
        ++distinct;
    if (distinct < 3)
      return make_error(ErrorCode::kInvalidArgument, field + ".ring",
                        "a no-fly zone needs at least 3 distinct vertices, it has " + std::to_string(distinct));
    out.push_back(std::move(zone));
  }
  return out;
}

Status checkOptions(const QgcPlanOptions& o) {
  auto bad = [](const char* field, const std::string& why) {
    return Status(make_error(ErrorCode::kInvalidArgument, field, why));
  };
  if (!(o.corridor_m > 0.0) || !std::isfinite(o.corridor_m))
    return bad("corridor_m", "must be a positive number of metres");
  if (!(o.cruise_speed_mps >= 0.0) || !std::isfinite(o.cruise_speed_mps))
    return bad("cruise_speed_mps", "must be 0 (the trajectory's mean speed) or a positive speed");
  if (!(o.hover_speed_mps > 0.0) || !std::isfinite(o.hover_speed_mps))
    return bad("hover_speed_mps", "must be positive");
  if (!(o.hold_s >= 0.0) || !std::isfinite(o.hold_s)) return bad("hold_s", "must be 0 or more seconds");
  if (!(o.acceptance_radius_m >= 0.0) || !std::isfinite(o.acceptance_radius_m))
    return bad("acceptance_radius_m", "must be 0 (the autopilot's own) or more metres");
  if (o.firmware_type < 0) return bad("firmware_type", "is a MAV_AUTOPILOT value (12 PX4, 3 ArduPilot)");
  if (o.vehicle_type < 0) return bad("vehicle_type", "is a MAV_TYPE value (2 quadrotor, 1 fixed wing)");
  return Status::success();
}

std::string fileNameOf(const std::string& vehicle_id) {
  std::string name = vehicle_id;
  for (char& c : name) {
    const bool safe = std::isalnum(static_cast<unsigned char>(c)) || c == '-' || c == '_' || c == '.';
    if (!safe) c = '_';
  }
  // "." and ".." are folders, and a leading dot hides the file.
  if (!name.empty() && name.front() == '.') name.front() = '_';
  return name + ".plan";
}

Status writeText(const std::string& path, const std::string& text, const char* what) {
  std::ofstream out(path);
  if (!out) return make_error(ErrorCode::kFileNotFound, path, std::string("cannot create the ") + what);
  out << text;
  out.flush();
  if (!out) return make_error(ErrorCode::kFileNotFound, path, std::string("writing the ") + what + " failed");
  return Status::success();
}

}  // namespace

Result<QgcMission> qgcMissionFromTrajectory(const TrajectoryData& trajectory,
                                            const std::vector<GeofencePolygon>& no_fly_zones, const QgcPlanOptions& options) {
  if (Status ok = checkOptions(options); !ok.ok()) return ok.error();
  const auto& samples = trajectory.samples;
  if (samples.size() < 2)
    return make_error(ErrorCode::kInvalidArgument, "samples",
                      "a mission needs a trajectory of at least 2 samples, " + trajectory.vehicle_id + "'s has " +
                          std::to_string(samples.size()));
  std::vector<Eigen::Vector3d> enu;
  enu.reserve(samples.size());
  for (std::size_t i = 0; i < samples.size(); ++i) {
    if (!finite(samples[i].geo) || !samples[i].position_enu_m.allFinite() || !std::isfinite(samples[i].t_rel_s))
      return make_error(ErrorCode::kInvalidArgument, "samples[" + std::to_string(i) + "]", "has a non-finite value");
    if (i > 0 && !(samples[i].t_rel_s > samples[i - 1].t_rel_s))
      return make_error(ErrorCode::kInvalidArgument, "samples[" + std::to_string(i) + "].t_rel_s",
                        "is not after the previous sample's time");
    enu.push_back(samples[i].position_enu_m);
  }
  auto zones = checkedZones(no_fly_zones);
  if (!zones) return zones.error();

  std::vector<double> boundaries = {samples.front().t_rel_s, samples.back().t_rel_s};
  for (const LegBoundaryData& leg : trajectory.legs) {
    if (!std::isfinite(leg.start_s) || !std::isfinite(leg.end_s))
      return make_error(ErrorCode::kInvalidArgument, "legs", "a leg boundary time is not finite");
    boundaries.push_back(leg.start_s);
    boundaries.push_back(leg.end_s);
  }
  const std::vector<RouteVertex> vertices = routeVertices(samples, boundaries);
  std::vector<Eigen::Vector3d> route_enu;
  std::vector<std::size_t> mission_points;
  for (std::size_t i = 0; i < vertices.size(); ++i) {
    route_enu.push_back(vertices[i].enu_m);
    if (vertices[i].mission_point) mission_points.push_back(i);
  }
  // The corridor is measured in the local ENU frame, in metres, where the trajectory was planned.
  auto kept = simplifyPolyline(route_enu, options.corridor_m, mission_points);
  if (!kept) return kept.error();

  QgcMission mission;
  mission.home = samples.front().geo;
  for (std::size_t i : *kept)
    mission.items.push_back(QgcMissionItem{vertices[i].geo, vertices[i].mission_point, vertices[i].time_s});
  mission.no_fly_zones = std::move(*zones);

  double cruise = options.cruise_speed_mps;
  if (cruise == 0.0) {
    double length_m = 0.0;
    for (std::size_t i = 1; i < enu.size(); ++i) length_m += (enu[i] - enu[i - 1]).norm();
    const double duration_s = samples.back().t_rel_s - samples.front().t_rel_s;
    if (!(duration_s > 0.0))
      return make_error(ErrorCode::kInvalidArgument, "samples",
                        "the trajectory takes no time, so it has no mean speed: give cruise_speed_mps");
    cruise = length_m / duration_s;
  }
  mission.cruise_speed_mps = cruise;
  mission.hover_speed_mps = options.hover_speed_mps;
  mission.firmware_type = options.firmware_type;
  mission.vehicle_type = options.vehicle_type;
  mission.hold_s = options.hold_s;
  mission.acceptance_radius_m = options.acceptance_radius_m;
  return mission;
}

nlohmann::json qgcPlanJson(const QgcMission& mission) {
  using nlohmann::json;
  json items = json::array();
  for (std::size_t i = 0; i < mission.items.size(); ++i) {
    const GeoPoint& p = mission.items[i].point;
    items.push_back(
        {{"type", "SimpleItem"},
         {"command", kMavCmdNavWaypoint},
         {"frame", kMavFrameGlobal},
         {"doJumpId", i + 1},
         {"autoContinue", true},
         {"AltitudeMode", kQgcAltitudeModeAbsolute},
         {"Altitude", p.alt_amsl_m},
         {"AMSLAltAboveTerrain", nullptr},
         // hold, acceptance radius, pass radius (0: through the point), yaw (null: the
         // autopilot's heading mode), latitude, longitude, altitude.
         {"params", {mission.hold_s, mission.acceptance_radius_m, 0.0, nullptr, p.lat_deg, p.lon_deg, p.alt_amsl_m}}});
  }
  json polygons = json::array();
  for (const GeofencePolygon& zone : mission.no_fly_zones) {
    json ring = json::array();
    for (const LatLonDeg& v : zone.ring) ring.push_back({v.lat_deg, v.lon_deg});
    polygons.push_back({{"version", 1}, {"inclusion", false}, {"polygon", std::move(ring)}});
  }
  return json{{"fileType", "Plan"},
              {"version", 1},
              {"groundStation", "skyroute"},
              {"mission",
               {{"version", 2},
                {"firmwareType", mission.firmware_type},
                {"vehicleType", mission.vehicle_type},
                {"globalPlanAltitudeMode", kQgcAltitudeModeAbsolute},
                {"cruiseSpeed", mission.cruise_speed_mps},
                {"hoverSpeed", mission.hover_speed_mps},
                {"plannedHomePosition", {mission.home.lat_deg, mission.home.lon_deg, mission.home.alt_amsl_m}},
                {"items", std::move(items)}}},
              {"geoFence", {{"version", 2}, {"polygons", std::move(polygons)}, {"circles", json::array()}}},
              {"rallyPoints", {{"version", 2}, {"points", json::array()}}}};
}

std::string qgcWaypointsText(const QgcMission& mission) {
  std::string text = "QGC WPL 110\n";
  char line[256];
  // seq, current, frame, command, p1..p4, latitude, longitude, altitude, autocontinue; tab-separated.
  // Ten decimals of a degree keep points to ~0.01 mm; "nan" is how QGroundControl writes a yaw left
  // to the autopilot.
  std::snprintf(line, sizeof line, "0\t1\t%d\t%d\t0\t0\t0\t0\t%.10f\t%.10f\t%.3f\t1\n", kMavFrameGlobal,
                kMavCmdNavWaypoint, mission.home.lat_deg, mission.home.lon_deg, mission.home.alt_amsl_m);
  text += line;
  for (std::size_t i = 0; i < mission.items.size(); ++i) {
    const GeoPoint& p = mission.items[i].point;
    std::snprintf(line, sizeof line, "%zu\t0\t%d\t%d\t%g\t%g\t0\tnan\t%.10f\t%.10f\t%.3f\t1\n", i + 1, kMavFrameGlobal,
                  kMavCmdNavWaypoint, mission.hold_s, mission.acceptance_radius_m, p.lat_deg, p.lon_deg, p.alt_amsl_m);
    text += line;
  }
  return text;
}

Status writeQgcPlan(const std::string& path, const QgcMission& mission) {
  return writeText(path, qgcPlanJson(mission).dump(2) + "\n", "QGroundControl plan");
}

Status writeQgcWaypoints(const std::string& path, const QgcMission& mission) {
  return writeText(path, qgcWaypointsText(mission), "QGC WPL 110 waypoints file");
}

Result<std::vector<std::string>> writeQgcPlanPerVehicle(const std::string& dir,
                                                        const std::vector<TrajectoryData>& trajectories,
                                                        const std::vector<GeofencePolygon>& no_fly_zones,
                                                        const QgcPlanOptions& options) {
  // Every mission first, so a bad trajectory leaves no partial set of files.
  std::vector<std::pair<std::string, QgcMission>> files;
  std::map<std::string, std::string> owner;  // file name -> vehicle id, to catch ids that collide
  for (const TrajectoryData& t : trajectories) {
    if (t.vehicle_id.empty())
      return make_error(ErrorCode::kInvalidArgument, "vehicle_id", "a trajectory has no vehicle id");
    const std::string name = fileNameOf(t.vehicle_id);
    if (auto [it, inserted] = owner.emplace(name, t.vehicle_id); !inserted)
      return make_error(ErrorCode::kInvalidArgument, t.vehicle_id,
                        "vehicles '" + it->second + "' and '" + t.vehicle_id + "' would both be written to " + name);
    auto mission = qgcMissionFromTrajectory(t, no_fly_zones, options);
    if (!mission)
      return make_error(mission.error().code, t.vehicle_id + "." + mission.error().field, mission.error().message);
    files.emplace_back((std::filesystem::path(dir) / name).string(), std::move(*mission));
  }
  std::error_code ec;
  std::filesystem::create_directories(dir, ec);
  if (ec) return make_error(ErrorCode::kFileNotFound, dir, "cannot create the folder: " + ec.message());
  std::vector<std::string> written;
  for (const auto& [path, mission] : files) {
    if (Status ok = writeQgcPlan(path, mission); !ok.ok()) return ok.error();
    written.push_back(path);
  }
  return written;
}

std::vector<GeofencePolygon> geofencePolygons(const std::vector<NoFlyZone>& zones, const LocalFrame& frame) {
  std::vector<GeofencePolygon> out;
  for (const NoFlyZone& zone : zones) out.push_back(geofencePolygon(toNoFlyZoneData(zone, frame)));
  return out;
}

GeofencePolygon geofencePolygon(const NoFlyZoneData& zone) {
  GeofencePolygon polygon;
  for (const GeoPoint& p : zone.ring) polygon.ring.push_back(LatLonDeg{p.lat_deg, p.lon_deg});
  return polygon;
}

}  // namespace skyroute
