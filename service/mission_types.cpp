#include "service/mission_types.hpp"

#include "planning/core/enum_names.hpp"
#include "planning/core/field_problem.hpp"

#include "service/number_text.hpp"
#include "service/text_bounds.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>

namespace skyroute {

std::int64_t utcNowNs() {
  return std::chrono::duration_cast<std::chrono::nanoseconds>(
             std::chrono::system_clock::now().time_since_epoch())
      .count();
}

MissionPointData MissionPointData::wgs84(double lat_deg, double lon_deg, double alt_amsl_m) {
  MissionPointData p;
  p.frame = Frame::kWgs84;
  p.geo = GeoPoint{lat_deg, lon_deg, alt_amsl_m};
  return p;
}

MissionPointData MissionPointData::enu(const Eigen::Vector3d& enu_m) {
  MissionPointData p;
  p.frame = Frame::kEnu;
  p.enu_m = enu_m;
  return p;
}

Eigen::Vector3d MissionPointData::toEnu(const LocalFrame& frame_of) const {
  return frame == Frame::kWgs84 ? frame_of.toEnu(geo) : enu_m;
}

std::string_view to_string(PlanState state) {
  switch (state) {
    case PlanState::kAccepted: return "accepted";
    case PlanState::kPlanning: return "planning";
    case PlanState::kSucceeded: return "succeeded";
    case PlanState::kFailed: return "failed";
    case PlanState::kCancelled: return "cancelled";
    case PlanState::kReplanned: return "replanned";
    case PlanState::kHolding: return "holding";
    case PlanState::kReordered: return "reordered";
  }
  return "unknown";
}

bool isTerminal(PlanState state) {
  return state == PlanState::kSucceeded || state == PlanState::kFailed || state == PlanState::kCancelled;
}

std::string_view to_string(PlanErrorCode code) {
  switch (code) {
    case PlanErrorCode::kNone: return "none";
    case PlanErrorCode::kInvalidArgument: return "invalid_argument";
    case PlanErrorCode::kUnknownPlanner: return "unknown_planner";
    case PlanErrorCode::kEmptyMission: return "empty_mission";
    case PlanErrorCode::kMissionTooLarge: return "mission_too_large";
    case PlanErrorCode::kLimitsOutOfRange: return "limits_out_of_range";
    case PlanErrorCode::kOutsideMap: return "outside_map";
    case PlanErrorCode::kUnderGround: return "under_ground";
    case PlanErrorCode::kUnreachable: return "unreachable";
    case PlanErrorCode::kTimeout: return "timeout";
    case PlanErrorCode::kCancelled: return "cancelled";
    case PlanErrorCode::kBusy: return "busy";
    case PlanErrorCode::kInternal: return "internal";
    case PlanErrorCode::kTooLarge: return "too_large";
    case PlanErrorCode::kDuplicateRequest: return "duplicate_request";
    case PlanErrorCode::kJournalUnavailable: return "journal_unavailable";
  }
  return "unknown";
}

std::string_view to_string(PlanStage stage) {
  constexpr EnumName<PlanStage> kNames[] = {
      {PlanStage::kNone, "none"},         {PlanStage::kValidate, "validate"},     {PlanStage::kOrder, "order"},
      {PlanStage::kLegs, "legs"},         {PlanStage::kTrajectory, "trajectory"}, {PlanStage::kSampling, "sampling"},
      {PlanStage::kReplan, "replan"}};
  return enumName(kNames, stage);
}

std::string PlanError::describe() const { return describeFieldProblem(field, message); }

VehicleLimits toVehicleLimits(const VehicleLimitsData& d) {
  VehicleLimits l;
  l.v_ref_mps = d.v_ref_mps;
  l.max_speed_mps = d.max_speed_mps;
  l.max_accel_mps2 = d.max_accel_mps2;
  l.max_climb_mps = d.max_climb_rate_mps;
  l.max_descent_mps = d.max_descent_rate_mps;
  l.min_turn_radius_m = d.min_turn_radius_m;
  l.model = d.model.value_or(VehicleModel::kMultirotor);
  l.stall_speed_mps = d.stall_speed_mps;
  l.stall_margin = d.stall_margin;
  l.max_bank_deg = d.max_bank_deg;
  l.max_climb_angle_deg = d.max_climb_angle_deg;
  l.max_descent_angle_deg = d.max_descent_angle_deg;
  return l;
}

VehicleLimitsData withVehicleDefaults(VehicleLimitsData l, const VehicleModelDefaults& d) {
  if (!l.model) l.model = d.model;
  const std::pair<double VehicleLimitsData::*, double> given[] = {
      {&VehicleLimitsData::stall_speed_mps, d.stall_speed_mps},
      {&VehicleLimitsData::stall_margin, d.stall_margin},
      {&VehicleLimitsData::max_bank_deg, d.max_bank_deg},
      {&VehicleLimitsData::max_climb_angle_deg, d.max_climb_angle_deg},
      {&VehicleLimitsData::max_descent_angle_deg, d.max_descent_angle_deg}};
  for (const auto& [field, fallback] : given)
    if (l.*field == 0.0) l.*field = fallback;
  return l;
}

PlanError toPlanError(const Error& error) {
  PlanErrorCode code = PlanErrorCode::kInternal;
  switch (error.code) {
    case ErrorCode::kInvalidArgument:
    case ErrorCode::kParseError: code = PlanErrorCode::kInvalidArgument; break;
    case ErrorCode::kOutsideMap: code = PlanErrorCode::kOutsideMap; break;
    case ErrorCode::kOccupied: code = PlanErrorCode::kUnderGround; break;
    case ErrorCode::kUnreachable: code = PlanErrorCode::kUnreachable; break;
    case ErrorCode::kTimeout: code = PlanErrorCode::kTimeout; break;
    case ErrorCode::kCancelled: code = PlanErrorCode::kCancelled; break;
    case ErrorCode::kFileNotFound:
    case ErrorCode::kNotARaster:
    case ErrorCode::kNoCrs:
    case ErrorCode::kBandAmbiguous:
    case ErrorCode::kAllNodata:
    case ErrorCode::kAbsurdHeights:
    case ErrorCode::kInternal: code = PlanErrorCode::kInternal; break;
  }
  return PlanError{code, error.field, error.message};
}

PlanStatusData PlanStatusData::failed(const MissionRequestData& request, const PlanError& error,
                                      double planning_time_s) {
  PlanStatusData status;
  status.request_id = request.request_id;
  status.vehicle_id = request.vehicle_id;
  status.state = error.code == PlanErrorCode::kCancelled ? PlanState::kCancelled : PlanState::kFailed;
  status.error_code = error.code;
  status.field = error.field;
  status.message = error.describe();
  status.planning_time_s = planning_time_s;
  status.stage = error.stage;
  status.leg_index = error.leg_index;
  status.point_index = error.point_index;
  status.requester = request.requester;
  return status;
}

namespace {

PlanError problem(PlanErrorCode code, std::string field, const std::string& reason) {
  std::string message = field + " " + reason;
  return PlanError{code, std::move(field), std::move(message)};
}

std::optional<PlanError> checkFinite(double v, const std::string& field) {
  if (!std::isfinite(v)) return problem(PlanErrorCode::kInvalidArgument, field, "is not a finite number (" + numberText(v) + ")");
  return std::nullopt;
}

std::optional<PlanError> checkPoint(const MissionPointData& p, const std::string& field) {
  if (p.frame == MissionPointData::Frame::kWgs84) {
    if (auto e = checkFinite(p.geo.lat_deg, field + ".lat_deg")) return e;
    if (auto e = checkFinite(p.geo.lon_deg, field + ".lon_deg")) return e;
    if (auto e = checkFinite(p.geo.alt_amsl_m, field + ".alt_amsl_m")) return e;
    if (std::abs(p.geo.lat_deg) > 90.0)
      return problem(PlanErrorCode::kInvalidArgument, field + ".lat_deg", "must be within [-90, 90] (got " + numberText(p.geo.lat_deg) +
                         "): latitude and longitude may be swapped (write LAT,LON,ALT)");
    if (std::abs(p.geo.lon_deg) > 180.0)
      return problem(PlanErrorCode::kInvalidArgument, field + ".lon_deg", "must be within [-180, 180] (got " + numberText(p.geo.lon_deg) + ")");
    return std::nullopt;
  }
  if (auto e = checkFinite(p.enu_m.x(), field + ".east_m")) return e;
  if (auto e = checkFinite(p.enu_m.y(), field + ".north_m")) return e;
  return checkFinite(p.enu_m.z(), field + ".up_m");
}

std::optional<PlanError> checkRange(double v, double lo, double hi, bool lo_open, const std::string& field) {
  if (auto e = checkFinite(v, field)) return e;
  const bool below = lo_open ? !(v > lo) : v < lo;
  if (below || v > hi) {
    const std::string range = std::string(lo_open ? "(" : "[") + numberText(lo) + ", " + numberText(hi) + "]";
    return problem(PlanErrorCode::kLimitsOutOfRange, field, "must be within " + range + " (got " + numberText(v) + ")");
  }
  return std::nullopt;
}

std::optional<PlanError> checkFiniteVector(const Eigen::Vector3d& v, const std::string& field) {
  static const char* const kAxes[3] = {".x", ".y", ".z"};
  for (int i = 0; i < 3; ++i)
    if (auto e = checkFinite(v[i], field + kAxes[i])) return e;
  return std::nullopt;
}

}  // namespace

std::optional<PlanError> checkVehicleLimits(const VehicleLimitsData& l, const VehicleLimitBounds& b) {
  if (auto e = checkRange(l.max_speed_mps, b.min_speed_mps, b.max_speed_mps, false, "limits.max_speed_mps")) return e;
  if (auto e = checkRange(l.v_ref_mps, b.min_speed_mps, l.max_speed_mps, false, "limits.v_ref_mps")) return e;
  if (auto e = checkRange(l.max_accel_mps2, b.min_accel_mps2, b.max_accel_mps2, false, "limits.max_accel_mps2")) return e;
  if (auto e = checkRange(l.max_climb_rate_mps, b.min_vertical_speed_mps, b.max_speed_mps, false, "limits.max_climb_rate_mps"))
    return e;
  if (auto e = checkRange(l.max_descent_rate_mps, b.min_vertical_speed_mps, b.max_speed_mps, false,
                          "limits.max_descent_rate_mps"))
    return e;
  if (auto e = checkRange(l.min_turn_radius_m, 0.0, b.max_turn_radius_m, false, "limits.min_turn_radius_m")) return e;
  if (auto e = checkRange(l.min_clearance_agl_m, 0.0, b.max_clearance_m, false, "limits.min_clearance_agl_m")) return e;
  if (auto e = checkRange(l.ceiling_amsl_m, -500.0, b.max_ceiling_amsl_m, true, "limits.ceiling_amsl_m")) return e;
  // The fixed-wing values (0 = the service's): each within its range; the whole model (v_ref_mps
  // above the minimum airspeed) once the service's values are in (VehicleLimits::validate).
  if (auto e = checkRange(l.stall_speed_mps, 0.0, b.max_speed_mps, false, "limits.stall_speed_mps")) return e;
  if (l.stall_margin != 0.0)
    if (auto e = checkRange(l.stall_margin, 1.0, 3.0, false, "limits.stall_margin")) return e;
  if (auto e = checkRange(l.max_bank_deg, 0.0, 79.9, false, "limits.max_bank_deg")) return e;
  if (auto e = checkRange(l.max_climb_angle_deg, 0.0, 60.0, false, "limits.max_climb_angle_deg")) return e;
  if (auto e = checkRange(l.max_descent_angle_deg, 0.0, 60.0, false, "limits.max_descent_angle_deg")) return e;
  return std::nullopt;
}

std::optional<PlanError> validateMissionRequest(const MissionRequestData& request, const MissionRequestBounds& bounds) {
  // The strings first: nothing else may see an id that could not name a topic or a log line.
  // The vehicle id first: a tool may have made the request id from it.
  if (auto e = checkId(request.vehicle_id, "vehicle_id")) return toPlanError(*e);
  if (auto e = checkId(request.request_id, "request_id", kMaxRequestIdChars)) return toPlanError(*e);
  if (auto e = checkName(request.planner, "planner")) return toPlanError(*e);
  if (request.points.size() > bounds.max_points)
    return problem(PlanErrorCode::kMissionTooLarge, "points",
                   "has " + std::to_string(request.points.size()) + " points, more than the limit of " + std::to_string(bounds.max_points));
  if (auto e = checkPoint(request.begin, "begin")) return e;
  for (std::size_t i = 0; i < request.points.size(); ++i)
    if (auto e = checkPoint(request.points[i], "points[" + std::to_string(i) + "]")) return e;
  if (auto e = checkPoint(request.end, "end")) return e;

  return checkVehicleLimits(request.limits, bounds.limits);
}

constexpr EnumName<ObstacleMotionKind> kMotionKindNames[] = {{ObstacleMotionKind::kStatic, "static"},
                                                             {ObstacleMotionKind::kConstantVelocity, "constant_velocity"},
                                                             {ObstacleMotionKind::kBackAndForth, "back_and_forth"}};

std::string_view to_string(ObstacleMotionKind kind) { return enumName(kMotionKindNames, kind); }

ObstacleMotionKind ObstacleUpdateData::motionKind() const {
  if (obstacle.motion) return ObstacleMotionKind::kBackAndForth;
  if (constant_velocity_enu_mps) return ObstacleMotionKind::kConstantVelocity;
  return ObstacleMotionKind::kStatic;
}

std::optional<ObstacleShape> parseObstacleShape(std::string_view name) {
  for (ObstacleShape s : {ObstacleShape::kSphere, ObstacleShape::kEllipsoid, ObstacleShape::kBox, ObstacleShape::kCylinder})
    if (to_string(s) == name) return s;
  return std::nullopt;
}

std::optional<ObstacleMotionKind> parseObstacleMotionKind(std::string_view name) {
  return enumNamed(kMotionKindNames, name);
}

std::optional<PlanError> validateObstacleUpdate(const ObstacleUpdateData& update) {
  if (update.remove) return std::nullopt;  // geometry is ignored
  const Obstacle& o = update.obstacle;
  if (auto e = checkFiniteVector(o.size_m, "size_m")) return e;
  static const char* const kAxes[3] = {"size_m.x", "size_m.y", "size_m.z"};
  // Which size components the shape uses: sphere x; cylinder x and z; the others all three.
  const bool used[3] = {true, o.shape == ObstacleShape::kEllipsoid || o.shape == ObstacleShape::kBox,
                        o.shape != ObstacleShape::kSphere};
  for (int i = 0; i < 3; ++i)
    if (used[i] && !(o.size_m[i] > 0.0))
      return problem(PlanErrorCode::kInvalidArgument, kAxes[i], "must be positive for a " + std::string(to_string(o.shape)) +
                                                                    " (got " + numberText(o.size_m[i]) + ")");
  if (auto e = checkFiniteVector(o.center_m, "position_enu_m")) return e;
  if (update.constant_velocity_enu_mps)
    if (auto e = checkFiniteVector(*update.constant_velocity_enu_mps, "velocity_enu_mps")) return e;
  if (o.motion) {
    if (auto e = checkFiniteVector(o.motion->from_m, "from_enu_m")) return e;
    if (auto e = checkFiniteVector(o.motion->to_m, "to_enu_m")) return e;
    if (auto e = checkFinite(o.motion->speed_mps, "speed_mps")) return e;
    if (!(o.motion->speed_mps > 0.0))
      return problem(PlanErrorCode::kInvalidArgument, "speed_mps", "must be positive for a back-and-forth motion (got " + numberText(o.motion->speed_mps) + ")");
  }
  if (update.valid_until_utc_ns != 0 && update.valid_until_utc_ns <= update.valid_from_utc_ns)
    return problem(PlanErrorCode::kInvalidArgument, "valid_until_utc_ns", "must be after valid_from_utc_ns (or 0 for until removed)");
  return std::nullopt;
}

}  // namespace skyroute
