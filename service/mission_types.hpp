// Plain C++ mirrors of the DDS messages (idl/skyroute.idl), without any DDS type, so the engine,
// the CLI tools and the tests work with them directly. service/dds/ converts at the boundary.
// Times: absolute times are UTC nanoseconds since the Unix epoch (*_utc_ns); relative times are
// seconds (*_s). Positions are in the daemon's local ENU frame (terrain/local_frame.hpp) or WGS84.
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include <Eigen/Core>

#include "planning/core/result.hpp"
#include "terrain/local_frame.hpp"
#include "terrain/obstacle.hpp"
#include "trajectory/vehicle_limits.hpp"

namespace skyroute {

// Wall-clock now as UTC nanoseconds since the Unix epoch (the same clock as dds_time()).
std::int64_t utcNowNs();

// A mission point as the requester gave it: WGS84 or local ENU.
struct MissionPointData {
  enum class Frame { kWgs84, kEnu };
  Frame frame = Frame::kWgs84;
  GeoPoint geo;                                      // when frame == kWgs84
  Eigen::Vector3d enu_m = Eigen::Vector3d::Zero();   // when frame == kEnu

  static MissionPointData wgs84(double lat_deg, double lon_deg, double alt_amsl_m);
  static MissionPointData enu(const Eigen::Vector3d& enu_m);
  // The point in the frame's ENU metres, whichever frame it was given in.
  Eigen::Vector3d toEnu(const LocalFrame& frame) const;
};

// Vehicle limits (defaults are a small fixed-wing UAV; ranges in VehicleLimitBounds).
struct VehicleLimitsData {
  double v_ref_mps = 20.0;             // cruise speed for time allocation (V_ref)
  double max_speed_mps = 30.0;
  double max_accel_mps2 = 4.0;
  double max_climb_rate_mps = 5.0;
  double max_descent_rate_mps = 4.0;   // positive number
  double min_turn_radius_m = 0.0;     // 0 = no limit (a multirotor); a fixed wing sets its own
  double min_clearance_agl_m = 30.0;   // minimum height above ground
  double ceiling_amsl_m = 5000.0;      // maximum altitude AMSL
  // The vehicle model (trajectory/vehicle_limits.hpp); nullopt = the service's vehicle.model.
  std::optional<VehicleModel> model = std::nullopt;
  // Fixed wing only; 0 = the service's [vehicle] value (VehicleModelDefaults).
  double stall_speed_mps = 0.0;
  double stall_margin = 0.0;           // minimum airspeed = stall_speed_mps x stall_margin
  double max_bank_deg = 0.0;
  double max_climb_angle_deg = 0.0;    // flight path angle above the horizontal
  double max_descent_angle_deg = 0.0;  // below the horizontal (positive number)
};

// The service's vehicle model for requests that leave it to the service (the configuration's
// [vehicle] section): the model, and the fixed-wing values a request gives as 0.
struct VehicleModelDefaults {
  VehicleModel model = VehicleModel::kMultirotor;
  double stall_speed_mps = 0.0;  // none: a fixed-wing request must give its own
  double stall_margin = 1.3;
  double max_bank_deg = 30.0;
  double max_climb_angle_deg = 15.0;
  double max_descent_angle_deg = 15.0;
};

// The request's limits with the model and every fixed-wing value it left to the service filled in.
VehicleLimitsData withVehicleDefaults(VehicleLimitsData limits, const VehicleModelDefaults& defaults);

// The trajectory stage's limits for a request's (same values; climb and descent renamed; no model
// given: a multirotor).
VehicleLimits toVehicleLimits(const VehicleLimitsData& limits);

struct MissionRequestData {
  std::string request_id;
  std::string vehicle_id;
  MissionPointData begin;
  std::vector<MissionPointData> points;
  MissionPointData end;
  VehicleLimitsData limits;
  std::string planner;       // "" = the daemon's default
  bool fixed_order = false;  // true: visit points in the given order; false: MMD*L orders them
  // Not on the wire: the GUID of the writer the request came from (set by the service's DDS
  // edge), so its statuses can be addressed to that client alone ("" = not known).
  std::string requester = {};
};

// Point indices in a trajectory follow the request: 0 = begin, 1..N = points[0..N-1], N+1 = end.
struct LegBoundaryData {
  std::uint32_t from_point = 0;
  std::uint32_t to_point = 0;
  double start_s = 0.0;  // relative time where the leg starts
  double end_s = 0.0;
};

struct TrajectorySampleData {
  double t_rel_s = 0.0;       // seconds since the trajectory start
  std::int64_t utc_ns = 0;    // absolute UTC time of this sample
  Eigen::Vector3d position_enu_m = Eigen::Vector3d::Zero();
  Eigen::Vector3d velocity_enu_mps = Eigen::Vector3d::Zero();
  Eigen::Vector3d acceleration_enu_mps2 = Eigen::Vector3d::Zero();
  double heading_deg = 0.0;   // clockwise from north, [0, 360)
  GeoPoint geo;               // WGS84 latitude, longitude, altitude AMSL
};

struct TrajectoryData {
  std::string vehicle_id;     // the DDS key: one current trajectory per vehicle
  std::string plan_id;
  std::uint32_t revision = 0; // grows with each replan of the same plan
  std::string request_id;
  std::int64_t created_utc_ns = 0;
  std::vector<std::uint32_t> visiting_order;  // begin (0) first, end (N+1) last
  std::vector<LegBoundaryData> legs;
  std::vector<TrajectorySampleData> samples;
  // Not on the wire: the daemon whose writer delivered it (its instance id and role, from the
  // writer's USER_DATA; "" when not known), filled by the reader.
  std::string source_instance = {};
  std::string source_role = {};
};

// kReplanned: a new revision of a flying mission's trajectory (or, with an error, a replan that
// found nothing better; the revision named stays in force). kHolding: no new plan was found, so
// the new revision keeps the trajectory as far as it is clear, then stops and waits at rest; the
// mission goes on and replanning continues from the hold (docs/dds.md). kReordered: a new
// revision that visits the points left in a new order, chosen again after the obstacles changed
// (the message gives the old and the new order). None of these is terminal.
enum class PlanState { kAccepted, kPlanning, kSucceeded, kFailed, kCancelled, kReplanned, kHolding, kReordered };
std::string_view to_string(PlanState state);
bool isTerminal(PlanState state);  // succeeded, failed or cancelled

// The one error-code table of the service's replies (mirrors PlanErrorCode in the IDL).
enum class PlanErrorCode {
  kNone,
  kInvalidArgument,   // NaN, malformed or missing field
  kUnknownPlanner,
  kEmptyMission,
  kMissionTooLarge,
  kLimitsOutOfRange,
  kOutsideMap,
  kUnderGround,       // a point lies inside the terrain or an obstacle
  kUnreachable,
  kTimeout,
  kCancelled,
  kBusy,
  kInternal,
  kTooLarge,          // the plan would exceed a size bound: duration, samples or memory share
  kDuplicateRequest,  // the request_id is already queued or being planned for this vehicle
  kJournalUnavailable,  // the state journal cannot record it (a full disk): refused, nothing changed
};
std::string_view to_string(PlanErrorCode code);

// The pipeline's stages (mission_pipeline.hpp), so a failure says where it happened.
enum class PlanStage { kNone, kValidate, kOrder, kLegs, kTrajectory, kSampling, kReplan };
std::string_view to_string(PlanStage stage);

// A rejected or failed request: the wire code, the offending field and a message naming it, and
// where it failed: the stage and, when the failure is about one, the leg (0 = from the first
// point visited to the second) and the point (request numbering: 0 = begin, 1..N = points, N+1
// = end); -1 when none.
struct PlanError {
  PlanErrorCode code = PlanErrorCode::kInternal;
  std::string field;
  std::string message;
  PlanStage stage = PlanStage::kNone;
  int leg_index = -1;
  int point_index = -1;
  std::string describe() const;  // "field: message"
};
// Maps the library-wide ErrorCode onto the reply table (field and message carried over).
PlanError toPlanError(const Error& error);

struct PlanStatusData {
  std::string request_id;
  std::string vehicle_id;
  PlanState state = PlanState::kAccepted;
  PlanErrorCode error_code = PlanErrorCode::kNone;
  std::string field;            // the offending request field ("" when none)
  std::string message;          // names the field; on success, notes such as a capped budget
  double planning_time_s = 0.0;
  PlanStage stage = PlanStage::kNone;  // where a failure happened (PlanError)
  int leg_index = -1;
  int point_index = -1;
  std::string requester = {};        // the request's writer (MissionRequestData::requester); "" = anyone
  std::string service_instance = {}; // ServiceStatusData::instance_id of the daemon that answered
  std::string service_id = {};       // the DDS key: the answering service (dds.service_id)

