#include "service/dds/conversions.hpp"

#include "planning/core/assign_result.hpp"
#include "service/number_text.hpp"
#include "service/text_bounds.hpp"

#include <cmath>
#include <cstring>
#include <string>
#include <type_traits>

namespace skyroute::dds {

namespace {

// ---- writing: every string and buffer comes from dds_alloc, so dds_sample_free releases it ----

char* dup(const std::string& s) { return dds_string_dup(s.c_str()); }

// Allocates a zeroed buffer of n elements for an IDL sequence (nullptr for an empty one).
template <class Seq, class Elem>
Elem* allocSequence(Seq& seq, std::size_t n) {
  seq._length = static_cast<uint32_t>(n);
  seq._maximum = static_cast<uint32_t>(n);
  seq._release = n > 0;
  if (n == 0) {
    seq._buffer = nullptr;
    return nullptr;
  }
  auto* buffer = static_cast<Elem*>(dds_alloc(n * sizeof(Elem)));
  std::memset(static_cast<void*>(buffer), 0, n * sizeof(Elem));
  seq._buffer = buffer;
  return buffer;
}

skyroute_msgs_Vec3 vec(const Eigen::Vector3d& v) { return skyroute_msgs_Vec3{v.x(), v.y(), v.z()}; }
Eigen::Vector3d vec(const skyroute_msgs_Vec3& v) { return {v.x, v.y, v.z}; }

void pointToWire(const MissionPointData& in, skyroute_msgs_MissionPoint& out) {
  out = skyroute_msgs_MissionPoint{};
  if (in.frame == MissionPointData::Frame::kWgs84) {
    out.frame = skyroute_msgs_FRAME_WGS84;
    out.lat_deg = in.geo.lat_deg;
    out.lon_deg = in.geo.lon_deg;
    out.alt_amsl_m = in.geo.alt_amsl_m;
  } else {
    out.frame = skyroute_msgs_FRAME_ENU;
    out.east_m = in.enu_m.x();
    out.north_m = in.enu_m.y();
    out.up_m = in.enu_m.z();
  }
}

void pointsToWire(const std::vector<MissionPointData>& in, dds_sequence_skyroute_msgs_MissionPoint& out) {
  auto* buf = allocSequence<dds_sequence_skyroute_msgs_MissionPoint, skyroute_msgs_MissionPoint>(out, in.size());
  for (std::size_t i = 0; i < in.size(); ++i) pointToWire(in[i], buf[i]);
}

// The request's model on the wire: DEFAULT when it leaves it to the service.
std::int32_t modelToWire(const std::optional<VehicleModel>& model) {
  if (!model) return skyroute_msgs_VEHICLE_MODEL_DEFAULT;
  return *model == VehicleModel::kFixedWing ? skyroute_msgs_VEHICLE_MODEL_FIXED_WING : skyroute_msgs_VEHICLE_MODEL_MULTIROTOR;
}

skyroute_msgs_VehicleLimits limitsToWire(const VehicleLimitsData& l) {
  return skyroute_msgs_VehicleLimits{l.v_ref_mps,          l.max_speed_mps,        l.max_accel_mps2,
                                     l.max_climb_rate_mps, l.max_descent_rate_mps, l.min_turn_radius_m,
                                     l.min_clearance_agl_m, l.ceiling_amsl_m,      modelToWire(l.model),
                                     l.stall_speed_mps,    l.stall_margin,         l.max_bank_deg,
                                     l.max_climb_angle_deg, l.max_descent_angle_deg};
}

// ---- reading: first problem wins; field names are built only when something is wrong ----

Error invalid(const std::string& field, const std::string& reason) {
  return make_error(ErrorCode::kInvalidArgument, field, field + " " + reason);
}

std::optional<Error> finite(double v, const std::string& field) {
  if (std::isfinite(v)) return std::nullopt;
  return invalid(field, "is not a finite number (" + numberText(v) + ")");
}

std::optional<Error> finite(const skyroute_msgs_Vec3& v, const std::string& field) {
  if (auto e = finite(v.x, field + ".x")) return e;
  if (auto e = finite(v.y, field + ".y")) return e;
  return finite(v.z, field + ".z");
}

std::optional<Error> required(const char* s, const std::string& field) {
  if (s != nullptr && s[0] != '\0') return std::nullopt;
  return invalid(field, "is missing (empty)");
}

std::string text(const char* s) { return s != nullptr ? std::string(s) : std::string(); }

// The text bounds (service/text_bounds.hpp) on a wire string, checked before it is copied.
std::optional<Error> wireId(const char* s, const char* field, std::size_t max_chars = kMaxIdChars) {
  return checkId(s != nullptr ? std::string_view(s) : std::string_view(), field, max_chars);
}
std::optional<Error> wireOptionalId(const char* s, const char* field, std::size_t max_chars = kMaxIdChars) {
  return checkOptionalId(s != nullptr ? std::string_view(s) : std::string_view(), field, max_chars);
}
std::optional<Error> wireName(const char* s, const char* field) {
  return checkName(s != nullptr ? std::string_view(s) : std::string_view(), field);
}
std::optional<Error> wireFreeText(const char* s, const char* field) {
  return checkFreeText(s != nullptr ? std::string_view(s) : std::string_view(), field);
}
// An id as it may be echoed in a refusal: itself when valid, else its safe echo.
std::string echoedId(const char* s, std::size_t max_chars) {
  const std::string_view id = s != nullptr ? std::string_view(s) : std::string_view();
  return isValidId(id, max_chars) || id.empty() ? std::string(id) : echoOfUntrusted(id);
}

// A wire enum's value as an integer, read from its bytes: a sample may carry any value, and
// loading one outside the enumerators through the enum type is undefined (UBSan flags it).
template <class Enum>
int rawEnumValue(const Enum& v) {
  std::underlying_type_t<Enum> raw;
  static_assert(sizeof raw == sizeof v);
  std::memcpy(&raw, &v, sizeof raw);
  return static_cast<int>(raw);
}

std::optional<Error> valueInRange(int value, int last, const std::string& field) {
  if (value >= 0 && value <= last) return std::nullopt;
  return invalid(field, "has an unknown value " + std::to_string(value));
}

template <class Enum>
std::optional<Error> enumInRange(const Enum& v, int last, const std::string& field) {
  if constexpr (std::is_enum_v<Enum>) {
    return valueInRange(rawEnumValue(v), last, field);
  } else {
    return valueInRange(static_cast<int>(v), last, field);  // an enum sent as int32 (see the IDL)
  }
}

Result<MissionPointData> pointFromWire(const skyroute_msgs_MissionPoint& in, const std::string& field) {
  if (auto e = enumInRange(in.frame, skyroute_msgs_FRAME_ENU, field + ".frame")) return *e;
  if (in.frame == skyroute_msgs_FRAME_WGS84) {
    if (auto e = finite(in.lat_deg, field + ".lat_deg")) return *e;
    if (auto e = finite(in.lon_deg, field + ".lon_deg")) return *e;
    if (auto e = finite(in.alt_amsl_m, field + ".alt_amsl_m")) return *e;
    return MissionPointData::wgs84(in.lat_deg, in.lon_deg, in.alt_amsl_m);
  }
  if (auto e = finite(in.east_m, field + ".east_m")) return *e;
  if (auto e = finite(in.north_m, field + ".north_m")) return *e;
  if (auto e = finite(in.up_m, field + ".up_m")) return *e;
  return MissionPointData::enu({in.east_m, in.north_m, in.up_m});
}

Result<std::vector<MissionPointData>> pointsFromWire(const dds_sequence_skyroute_msgs_MissionPoint& in,
                                                     const std::string& field) {
  std::vector<MissionPointData> out;
  out.reserve(in._length);
  for (uint32_t i = 0; i < in._length; ++i) {
    auto p = pointFromWire(in._buffer[i], field + "[" + std::to_string(i) + "]");
    if (!p) return p.error();
    out.push_back(*p);
  }
  return out;
}

Result<VehicleLimitsData> limitsFromWire(const skyroute_msgs_VehicleLimits& in, const std::string& field) {
  const std::pair<double, const char*> values[] = {
      {in.v_ref_mps, "v_ref_mps"},
      {in.max_speed_mps, "max_speed_mps"},
      {in.max_accel_mps2, "max_accel_mps2"},
      {in.max_climb_rate_mps, "max_climb_rate_mps"},
      {in.max_descent_rate_mps, "max_descent_rate_mps"},
      {in.min_turn_radius_m, "min_turn_radius_m"},
      {in.min_clearance_agl_m, "min_clearance_agl_m"},
      {in.ceiling_amsl_m, "ceiling_amsl_m"},
      {in.stall_speed_mps, "stall_speed_mps"},
      {in.stall_margin, "stall_margin"},
      {in.max_bank_deg, "max_bank_deg"},
      {in.max_climb_angle_deg, "max_climb_angle_deg"},
      {in.max_descent_angle_deg, "max_descent_angle_deg"},
  };
  for (const auto& [v, name] : values)
    if (auto e = finite(v, field + "." + name)) return *e;
  if (auto e = enumInRange(in.model, skyroute_msgs_VEHICLE_MODEL_FIXED_WING, field + ".model")) return *e;
  VehicleLimitsData out;
  out.v_ref_mps = in.v_ref_mps;
  out.max_speed_mps = in.max_speed_mps;
  out.max_accel_mps2 = in.max_accel_mps2;
  out.max_climb_rate_mps = in.max_climb_rate_mps;
  out.max_descent_rate_mps = in.max_descent_rate_mps;
  out.min_turn_radius_m = in.min_turn_radius_m;
  out.min_clearance_agl_m = in.min_clearance_agl_m;
  out.ceiling_amsl_m = in.ceiling_amsl_m;
  if (in.model == skyroute_msgs_VEHICLE_MODEL_MULTIROTOR) out.model = VehicleModel::kMultirotor;
  if (in.model == skyroute_msgs_VEHICLE_MODEL_FIXED_WING) out.model = VehicleModel::kFixedWing;
  out.stall_speed_mps = in.stall_speed_mps;
  out.stall_margin = in.stall_margin;
  out.max_bank_deg = in.max_bank_deg;
  out.max_climb_angle_deg = in.max_climb_angle_deg;
  out.max_descent_angle_deg = in.max_descent_angle_deg;
  return out;
}

// ---- both directions: each message's plain members are listed once ----

// Copies a member from the plain struct to the wire message: strings are dds_alloc'ed, enums
// travel as their integer value.
struct CopyToWire {
  void operator()(const std::string& plain, char*& wire) const { wire = dup(plain); }
  template <class Plain, class Wire>
  void operator()(const Plain& plain, Wire& wire) const {
    if constexpr (std::is_enum_v<Plain>) {
      wire = static_cast<Wire>(static_cast<int>(plain));
    } else {
      wire = plain;
    }
  }
};

// Copies a member from the wire message to the plain struct (a null string reads as "").
// Enums are range-checked before this runs.
struct CopyFromWire {
  void operator()(std::string& plain, char* const& wire) const { plain = text(wire); }
  template <class Plain, class Wire>
  void operator()(Plain& plain, const Wire& wire) const {
    if constexpr (std::is_enum_v<Plain>) {
      plain = static_cast<Plain>(static_cast<int>(wire));
    } else {
      plain = wire;
    }
  }
};

// Each message's members that cross unchanged, named once for both directions (the plain
// structs spell them as the IDL does): MEMBER(name) stands for one member.
#define SKYROUTE_MISSION_REQUEST_MEMBERS(MEMBER) \
  MEMBER(request_id) MEMBER(vehicle_id) MEMBER(planner) MEMBER(fixed_order)
#define SKYROUTE_TRAJECTORY_MEMBERS(MEMBER) \
  MEMBER(vehicle_id) MEMBER(plan_id) MEMBER(revision) MEMBER(request_id) MEMBER(created_utc_ns)
#define SKYROUTE_PLAN_STATUS_MEMBERS(MEMBER)                                                                 \
  MEMBER(request_id) MEMBER(vehicle_id) MEMBER(state) MEMBER(error_code) MEMBER(field) MEMBER(message) \
  MEMBER(planning_time_s) MEMBER(stage) MEMBER(leg_index) MEMBER(point_index) MEMBER(requester) MEMBER(service_instance) \
  MEMBER(service_id)
#define SKYROUTE_SERVICE_STATUS_MEMBERS(MEMBER)                                                                \
  MEMBER(service_id) MEMBER(instance_id) MEMBER(started_utc_ns) MEMBER(heartbeat_period_s) MEMBER(stamp_utc_ns) \
  MEMBER(terrain_loaded) MEMBER(terrain_name) MEMBER(vehicles) MEMBER(replans) MEMBER(queue_length)           \
  MEMBER(obstacles) MEMBER(service_version) MEMBER(idl_version) MEMBER(journal_ok) MEMBER(audits) MEMBER(audit_failures) MEMBER(life_started_utc_ns)
#define SKYROUTE_FLEET_STATUS_MEMBERS(MEMBER)                                                                 \
  MEMBER(request_id) MEMBER(state) MEMBER(error_code) MEMBER(field) MEMBER(message) MEMBER(makespan_steps) \
  MEMBER(makespan_s) MEMBER(min_separation_m) MEMBER(achieved_separation_m) MEMBER(separation_repairs)      \
  MEMBER(planning_time_s)
// Used inside toWire(in, out) and fromWire(in) (filling `out`) respectively.
#define SKYROUTE_MEMBER_TO_WIRE(name) CopyToWire{}(in.name, out.name);
#define SKYROUTE_MEMBER_FROM_WIRE(name) CopyFromWire{}(out.name, in.name);

// Fills a wire sequence with one converted element per plain element.
template <class Elem, class Seq, class Plain, class Convert>
void sequenceToWire(const std::vector<Plain>& in, Seq& out, Convert convert) {
  Elem* buffer = allocSequence<Seq, Elem>(out, in.size());
  for (std::size_t i = 0; i < in.size(); ++i) buffer[i] = convert(in[i]);
}

}  // namespace

// ------------------------------------------------------------------------------------------------

void toWire(const MissionRequestData& in, skyroute_msgs_MissionRequest& out) {
  SKYROUTE_MISSION_REQUEST_MEMBERS(SKYROUTE_MEMBER_TO_WIRE)
  pointToWire(in.begin, out.begin);
  pointsToWire(in.points, out.points);
  pointToWire(in.end, out.end);
  out.limits = limitsToWire(in.limits);
}

Result<MissionRequestData> fromWire(const skyroute_msgs_MissionRequest& in) {
  if (auto e = wireId(in.vehicle_id, "vehicle_id")) return *e;
  if (auto e = wireId(in.request_id, "request_id", kMaxRequestIdChars)) return *e;
  if (auto e = wireName(in.planner, "planner")) return *e;
  MissionRequestData out;
  SKYROUTE_MISSION_REQUEST_MEMBERS(SKYROUTE_MEMBER_FROM_WIRE)
  if (auto e = assignResult(pointFromWire(in.begin, "begin"), out.begin)) return *e;
  if (auto e = assignResult(pointsFromWire(in.points, "points"), out.points)) return *e;
  if (auto e = assignResult(pointFromWire(in.end, "end"), out.end)) return *e;
  if (auto e = assignResult(limitsFromWire(in.limits, "limits"), out.limits)) return *e;
  return out;
}

void toWire(const TrajectoryData& in, skyroute_msgs_Trajectory& out) {
  SKYROUTE_TRAJECTORY_MEMBERS(SKYROUTE_MEMBER_TO_WIRE)
  sequenceToWire<uint32_t>(in.visiting_order, out.visiting_order, [](std::uint32_t v) { return v; });
  sequenceToWire<skyroute_msgs_LegBoundary>(in.legs, out.legs, [](const LegBoundaryData& l) {
    return skyroute_msgs_LegBoundary{l.from_point, l.to_point, l.start_s, l.end_s};
  });
  sequenceToWire<skyroute_msgs_TrajectorySample>(in.samples, out.samples, [](const TrajectorySampleData& s) {
    return skyroute_msgs_TrajectorySample{s.t_rel_s,
                                          s.utc_ns,
                                          vec(s.position_enu_m),
                                          vec(s.velocity_enu_mps),
                                          vec(s.acceleration_enu_mps2),
                                          s.heading_deg,
                                          s.geo.lat_deg,
                                          s.geo.lon_deg,
                                          s.geo.alt_amsl_m};
  });
}

namespace {

// The first non-finite member of samples[index], named in full.
std::optional<Error> sampleFiniteness(const skyroute_msgs_TrajectorySample& s, uint32_t index) {
  const double values[] = {s.t_rel_s, s.position_enu_m.x, s.position_enu_m.y, s.position_enu_m.z,
                           s.velocity_enu_mps.x, s.velocity_enu_mps.y, s.velocity_enu_mps.z,
                           s.acceleration_enu_mps2.x, s.acceleration_enu_mps2.y, s.acceleration_enu_mps2.z,
                           s.heading_deg, s.lat_deg, s.lon_deg, s.alt_amsl_m};
  bool all_finite = true;
  for (double v : values) all_finite = all_finite && std::isfinite(v);
  if (all_finite) return std::nullopt;  // the common case builds no field names
  const std::string field = "samples[" + std::to_string(index) + "]";
  if (auto e = finite(s.t_rel_s, field + ".t_rel_s")) return e;
  if (auto e = finite(s.position_enu_m, field + ".position_enu_m")) return e;
  if (auto e = finite(s.velocity_enu_mps, field + ".velocity_enu_mps")) return e;
  if (auto e = finite(s.acceleration_enu_mps2, field + ".acceleration_enu_mps2")) return e;
  if (auto e = finite(s.heading_deg, field + ".heading_deg")) return e;
  if (auto e = finite(s.lat_deg, field + ".lat_deg")) return e;
  if (auto e = finite(s.lon_deg, field + ".lon_deg")) return e;
  return finite(s.alt_amsl_m, field + ".alt_amsl_m");
}

}  // namespace

Result<TrajectoryData> fromWire(const skyroute_msgs_Trajectory& in) {
  if (auto e = wireId(in.vehicle_id, "vehicle_id")) return *e;
  if (auto e = wireId(in.plan_id, "plan_id", kMaxDerivedIdChars)) return *e;
  if (auto e = wireOptionalId(in.request_id, "request_id", kMaxDerivedIdChars)) return *e;
  TrajectoryData out;
  SKYROUTE_TRAJECTORY_MEMBERS(SKYROUTE_MEMBER_FROM_WIRE)
  out.visiting_order.assign(in.visiting_order._buffer, in.visiting_order._buffer + in.visiting_order._length);
  out.legs.reserve(in.legs._length);
  for (uint32_t i = 0; i < in.legs._length; ++i) {
    const skyroute_msgs_LegBoundary& l = in.legs._buffer[i];
    const std::string field = "legs[" + std::to_string(i) + "]";
    if (auto e = finite(l.start_s, field + ".start_s")) return *e;
    if (auto e = finite(l.end_s, field + ".end_s")) return *e;
    out.legs.push_back(LegBoundaryData{l.from_point, l.to_point, l.start_s, l.end_s});
  }
  out.samples.reserve(in.samples._length);
  for (uint32_t i = 0; i < in.samples._length; ++i) {
    const skyroute_msgs_TrajectorySample& s = in.samples._buffer[i];
    if (auto e = sampleFiniteness(s, i)) return *e;
    TrajectorySampleData d;
    d.t_rel_s = s.t_rel_s;
    d.utc_ns = s.utc_ns;
    d.position_enu_m = vec(s.position_enu_m);
    d.velocity_enu_mps = vec(s.velocity_enu_mps);
    d.acceleration_enu_mps2 = vec(s.acceleration_enu_mps2);
    d.heading_deg = s.heading_deg;
    d.geo = GeoPoint{s.lat_deg, s.lon_deg, s.alt_amsl_m};
    out.samples.push_back(d);
  }
  return out;
}

void toWire(const PlanStatusData& in, skyroute_msgs_PlanStatus& out) {
  SKYROUTE_PLAN_STATUS_MEMBERS(SKYROUTE_MEMBER_TO_WIRE)
  // A message is free text: within its bound on the wire, however long the reason grew.
  dds_string_free(out.message);
  out.message = dup(boundedFreeText(in.message));
}

// The plain enums list their values in the IDL's order; these pin that down at compile time.
static_assert(static_cast<int>(PlanState::kReplanned) == skyroute_msgs_STATE_REPLANNED);
static_assert(static_cast<int>(PlanState::kHolding) == skyroute_msgs_STATE_HOLDING);
static_assert(static_cast<int>(PlanState::kReordered) == skyroute_msgs_STATE_REORDERED);
static_assert(static_cast<int>(PlanErrorCode::kInternal) == skyroute_msgs_ERROR_INTERNAL);
static_assert(static_cast<int>(PlanErrorCode::kTooLarge) == skyroute_msgs_ERROR_TOO_LARGE);
static_assert(static_cast<int>(PlanErrorCode::kDuplicateRequest) == skyroute_msgs_ERROR_DUPLICATE_REQUEST);
static_assert(static_cast<int>(PlanErrorCode::kJournalUnavailable) == skyroute_msgs_ERROR_JOURNAL_UNAVAILABLE);
static_assert(static_cast<int>(PlanErrorCode::kUnderGround) == skyroute_msgs_ERROR_UNDER_GROUND);
static_assert(static_cast<int>(PlanStage::kReplan) == skyroute_msgs_STAGE_REPLAN);
static_assert(static_cast<int>(ObstacleShape::kCylinder) == skyroute_msgs_SHAPE_CYLINDER);
static_assert(static_cast<int>(ObstacleMotionKind::kBackAndForth) == skyroute_msgs_MOTION_BACK_AND_FORTH);

Result<PlanStatusData> fromWire(const skyroute_msgs_PlanStatus& in) {
  // A refused vehicle-wide cancel has no request id: the vehicle id then names what it answers.
  if (text(in.request_id).empty() && text(in.vehicle_id).empty()) {
    return invalid("request_id", "and vehicle_id are both missing (empty)");
  }
  // A refusal echoes what it refused: ids as sent when valid, else their safe echo.
  if (auto e = wireFreeText(in.request_id, "request_id")) return *e;
  if (auto e = wireFreeText(in.vehicle_id, "vehicle_id")) return *e;
  if (auto e = wireFreeText(in.field, "field")) return *e;
  if (auto e = wireFreeText(in.message, "message")) return *e;
  if (auto e = wireOptionalId(in.service_id, "service_id")) return *e;
  if (auto e = wireFreeText(in.service_instance, "service_instance")) return *e;
  if (auto e = wireFreeText(in.requester, "requester")) return *e;
  if (auto e = enumInRange(in.state, skyroute_msgs_STATE_REORDERED, "state")) return *e;
  if (auto e = enumInRange(in.error_code, skyroute_msgs_ERROR_JOURNAL_UNAVAILABLE, "error_code")) return *e;
  if (auto e = enumInRange(in.stage, skyroute_msgs_STAGE_REPLAN, "stage")) return *e;
  if (auto e = finite(in.planning_time_s, "planning_time_s")) return *e;
  PlanStatusData out;
  SKYROUTE_PLAN_STATUS_MEMBERS(SKYROUTE_MEMBER_FROM_WIRE)
  return out;
}

void toWire(const ObstacleUpdateData& in, skyroute_msgs_ObstacleUpdate& out) {
  const Obstacle& o = in.obstacle;
  out.obstacle_id = o.id;
  out.shape = static_cast<int32_t>(o.shape);
  out.size_m = vec(o.size_m);
  out.position_enu_m = vec(o.center_m);
  out.motion = static_cast<int32_t>(in.motionKind());
  out.velocity_enu_mps = vec(in.constant_velocity_enu_mps.value_or(Eigen::Vector3d::Zero()));
  if (o.motion) {
    out.from_enu_m = vec(o.motion->from_m);
    out.to_enu_m = vec(o.motion->to_m);
    out.speed_mps = o.motion->speed_mps;
  }
  out.valid_from_utc_ns = in.valid_from_utc_ns;
  out.valid_until_utc_ns = in.valid_until_utc_ns;
  out.remove = in.remove;
}

Result<ObstacleUpdateData> fromWire(const skyroute_msgs_ObstacleUpdate& in, std::int64_t now_utc_ns) {
  ObstacleUpdateData out;
  out.obstacle.id = in.obstacle_id;
  out.remove = in.remove;
  out.valid_from_utc_ns = in.valid_from_utc_ns != 0 ? in.valid_from_utc_ns : now_utc_ns;
  out.valid_until_utc_ns = in.valid_until_utc_ns;
  if (in.remove) return out;  // the geometry of a removal is ignored
  if (auto e = enumInRange(in.shape, skyroute_msgs_SHAPE_CYLINDER, "shape")) return *e;
  if (auto e = enumInRange(in.motion, skyroute_msgs_MOTION_BACK_AND_FORTH, "motion")) return *e;
  if (auto e = finite(in.size_m, "size_m")) return *e;
  if (auto e = finite(in.position_enu_m, "position_enu_m")) return *e;
  out.obstacle.shape = static_cast<ObstacleShape>(static_cast<int>(in.shape));
  out.obstacle.size_m = vec(in.size_m);
  out.obstacle.center_m = vec(in.position_enu_m);
  if (in.motion == skyroute_msgs_MOTION_CONSTANT_VELOCITY) {
    if (auto e = finite(in.velocity_enu_mps, "velocity_enu_mps")) return *e;
    out.constant_velocity_enu_mps = vec(in.velocity_enu_mps);
  } else if (in.motion == skyroute_msgs_MOTION_BACK_AND_FORTH) {
    if (auto e = finite(in.from_enu_m, "from_enu_m")) return *e;
    if (auto e = finite(in.to_enu_m, "to_enu_m")) return *e;
    if (auto e = finite(in.speed_mps, "speed_mps")) return *e;
    BackAndForth motion;
    motion.from_m = vec(in.from_enu_m);
    motion.to_m = vec(in.to_enu_m);
    motion.speed_mps = in.speed_mps;
    motion.start_time_s = static_cast<double>(out.valid_from_utc_ns) * 1e-9;
    out.obstacle.motion = motion;
  }
  if (auto problem = validateObstacleUpdate(out))
    return make_error(ErrorCode::kInvalidArgument, problem->field, problem->message);
  return out;
}

Result<ObstacleUpdateData> fromWire(const skyroute_msgs_ObstacleUpdate& in) { return fromWire(in, utcNowNs()); }

void toWire(const CancelRequestData& in, skyroute_msgs_CancelRequest& out) {
  out.request_id = dup(in.request_id);
  out.vehicle_id = dup(in.vehicle_id);
}

Result<CancelRequestData> fromWire(const skyroute_msgs_CancelRequest& in) {
  // A cancel names the vehicle, the request, or both.
  if (text(in.request_id).empty() && text(in.vehicle_id).empty()) {
    return invalid("vehicle_id", "and request_id are both missing (empty)");
  }
  if (auto e = wireOptionalId(in.request_id, "request_id", kMaxRequestIdChars)) return *e;
  if (auto e = wireOptionalId(in.vehicle_id, "vehicle_id")) return *e;
  return CancelRequestData{text(in.request_id), text(in.vehicle_id)};
}

void toWire(const ServiceStatusData& in, skyroute_msgs_ServiceStatus& out) {
  SKYROUTE_SERVICE_STATUS_MEMBERS(SKYROUTE_MEMBER_TO_WIRE)
}

Result<ServiceStatusData> fromWire(const skyroute_msgs_ServiceStatus& in) {
  if (auto e = wireId(in.service_id, "service_id")) return *e;
  if (auto e = wireFreeText(in.instance_id, "instance_id")) return *e;
  if (auto e = wireFreeText(in.terrain_name, "terrain_name")) return *e;
  if (auto e = wireName(in.service_version, "service_version")) return *e;
  if (auto e = wireName(in.idl_version, "idl_version")) return *e;
  if (auto e = finite(in.heartbeat_period_s, "heartbeat_period_s")) return *e;
  ServiceStatusData out;
  SKYROUTE_SERVICE_STATUS_MEMBERS(SKYROUTE_MEMBER_FROM_WIRE)
  return out;
}

void toWire(const FleetRequestData& in, skyroute_msgs_FleetRequest& out) {
  out.request_id = dup(in.request_id);
  sequenceToWire<char*>(in.vehicle_ids, out.vehicle_ids, [](const std::string& id) { return dup(id); });
  pointsToWire(in.begins, out.begins);
  pointsToWire(in.tasks, out.tasks);
  pointsToWire(in.ends, out.ends);
  out.limits = limitsToWire(in.limits);
  out.planner = dup(in.planner);
}

Result<FleetRequestData> fromWire(const skyroute_msgs_FleetRequest& in) {
  if (auto e = wireId(in.request_id, "request_id", kMaxRequestIdChars)) return *e;
  if (auto e = wireName(in.planner, "planner")) return *e;
  FleetRequestData out;
  out.request_id = in.request_id;
  for (uint32_t i = 0; i < in.vehicle_ids._length; ++i) {
    const std::string field = "vehicle_ids[" + std::to_string(i) + "]";
    if (auto e = wireId(in.vehicle_ids._buffer[i], field.c_str())) return *e;
    out.vehicle_ids.emplace_back(in.vehicle_ids._buffer[i]);
  }
  if (auto e = assignResult(pointsFromWire(in.begins, "begins"), out.begins)) return *e;
  if (auto e = assignResult(pointsFromWire(in.tasks, "tasks"), out.tasks)) return *e;
  if (auto e = assignResult(pointsFromWire(in.ends, "ends"), out.ends)) return *e;
  if (auto e = assignResult(limitsFromWire(in.limits, "limits"), out.limits)) return *e;
  out.planner = text(in.planner);
  return out;
}

MissionRequestData identityFromWire(const skyroute_msgs_MissionRequest& in) {
  MissionRequestData out;
  out.request_id = echoedId(in.request_id, kMaxRequestIdChars);
  out.vehicle_id = echoedId(in.vehicle_id, kMaxIdChars);
  return out;
}

CancelRequestData identityFromWire(const skyroute_msgs_CancelRequest& in) {
  return CancelRequestData{echoedId(in.request_id, kMaxRequestIdChars), echoedId(in.vehicle_id, kMaxIdChars)};
}

FleetRequestData identityFromWire(const skyroute_msgs_FleetRequest& in) {
  FleetRequestData out;
  out.request_id = echoedId(in.request_id, kMaxRequestIdChars);
  return out;
}

void toWire(const FleetStatusData& in, skyroute_msgs_FleetStatus& out) {
  SKYROUTE_FLEET_STATUS_MEMBERS(SKYROUTE_MEMBER_TO_WIRE)
  dds_string_free(out.message);
  out.message = dup(boundedFreeText(in.message));
  using WireAllocation = skyroute_msgs_FleetVehicleAllocation;
  sequenceToWire<WireAllocation>(in.allocation, out.allocation, [](const FleetVehicleAllocationData& a) {
    WireAllocation wire{};
    wire.vehicle_id = dup(a.vehicle_id);
    sequenceToWire<uint32_t>(a.tasks, wire.tasks, [](std::uint32_t task) { return task; });
    wire.delay_s = a.delay_s;
    return wire;
  });
}

Result<FleetStatusData> fromWire(const skyroute_msgs_FleetStatus& in) {
  if (auto e = required(in.request_id, "request_id")) return *e;
  if (auto e = wireFreeText(in.request_id, "request_id")) return *e;
  if (auto e = wireFreeText(in.field, "field")) return *e;
  if (auto e = wireFreeText(in.message, "message")) return *e;
  if (auto e = enumInRange(in.state, skyroute_msgs_STATE_HOLDING, "state")) return *e;
  if (auto e = enumInRange(in.error_code, skyroute_msgs_ERROR_JOURNAL_UNAVAILABLE, "error_code")) return *e;
  if (auto e = finite(in.makespan_s, "makespan_s")) return *e;
  if (auto e = finite(in.min_separation_m, "min_separation_m")) return *e;
  if (auto e = finite(in.achieved_separation_m, "achieved_separation_m")) return *e;
  if (auto e = finite(in.planning_time_s, "planning_time_s")) return *e;
  FleetStatusData out;
  SKYROUTE_FLEET_STATUS_MEMBERS(SKYROUTE_MEMBER_FROM_WIRE)
  for (uint32_t i = 0; i < in.allocation._length; ++i) {
    const skyroute_msgs_FleetVehicleAllocation& w = in.allocation._buffer[i];
    const std::string field = "allocation[" + std::to_string(i) + "]";
    if (auto e = wireId(w.vehicle_id, (field + ".vehicle_id").c_str())) return *e;
    if (auto e = finite(w.delay_s, field + ".delay_s")) return *e;
    FleetVehicleAllocationData a;
    a.vehicle_id = w.vehicle_id;
    a.tasks.assign(w.tasks._buffer, w.tasks._buffer + w.tasks._length);
    a.delay_s = w.delay_s;
    out.allocation.push_back(std::move(a));
  }
  return out;
}

#undef SKYROUTE_MEMBER_FROM_WIRE
#undef SKYROUTE_MEMBER_TO_WIRE
#undef SKYROUTE_FLEET_STATUS_MEMBERS
#undef SKYROUTE_SERVICE_STATUS_MEMBERS
#undef SKYROUTE_PLAN_STATUS_MEMBERS
#undef SKYROUTE_TRAJECTORY_MEMBERS
#undef SKYROUTE_MISSION_REQUEST_MEMBERS

}  // namespace skyroute::dds
