// JSON forms of missions and obstacle updates (mission files for `skyroute request --file`, lines
// of the obstacle feed). Reading validates types and names the offending field with its path,
// e.g. "points[2].lat_deg"; an unknown key is refused the same way, naming the known key it
// most likely misspells (service/known_keys.hpp). Formats: docs/obstacle_feed.md and docs/dds.md.
#pragma once

#include <nlohmann/json.hpp>

#include "planning/core/result.hpp"
#include "service/known_keys.hpp"
#include "service/mission_types.hpp"

namespace skyroute {

// A point is {"lat_deg", "lon_deg", "alt_amsl_m"} (WGS84) or {"east_m", "north_m", "up_m"} (ENU),
// never a mix of both.
nlohmann::json missionPointToJson(const MissionPointData& point);
Result<MissionPointData> missionPointFromJson(const nlohmann::json& j, const std::string& field);

// {"request_id", "vehicle_id", "begin", "points": [...], "end", "limits": {...}, "planner",
//  "fixed_order", "height_ref"}. Missing limits keep VehicleLimitsData's defaults; request_id and
// vehicle_id may be absent here (the CLI fills them in). height_ref is known but not read here
// (missionHeightReferenceFromJson reads it).
nlohmann::json missionToJson(const MissionRequestData& mission);
Result<MissionRequestData> missionFromJson(const nlohmann::json& j);

// A fleet request (`skyroute fleet --file`): {"request_id", "vehicle_ids": [...], "begins": [...],
// "tasks": [...], "ends": [...], "limits": {...}, "planner"}, points as in a mission. Reading:
// request_id may be absent (the CLI fills it in); without vehicle_ids the vehicles are uav-1 ..
// uav-N in the order of begins; without ends each vehicle returns to its begin; vehicle_ids and
// ends must match begins in length. Errors name the field with its path ("tasks[3].lat_deg").
nlohmann::json fleetToJson(const FleetRequestData& fleet);
Result<FleetRequestData> fleetFromJson(const nlohmann::json& j);

// Obstacle geometry and motion without the validity times (the feed stores those relative to the
// line's time): {"id", "remove", "shape", "size_m": [x,y,z], "position_m": [e,n,u],
// "motion": "static" | "constant_velocity" | "back_and_forth", "velocity_mps", "from_m", "to_m",
// "speed_mps"}. A motion's keys under another motion are refused (velocity_mps is for
// constant_velocity only; from_*, to_* and speed_mps for back_and_forth only). container_keys:
// keys the caller's format adds to the object and reads itself (the feed's position_deg, the
// journal's validity times).
nlohmann::json obstacleToJson(const ObstacleUpdateData& update);
Result<ObstacleUpdateData> obstacleFromJson(const nlohmann::json& j, const std::string& field,
                                            const KnownKeys& container_keys = {});

}  // namespace skyroute