  static PlanStatusData failed(const MissionRequestData& request, const PlanError& error, double planning_time_s);
};

// The vehicle limits a request may ask for. The lower bounds are physical: a route flown slower
// than min_speed_mps is a hover, and every second of it costs a trajectory sample, so a speed
// near zero would ask for unbounded work.
struct VehicleLimitBounds {
  double min_speed_mps = 1.0;            // v_ref_mps and max_speed_mps at least
  double max_speed_mps = 150.0;          // every speed limit at most
  double min_vertical_speed_mps = 0.1;   // max_climb_rate_mps and max_descent_rate_mps at least
  double min_accel_mps2 = 0.1;
  double max_accel_mps2 = 50.0;
  double max_turn_radius_m = 20000.0;
  double max_clearance_m = 5000.0;
  double max_ceiling_amsl_m = 12000.0;
};

// Every limit within its bounds (v_ref_mps also at most max_speed_mps); kLimitsOutOfRange naming
// the field, e.g. "limits.v_ref_mps", with the range and the value.
std::optional<PlanError> checkVehicleLimits(const VehicleLimitsData& limits, const VehicleLimitBounds& bounds);

// How big one published trajectory may be. Checked before anything is sampled: a request whose
// trajectory would be longer or have more samples is refused with kTooLarge.
struct TrajectorySizeBounds {
  double max_duration_s = 7200.0;        // longest trajectory, seconds
  std::size_t max_samples = 100000;      // most samples in one Trajectory message
};

// Limits the service accepts for a request before any planning (cheap checks first, as Nav2).
struct MissionRequestBounds {
  std::size_t max_points = 64;                 // mission points between begin and end
  VehicleLimitBounds limits;
  TrajectorySizeBounds trajectory;
};

// Structural checks of a request: ids present, every number finite, latitudes and longitudes in
// range, mission not oversize (a plain begin -> end mission has no points), limits in range. The
// planner's name is the registry's to check (planner_registry.hpp). Terrain checks (outside the
// DEM, under the ground) and the size of the plan are the engine's. Returns the first problem
// found.
std::optional<PlanError> validateMissionRequest(const MissionRequestData& request,
                                                const MissionRequestBounds& bounds = {});

struct CancelRequestData {
  std::string request_id;  // "" = whatever the vehicle is doing
  std::string vehicle_id;
  std::string requester = {};  // not on the wire: the cancel's writer, as MissionRequestData::requester
};

enum class ObstacleMotionKind { kStatic, kConstantVelocity, kBackAndForth };
std::string_view to_string(ObstacleMotionKind kind);

// An obstacle appears, moves or disappears. The geometry is terrain's Obstacle; its world clock
// here is UTC seconds since the epoch: a back-and-forth motion starts (at from_m) at valid_from.
struct ObstacleUpdateData {
  Obstacle obstacle;  // id, shape, size, centre at valid_from, optional back-and-forth motion
  std::optional<Eigen::Vector3d> constant_velocity_enu_mps;  // moves from centre_m at valid_from
  std::int64_t valid_from_utc_ns = 0;
  std::int64_t valid_until_utc_ns = 0;  // 0 = until removed
  bool remove = false;                   // the obstacle is gone (geometry ignored)

