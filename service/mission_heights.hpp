// A mission's heights in a chosen reference (AMSL, or above the WGS 84 ellipsoid as GNSS and
// GeoJSON give them), turned into AMSL, the service's own datum, before the mission goes anywhere.
// A mission file may say which reference its heights use with a top-level "height_ref" field.
#pragma once

#include <optional>

#include <nlohmann/json.hpp>

#include "planning/core/result.hpp"
#include "service/height_datum.hpp"
#include "service/mission_types.hpp"

namespace skyroute {

// The mission JSON's "height_ref": "amsl" | "ellipsoid"; nullopt when absent. Error
// kInvalidArgument (field "height_ref") for any other value or type.
Result<std::optional<HeightReference>> missionHeightReferenceFromJson(const nlohmann::json& mission);

// Rewrites every LAT,LON,ALT point's altitude (begin, points[i], end) to AMSL. An ellipsoidal
// reference needs LAT,LON,ALT points: an ENU point (its up is already AMSL) is an error naming it.
Status convertMissionHeightsToAmsl(MissionRequestData& mission, const InputHeightConverter& converter);

}  // namespace skyroute
