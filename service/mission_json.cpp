#include "service/mission_json.hpp"

#include <cmath>
#include <optional>
#include <utility>
#include <vector>

#include "planning/core/assign_result.hpp"
#include "service/known_keys.hpp"

namespace skyroute {

namespace {

using nlohmann::json;

Error invalid(const std::string& field, const std::string& reason) {
  return make_error(ErrorCode::kParseError, field, field + " " + reason);
}

std::string join(const std::string& parent, const std::string& key) {
  return parent.empty() ? key : parent + "." + key;
}

// Reads a finite number at j[key]; absent keys give fallback when one is allowed.
Result<double> number(const json& j, const std::string& key, const std::string& parent,
                      std::optional<double> fallback = std::nullopt) {
  const std::string field = join(parent, key);
  auto it = j.find(key);
  if (it == j.end()) {
    if (fallback) return *fallback;
    return invalid(field, "is missing");
  }
  if (!it->is_number()) return invalid(field, "must be a number");
  const double v = it->get<double>();
  if (!std::isfinite(v)) return invalid(field, "is not a finite number");
  return v;
}

Result<std::string> text(const json& j, const std::string& key, const std::string& parent, const std::string& fallback) {
  auto it = j.find(key);
  if (it == j.end()) return fallback;
  if (!it->is_string()) return invalid(join(parent, key), "must be a string");
  // A DDS string ends at its first NUL: "a\u0000b" would reach the daemon as "a".
  if (it->get_ref<const std::string&>().find('\0') != std::string::npos)
    return invalid(join(parent, key), "must not contain a NUL character");
  return it->get<std::string>();
}

Result<bool> boolean(const json& j, const std::string& key, const std::string& parent, bool fallback) {
  auto it = j.find(key);
  if (it == j.end()) return fallback;
  if (!it->is_boolean()) return invalid(join(parent, key), "must be true or false");
  return it->get<bool>();
}

Result<Eigen::Vector3d> vector3(const json& j, const std::string& key, const std::string& parent) {
  const std::string field = join(parent, key);
  auto it = j.find(key);
  if (it == j.end()) return invalid(field, "is missing");
  if (!it->is_array() || it->size() != 3) return invalid(field, "must be an array of 3 numbers");
  Eigen::Vector3d v;
  for (int i = 0; i < 3; ++i) {
    const json& e = (*it)[static_cast<std::size_t>(i)];
    if (!e.is_number() || !std::isfinite(e.get<double>()))
      return invalid(field + "[" + std::to_string(i) + "]", "must be a finite number");
    v[i] = e.get<double>();
  }
  return v;
}

json array3(const Eigen::Vector3d& v) { return json::array({v.x(), v.y(), v.z()}); }

// The limits' keys, as the IDL names them.
std::vector<std::pair<const char*, double VehicleLimitsData::*>> limitFields() {
  return {{"v_ref_mps", &VehicleLimitsData::v_ref_mps},
          {"max_speed_mps", &VehicleLimitsData::max_speed_mps},
          {"max_accel_mps2", &VehicleLimitsData::max_accel_mps2},
          {"max_climb_rate_mps", &VehicleLimitsData::max_climb_rate_mps},
          {"max_descent_rate_mps", &VehicleLimitsData::max_descent_rate_mps},
          {"min_turn_radius_m", &VehicleLimitsData::min_turn_radius_m},
          {"min_clearance_agl_m", &VehicleLimitsData::min_clearance_agl_m},
          {"ceiling_amsl_m", &VehicleLimitsData::ceiling_amsl_m},
          {"stall_speed_mps", &VehicleLimitsData::stall_speed_mps},
          {"stall_margin", &VehicleLimitsData::stall_margin},
          {"max_bank_deg", &VehicleLimitsData::max_bank_deg},
          {"max_climb_angle_deg", &VehicleLimitsData::max_climb_angle_deg},
          {"max_descent_angle_deg", &VehicleLimitsData::max_descent_angle_deg}};
}

json limitsToJson(const VehicleLimitsData& limits) {
  json j = json::object();
  if (limits.model) j["model"] = std::string(to_string(*limits.model));
  for (const auto& [key, field] : limitFields()) j[key] = limits.*field;
  return j;
}

KnownKeys limitKeys() {
  KnownKeys keys{"model"};
  for (const auto& [key, field] : limitFields()) keys.push_back(key);
  return keys;
}

// j["limits"] into `limits` (absent keys keep their values); the first problem found, if any.
std::optional<Error> limitsFromJson(const json& j, VehicleLimitsData& limits) {
  auto it = j.find("limits");
  if (it == j.end()) return std::nullopt;
  if (!it->is_object()) return invalid("limits", "must be an object");
  if (auto unknown = unknownJsonKey(*it, limitKeys(), "limits", "limits")) return unknown;
  if (it->contains("model")) {
    auto name = text(*it, "model", "limits", "");
    if (!name) return name.error();
    limits.model = parseVehicleModel(*name);
    if (!limits.model) return invalid("limits.model", "'" + *name + "' is not one of multirotor, fixed_wing");
  }
  for (const auto& [key, field] : limitFields()) {
    auto v = number(*it, key, "limits", limits.*field);
    if (!v) return v.error();
    limits.*field = *v;
  }
  return std::nullopt;
}

// Whether j has any of the three keys.
bool containsAny(const json& j, const char* const (&keys)[3]) {
  return j.contains(keys[0]) || j.contains(keys[1]) || j.contains(keys[2]);
}

// The numbers at the three keys, read in order (the first failure is the error).
Result<Eigen::Vector3d> numbers(const json& j, const char* const (&keys)[3], const std::string& parent) {
  Eigen::Vector3d v;
  for (int k = 0; k < 3; ++k) {
    auto x = number(j, keys[k], parent);
    if (!x) return x.error();
    v[k] = *x;
  }
  return v;
}

// j[key] as an array of points named key[i] (absent: empty when optional).
Result<std::vector<MissionPointData>> pointArray(const json& j, const std::string& key, bool required) {
  std::vector<MissionPointData> points;
  auto it = j.find(key);
  if (it == j.end()) {
    if (required) return invalid(key, "is missing");
    return points;
  }
  if (!it->is_array()) return invalid(key, "must be an array of points");
  for (std::size_t i = 0; i < it->size(); ++i) {
    auto p = missionPointFromJson((*it)[i], key + "[" + std::to_string(i) + "]");
    if (!p) return p.error();
    points.push_back(*p);
  }
  return points;
}

}  // namespace

json missionPointToJson(const MissionPointData& point) {
  if (point.frame == MissionPointData::Frame::kWgs84)
    return json{{"lat_deg", point.geo.lat_deg}, {"lon_deg", point.geo.lon_deg}, {"alt_amsl_m", point.geo.alt_amsl_m}};
  return json{{"east_m", point.enu_m.x()}, {"north_m", point.enu_m.y()}, {"up_m", point.enu_m.z()}};
}

Result<MissionPointData> missionPointFromJson(const json& j, const std::string& field) {
  if (!j.is_object()) return invalid(field, "must be an object with lat_deg, lon_deg, alt_amsl_m or east_m, north_m, up_m");
  if (auto unknown = unknownJsonKey(j, {"lat_deg", "lon_deg", "alt_amsl_m", "east_m", "north_m", "up_m"}, field, field))
    return *unknown;
  const char* const geo_keys[] = {"lat_deg", "lon_deg", "alt_amsl_m"};
  const char* const enu_keys[] = {"east_m", "north_m", "up_m"};
  // One frame per point: the other frame's numbers would be ignored.
  if (containsAny(j, geo_keys) && containsAny(j, enu_keys))
    return invalid(field, "mixes lat_deg/lon_deg/alt_amsl_m with east_m/north_m/up_m (give one of the two)");
  if (containsAny(j, geo_keys)) {
    auto geo = numbers(j, geo_keys, field);
    if (!geo) return geo.error();
    return MissionPointData::wgs84(geo->x(), geo->y(), geo->z());
  }
  if (containsAny(j, enu_keys)) {
    auto enu = numbers(j, enu_keys, field);
    if (!enu) return enu.error();
    return MissionPointData::enu(*enu);
  }
  return invalid(field, "has neither lat_deg/lon_deg/alt_amsl_m nor east_m/north_m/up_m");
}

json missionToJson(const MissionRequestData& m) {
  json points = json::array();
  for (const auto& p : m.points) points.push_back(missionPointToJson(p));
  return json{{"request_id", m.request_id},
              {"vehicle_id", m.vehicle_id},
              {"begin", missionPointToJson(m.begin)},
              {"points", points},
              {"end", missionPointToJson(m.end)},
              {"limits", limitsToJson(m.limits)},
              {"planner", m.planner},
              {"fixed_order", m.fixed_order}};
}

Result<MissionRequestData> missionFromJson(const json& j) {
  if (!j.is_object()) return invalid("mission", "must be a JSON object");
  // height_ref is the mission file's, read by the CLI (service/mission_heights.hpp).
  if (auto unknown = unknownJsonKey(j,
                                    {"request_id", "vehicle_id", "begin", "points", "end", "limits", "planner",
                                     "fixed_order", "height_ref"},
                                    "", "mission"))
    return *unknown;
  MissionRequestData m;
  if (auto e = assignResult(text(j, "request_id", "", ""), m.request_id)) return *e;
  if (auto e = assignResult(text(j, "vehicle_id", "", ""), m.vehicle_id)) return *e;
  for (const char* key : {"begin", "end"})
    if (!j.contains(key)) return invalid(key, "is missing");
  if (auto e = assignResult(missionPointFromJson(j.at("begin"), "begin"), m.begin)) return *e;
  if (auto e = assignResult(missionPointFromJson(j.at("end"), "end"), m.end)) return *e;
  if (auto e = assignResult(pointArray(j, "points", false), m.points)) return *e;
  if (auto bad = limitsFromJson(j, m.limits)) return *bad;
  if (auto e = assignResult(text(j, "planner", "", ""), m.planner)) return *e;
  if (auto e = assignResult(boolean(j, "fixed_order", "", false), m.fixed_order)) return *e;
  return m;
}

json fleetToJson(const FleetRequestData& f) {
  auto points = [](const std::vector<MissionPointData>& list) {
    json a = json::array();
    for (const auto& p : list) a.push_back(missionPointToJson(p));
    return a;
  };
  return json{{"request_id", f.request_id}, {"vehicle_ids", f.vehicle_ids},        {"begins", points(f.begins)},
              {"tasks", points(f.tasks)},     {"ends", points(f.ends)},              {"limits", limitsToJson(f.limits)},
              {"planner", f.planner}};
}

Result<FleetRequestData> fleetFromJson(const json& j) {
  if (!j.is_object()) return invalid("fleet", "must be a JSON object");
  if (auto unknown = unknownJsonKey(j, {"request_id", "vehicle_ids", "begins", "tasks", "ends", "limits", "planner"}, "",
                                    "fleet"))
    return *unknown;
  FleetRequestData f;
  if (auto e = assignResult(text(j, "request_id", "", ""), f.request_id)) return *e;
  if (auto e = assignResult(pointArray(j, "begins", true), f.begins)) return *e;
  if (auto ids = j.find("vehicle_ids"); ids != j.end()) {
    if (!ids->is_array()) return invalid("vehicle_ids", "must be an array of strings");
    for (std::size_t i = 0; i < ids->size(); ++i) {
      if (!(*ids)[i].is_string()) return invalid("vehicle_ids[" + std::to_string(i) + "]", "must be a string");
      f.vehicle_ids.push_back((*ids)[i].get<std::string>());
    }
    if (f.vehicle_ids.size() != f.begins.size()) {
      return invalid("vehicle_ids", "has " + std::to_string(f.vehicle_ids.size()) + " ids for " +
                                        std::to_string(f.begins.size()) + " begins");
    }
  } else {
    for (std::size_t i = 0; i < f.begins.size(); ++i) f.vehicle_ids.push_back("uav-" + std::to_string(i + 1));
  }
  if (auto e = assignResult(pointArray(j, "tasks", true), f.tasks)) return *e;
  auto ends = pointArray(j, "ends", false);
  if (!ends) return ends.error();
  f.ends = j.contains("ends") ? std::move(*ends) : f.begins;
  if (f.ends.size() != f.begins.size()) {
    return invalid("ends", "has " + std::to_string(f.ends.size()) + " points for " + std::to_string(f.begins.size()) +
                               " begins");
  }
  if (auto bad = limitsFromJson(j, f.limits)) return *bad;
  if (auto e = assignResult(text(j, "planner", "", ""), f.planner)) return *e;
  return f;
}

json obstacleToJson(const ObstacleUpdateData& u) {
  const Obstacle& o = u.obstacle;
  if (u.remove) return json{{"id", o.id}, {"remove", true}};
  json j{{"id", o.id},
         {"shape", std::string(to_string(o.shape))},
         {"size_m", array3(o.size_m)},
         {"position_m", array3(o.center_m)},
         {"motion", std::string(to_string(u.motionKind()))}};
  if (u.constant_velocity_enu_mps) j["velocity_mps"] = array3(*u.constant_velocity_enu_mps);
  if (o.motion) {
    j["from_m"] = array3(o.motion->from_m);
    j["to_m"] = array3(o.motion->to_m);
    j["speed_mps"] = o.motion->speed_mps;
  }
  return j;
}

Result<ObstacleUpdateData> obstacleFromJson(const json& j, const std::string& field, const KnownKeys& container_keys) {
  if (!j.is_object()) return invalid(field, "must be an object");
  KnownKeys known{"id",     "remove", "shape",   "size_m", "position_m", "motion", "velocity_mps",
                  "from_m", "to_m",   "speed_mps"};
  known.insert(known.end(), container_keys.begin(), container_keys.end());
  if (auto unknown = unknownJsonKey(j, known, field, field)) return *unknown;
  ObstacleUpdateData u;
  auto id = j.find("id");
  if (id == j.end()) return invalid(join(field, "id"), "is missing");
  if (!id->is_number_unsigned()) return invalid(join(field, "id"), "must be a non-negative integer");
  u.obstacle.id = id->get<std::uint64_t>();
  if (auto e = assignResult(boolean(j, "remove", field, false), u.remove)) return *e;
  if (u.remove) return u;

  auto shape_name = text(j, "shape", field, "");
  if (!shape_name) return shape_name.error();
  auto shape = parseObstacleShape(*shape_name);
  if (!shape) return invalid(join(field, "shape"), "'" + *shape_name + "' is not one of sphere, ellipsoid, box, cylinder");
  u.obstacle.shape = *shape;
  auto size = vector3(j, "size_m", field);
  if (!size) return size.error();
  u.obstacle.size_m = *size;

  auto motion_name = text(j, "motion", field, "static");
  if (!motion_name) return motion_name.error();
  auto motion = parseObstacleMotionKind(*motion_name);
  if (!motion)
    return invalid(join(field, "motion"), "'" + *motion_name + "' is not one of static, constant_velocity, back_and_forth");
  // A motion's keys under another motion would be ignored: velocity_mps without "motion":
  // "constant_velocity" is a static obstacle. (from_ and to_ cover the feed's from_deg, to_deg.)
  for (const auto& [key, value] : j.items()) {
    const bool back_and_forth_key = key == "speed_mps" || key.rfind("from_", 0) == 0 || key.rfind("to_", 0) == 0;
    const char* needs = key == "velocity_mps" ? "constant_velocity" : back_and_forth_key ? "back_and_forth" : nullptr;
    if (needs && to_string(*motion) != needs)
      return invalid(join(field, key), "applies to motion " + std::string(needs) + " only (motion is " +
                                           std::string(to_string(*motion)) + ")");
  }
  if (*motion == ObstacleMotionKind::kBackAndForth) {
    auto from = vector3(j, "from_m", field);
    if (!from) return from.error();
    auto to = vector3(j, "to_m", field);
    if (!to) return to.error();
    auto speed = number(j, "speed_mps", field);
    if (!speed) return speed.error();
    u.obstacle.motion = BackAndForth{*from, *to, *speed, 0.0};
    u.obstacle.center_m = *from;
    if (j.contains("position_m")) {
      auto position = vector3(j, "position_m", field);
      if (!position) return position.error();
      u.obstacle.center_m = *position;
    }
  } else {
    auto position = vector3(j, "position_m", field);
    if (!position) return position.error();
    u.obstacle.center_m = *position;
    if (*motion == ObstacleMotionKind::kConstantVelocity) {
      auto velocity = vector3(j, "velocity_mps", field);
      if (!velocity) return velocity.error();
      u.constant_velocity_enu_mps = *velocity;
    }
  }
  if (auto problem = validateObstacleUpdate(u)) return invalid(join(field, problem->field), problem->message.substr(problem->field.size() + 1));
  return u;
}

}  // namespace skyroute