  ObstacleMotionKind motionKind() const;
};

// Names used in files and messages are terrain's to_string(ObstacleShape): "sphere", "ellipsoid", "box",
// "cylinder".
std::optional<ObstacleShape> parseObstacleShape(std::string_view name);
std::optional<ObstacleMotionKind> parseObstacleMotionKind(std::string_view name);

// Checks an obstacle update: finite numbers, positive sizes, speed > 0 for back and forth,
// valid_until after valid_from. field names follow the message ("size_m.x", "speed_mps", ...).
std::optional<PlanError> validateObstacleUpdate(const ObstacleUpdateData& update);

struct ServiceStatusData {
  std::string service_id;
  std::int64_t stamp_utc_ns = 0;
  bool terrain_loaded = false;
  std::string terrain_name;
  std::uint32_t vehicles = 0;
  std::uint32_t replans = 0;
  std::uint32_t queue_length = 0;
  std::string service_version;
  std::string idl_version;
  std::string instance_id = {};     // unique per daemon process
  std::int64_t started_utc_ns = 0;  // when the instance started
  double heartbeat_period_s = 1.0;  // the next heartbeat is due this long after this one
  std::uint32_t obstacles = 0;      // obstacles in force
  bool journal_ok = true;           // false while the state journal's writes fail (none kept: true)
  std::uint32_t audits = 0;          // trajectories audited before publishing since start
  std::uint32_t audit_failures = 0;  // of those, refused by the audit
  std::int64_t life_started_utc_ns = 0;  // the current life's start (a shard that stalled began anew)
};

struct FleetRequestData {
  std::string request_id;
  std::vector<std::string> vehicle_ids;
  std::vector<MissionPointData> begins;  // one per vehicle
  std::vector<MissionPointData> tasks;
  std::vector<MissionPointData> ends;    // one per vehicle
  VehicleLimitsData limits;
  std::string planner;
};

// One vehicle's share of a fleet plan: its tasks (indices into FleetRequestData::tasks, in visiting
// order) and how long its start was held back so it keeps the minimum separation.
struct FleetVehicleAllocationData {
  std::string vehicle_id;
  std::vector<std::uint32_t> tasks;
  double delay_s = 0.0;
};

// The answer to a FleetRequest besides the trajectories: state, error (the offending field, e.g.
// "tasks[3]", "begins[1]", "vehicle_ids[2]") and, on success, the allocation and the timing.
struct FleetStatusData {
  std::string request_id;
  PlanState state = PlanState::kAccepted;
  PlanErrorCode error_code = PlanErrorCode::kNone;
  std::string field;
  std::string message;
  std::vector<FleetVehicleAllocationData> allocation;  // one per vehicle, request order
  std::int32_t makespan_steps = 0;      // the grid plan's T_max (time steps)
  double makespan_s = 0.0;              // latest end of the flown trajectories, delays included
  double min_separation_m = 0.0;        // required between any two vehicles at every instant
  double achieved_separation_m = 0.0;   // least distance at the samples and refinement points of the check (the check proves the separation between them)
  std::uint32_t separation_repairs = 0; // vehicles whose start had to be delayed
  double planning_time_s = 0.0;
};

}  // namespace skyroute
