// How the state journal (state_journal.hpp) stores what it keeps: a trajectory as a compact
// binary record (every number bit for bit, so a republished trajectory has the very samples that
// were published), obstacle updates, no-fly zones and fleet allocations as JSON text. Decoding
// never trusts its input: a short, overlong or malformed record is an error naming what is wrong.
#pragma once

#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "planning/core/result.hpp"
#include "service/mission_types.hpp"
#include "service/no_fly_zone_data.hpp"

namespace skyroute {

// Binary trajectory records: little-endian integers, IEEE doubles in host order (the journal is
// read back on the machine that wrote it), strings and arrays prefixed by a 32-bit length.
std::string encodeTrajectory(const TrajectoryData& trajectory);
Result<TrajectoryData> decodeTrajectory(const std::string& bytes);

// An obstacle update with its validity window (mission_json.hpp's form plus "valid_from_utc_ns"
// and "valid_until_utc_ns").
nlohmann::json obstacleRecordToJson(const ObstacleUpdateData& update);
Result<ObstacleUpdateData> obstacleRecordFromJson(const nlohmann::json& j);

// {"zone_id", "ring": [[lat, lon], ...], "floor_amsl_m", "ceiling_amsl_m", "valid_from_utc_ns",
//  "valid_until_utc_ns"}.
nlohmann::json noFlyZoneToJson(const NoFlyZoneData& zone);
Result<NoFlyZoneData> noFlyZoneFromJson(const nlohmann::json& j);

// A fleet's answer with its allocation: every FleetStatusData field.
nlohmann::json fleetStatusToJson(const FleetStatusData& status);
Result<FleetStatusData> fleetStatusFromJson(const nlohmann::json& j);

}  // namespace skyroute
