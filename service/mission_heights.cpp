#include "service/mission_heights.hpp"

#include <string>

namespace skyroute {

Result<std::optional<HeightReference>> missionHeightReferenceFromJson(const nlohmann::json& mission) {
  if (!mission.is_object() || !mission.contains("height_ref")) return std::optional<HeightReference>();
  const nlohmann::json& value = mission["height_ref"];
  const auto parsed = value.is_string() ? parseHeightReference(value.get<std::string>()) : std::nullopt;
  if (!parsed) {
    return make_error(ErrorCode::kInvalidArgument, "height_ref",
                      "height_ref " + value.dump() + " is not a height reference: use \"amsl\" or \"ellipsoid\"");
  }
  return std::optional<HeightReference>(*parsed);
}

Status convertMissionHeightsToAmsl(MissionRequestData& mission, const InputHeightConverter& converter) {
  auto convert = [&](MissionPointData& point, const std::string& field) -> Status {
    if (point.frame == MissionPointData::Frame::kEnu) {
      if (converter.reference() == HeightReference::kAmsl) return Status::success();
      return make_error(ErrorCode::kInvalidArgument, field,
                        "the point is given in ENU metres, whose up is already AMSL: height reference " +
                            std::string(to_string(converter.reference())) + " applies only to LAT,LON,ALT points");
    }
    auto amsl = converter.toAmslM(point.geo.lat_deg, point.geo.lon_deg, point.geo.alt_amsl_m, field);
    if (!amsl) return amsl.error();
    point.geo.alt_amsl_m = *amsl;
    return Status::success();
  };
  if (Status s = convert(mission.begin, "begin"); !s.ok()) return s;
  for (std::size_t i = 0; i < mission.points.size(); ++i) {
    if (Status s = convert(mission.points[i], "points[" + std::to_string(i) + "]"); !s.ok()) return s;
  }
  return convert(mission.end, "end");
}

}  // namespace skyroute
