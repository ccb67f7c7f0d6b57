// Fuzzes the DDS edge: IDL C structs built from the fuzz bytes (any sequence length, NaN and
// infinities, enum values no enumerator has, empty and null strings) -> fromWire, then what the
// daemon does next. An accepted request meets the engine's checks (validateMissionRequest,
// validateFleetRequest with the daemon's defaults); a rejected one is answered with a status built
// from identityFromWire, as the daemon's node does; an accepted obstacle update is placed in the
// world as the daemon places it, and recorded as `skyroute record` does (the line must read back). The first byte picks the message type; the
// client-side messages (trajectory, statuses) are read as the ground-station tools read them.
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <iostream>
#include <sstream>
#include <string>

#include "service/dds/conversions.hpp"
#include "service/engine.hpp"
#include "service/fleet_mission.hpp"
#include "service/obstacle_feed.hpp"
#include "service/text_bounds.hpp"
#include "service/world_model.hpp"
#include "tests/fuzz/finding.hpp"
#include "tests/fuzz/fuzz_bytes.hpp"
#include "tests/fuzz/mission_equal.hpp"
#include "tests/fuzz/world_obstacle_probe.hpp"

namespace {

using skyroute::fuzz::FuzzBytes;
namespace dds = skyroute::dds;

// Fixed "now" (2024-01-01T00:00:00Z), so a run is reproducible.
constexpr std::int64_t kNowUtcNs = 1'704'067'200'000'000'000;
// Longest sequence built: past every limit the service has (64 points, vehicles and tasks).
constexpr std::uint32_t kMaxSequence = 1024;

[[noreturn]] void finding(const std::string& what) { skyroute::fuzz::reportFinding("dds_conversion_fuzzer", what); }

// A string as Cyclone hands it over (dds_alloc'd, freed with the sample); now and then null.
char* wireString(FuzzBytes& in) {
  if (in.byte() % 32 == 31) return nullptr;
  return dds_string_dup(in.text(64).c_str());
}

// Mostly a valid enumerator (0..count-1, and one past), sometimes any 32-bit value. Written into
// the member's bytes as the wire's deserializer does: a C++ load of a value no enumerator has would
// itself be undefined (fromWire reads the bytes too).
template <class Enum>
void wireEnum(FuzzBytes& in, Enum& member, int count) {
  const std::int32_t raw = in.byte() % 8 == 7 ? in.raw<std::int32_t>() : static_cast<std::int32_t>(in.byte() % (count + 1));
  static_assert(sizeof(Enum) == sizeof raw);
  std::memcpy(&member, &raw, sizeof raw);
}

std::uint32_t sequenceLength(FuzzBytes& in) {
  return in.byte() % 4 == 3 ? in.raw<std::uint16_t>() % (kMaxSequence + 1) : in.byte() % 8;
}

// A sequence of `length` elements, each filled by fill(in, element) (zeros once the bytes run out).
template <class Seq, class Elem, class Fill>
void wireSequence(FuzzBytes& in, Seq& seq, Fill fill) {
  const std::uint32_t length = sequenceLength(in);
  seq._length = length;
  seq._maximum = length;
  seq._release = true;
  seq._buffer = nullptr;
  if (length == 0) return;
  seq._buffer = static_cast<Elem*>(dds_alloc(length * sizeof(Elem)));
  std::memset(static_cast<void*>(seq._buffer), 0, length * sizeof(Elem));
  for (std::uint32_t i = 0; i < length; ++i) fill(in, seq._buffer[i]);
}

skyroute_msgs_Vec3 wireVec(FuzzBytes& in) { return {in.number(), in.number(), in.number()}; }

void wirePoint(FuzzBytes& in, skyroute_msgs_MissionPoint& p) {
  wireEnum(in, p.frame, 2);
  p.lat_deg = in.number();
  p.lon_deg = in.number();
  p.alt_amsl_m = in.number();
  p.east_m = in.number();
  p.north_m = in.number();
  p.up_m = in.number();
}

void wirePoints(FuzzBytes& in, dds_sequence_skyroute_msgs_MissionPoint& seq) {
  wireSequence<dds_sequence_skyroute_msgs_MissionPoint, skyroute_msgs_MissionPoint>(in, seq, wirePoint);
}

skyroute_msgs_VehicleLimits wireLimits(FuzzBytes& in) {
  skyroute_msgs_VehicleLimits l;
  for (double* v : {&l.v_ref_mps, &l.max_speed_mps, &l.max_accel_mps2, &l.max_climb_rate_mps, &l.max_descent_rate_mps,
                    &l.min_turn_radius_m, &l.min_clearance_agl_m, &l.ceiling_amsl_m, &l.stall_speed_mps,
                    &l.stall_margin, &l.max_bank_deg, &l.max_climb_angle_deg, &l.max_descent_angle_deg})
    *v = in.number();
  l.model = in.raw<std::int32_t>();
  return l;
}

void wireUint32s(FuzzBytes& in, dds_sequence_uint32& seq) {
  wireSequence<dds_sequence_uint32, std::uint32_t>(in, seq, [](FuzzBytes& b, std::uint32_t& v) { v = b.raw<std::uint32_t>(); });
}

void missionRequest(FuzzBytes& in) {
  using namespace skyroute;
  dds::WireSample<skyroute_msgs_MissionRequest> wire(&skyroute_msgs_MissionRequest_desc);
  skyroute_msgs_MissionRequest& m = wire.msg();
  m.request_id = wireString(in);
  m.vehicle_id = wireString(in);
  wirePoint(in, m.begin);
  wirePoints(in, m.points);
  wirePoint(in, m.end);
  m.limits = wireLimits(in);
  m.planner = wireString(in);
  m.fixed_order = in.flag();

  auto request = dds::fromWire(m);
  if (!request) {  // the daemon answers with a failed status naming the field
    const PlanError error = toPlanError(request.error());
    if (error.field.empty()) finding("a rejected request names no field: " + error.message);
    // The refusal echoes the ids it could not take bounded: never a topic name or log line of 64 KiB.
    const MissionRequestData who = dds::identityFromWire(m);
    if (who.vehicle_id.size() > 2 * kMaxIdChars || who.request_id.size() > 2 * kMaxRequestIdChars)
      finding("a refusal echoes an unbounded id (" + std::to_string(who.vehicle_id.size()) + " characters)");
    dds::WireSample<skyroute_msgs_PlanStatus> status(&skyroute_msgs_PlanStatus_desc);
    dds::toWire(PlanStatusData::failed(who, error, 0.0), status.msg());
    return;
  }
  if (!isValidId(request->vehicle_id) || !isValidId(request->request_id, kMaxRequestIdChars))
    finding("an accepted request's id is outside the text bounds");
  if (auto problem = validateMissionRequest(*request, EngineOptions{}.pipeline.bounds); problem && problem->field.empty())
    finding("a refused request names no field: " + problem->message);
  // What the daemon took in is what a client sending it would have sent.
  dds::WireSample<skyroute_msgs_MissionRequest> again(&skyroute_msgs_MissionRequest_desc);
  dds::toWire(*request, again.msg());
  auto back = dds::fromWire(again.msg());
  if (!back || !fuzz::sameMission(*back, *request)) finding("an accepted request does not survive its own wire form");
}

void obstacleUpdate(FuzzBytes& in) {
  using namespace skyroute;
  dds::WireSample<skyroute_msgs_ObstacleUpdate> wire(&skyroute_msgs_ObstacleUpdate_desc);
  skyroute_msgs_ObstacleUpdate& o = wire.msg();
  o.obstacle_id = in.raw<std::uint64_t>();
  wireEnum(in, o.shape, 4);
  o.size_m = wireVec(in);
  o.position_enu_m = wireVec(in);
  wireEnum(in, o.motion, 3);
  o.velocity_enu_mps = wireVec(in);
  o.from_enu_m = wireVec(in);
  o.to_enu_m = wireVec(in);
  o.speed_mps = in.number();
  o.valid_from_utc_ns = in.flag() ? kNowUtcNs + in.raw<std::int32_t>() * 1'000'000LL : in.raw<std::int64_t>();
  o.valid_until_utc_ns = in.flag() ? 0 : in.raw<std::int64_t>();
  o.remove = in.flag();
  auto update = dds::fromWire(o, kNowUtcNs);
  if (!update) {
    if (update.error().field.empty()) finding("a rejected obstacle update names no field");
    return;
  }
  fuzz::probeWorldObstacle(*update, kNowUtcNs);
  // `skyroute record` writes what it hears as a feed line, which `skyroute replay` must read back.
  const FeedEntry entry = FeedEntry::fromUpdate(*update, 0.0, kNowUtcNs);
  std::istringstream recorded(obstacleFeedHeaderLine() + "\n" + obstacleFeedEntryLine(entry) + "\n");
  auto feed = parseObstacleFeed(recorded, "recorded.jsonl");
  if (!feed || feed->entries.size() != 1)
    finding("a recorded update does not replay: " + (feed && !feed->skipped.empty() ? feed->skipped[0].message : ""));
}

void cancelRequest(FuzzBytes& in) {
  dds::WireSample<skyroute_msgs_CancelRequest> wire(&skyroute_msgs_CancelRequest_desc);
  wire.msg().request_id = wireString(in);
  wire.msg().vehicle_id = wireString(in);
  auto cancel = dds::fromWire(wire.msg());
  if (!cancel) (void)dds::identityFromWire(wire.msg());
}

void fleetRequest(FuzzBytes& in) {
  using namespace skyroute;
  dds::WireSample<skyroute_msgs_FleetRequest> wire(&skyroute_msgs_FleetRequest_desc);
  skyroute_msgs_FleetRequest& f = wire.msg();
  f.request_id = wireString(in);
  wireSequence<dds_sequence_string, char*>(in, f.vehicle_ids, [](FuzzBytes& b, char*& s) { s = wireString(b); });
  wirePoints(in, f.begins);
  wirePoints(in, f.tasks);
  wirePoints(in, f.ends);
  f.limits = wireLimits(in);
  f.planner = wireString(in);
  auto request = dds::fromWire(f);
  if (!request) {
    const PlanError error = toPlanError(request.error());
    FleetStatusData status;
    status.request_id = dds::identityFromWire(f).request_id;
    status.state = PlanState::kFailed;
    status.error_code = error.code;
    status.field = error.field;
    status.message = error.describe();
    dds::WireSample<skyroute_msgs_FleetStatus> reply(&skyroute_msgs_FleetStatus_desc);
    dds::toWire(status, reply.msg());
    return;
  }
  if (auto problem = validateFleetRequest(*request, EngineOptions{}.pipeline.fleet); problem && problem->field.empty())
    finding("a refused fleet request names no field: " + problem->message);
}

void trajectory(FuzzBytes& in) {
  dds::WireSample<skyroute_msgs_Trajectory> wire(&skyroute_msgs_Trajectory_desc);
  skyroute_msgs_Trajectory& t = wire.msg();
  t.vehicle_id = wireString(in);
  t.plan_id = wireString(in);
  t.revision = in.raw<std::uint32_t>();
  t.request_id = wireString(in);
  t.created_utc_ns = in.raw<std::int64_t>();
  wireUint32s(in, t.visiting_order);
  wireSequence<dds_sequence_skyroute_msgs_LegBoundary, skyroute_msgs_LegBoundary>(
      in, t.legs, [](FuzzBytes& b, skyroute_msgs_LegBoundary& l) {
        l = {b.raw<std::uint32_t>(), b.raw<std::uint32_t>(), b.number(), b.number()};
      });
  wireSequence<dds_sequence_skyroute_msgs_TrajectorySample, skyroute_msgs_TrajectorySample>(
      in, t.samples, [](FuzzBytes& b, skyroute_msgs_TrajectorySample& s) {
        s.t_rel_s = b.number();
        s.utc_ns = b.raw<std::int64_t>();
        s.position_enu_m = wireVec(b);
        s.velocity_enu_mps = wireVec(b);
        s.acceleration_enu_mps2 = wireVec(b);
        s.heading_deg = b.number();
        s.lat_deg = b.number();
        s.lon_deg = b.number();
        s.alt_amsl_m = b.number();
      });
  (void)dds::fromWire(t);
}

void planStatus(FuzzBytes& in) {
  dds::WireSample<skyroute_msgs_PlanStatus> wire(&skyroute_msgs_PlanStatus_desc);
  skyroute_msgs_PlanStatus& s = wire.msg();
  s.request_id = wireString(in);
  s.vehicle_id = wireString(in);
  wireEnum(in, s.state, 6);
  wireEnum(in, s.error_code, 13);
  s.field = wireString(in);
  s.message = wireString(in);
  s.planning_time_s = in.number();
  (void)dds::fromWire(s);
}

void serviceStatus(FuzzBytes& in) {
  dds::WireSample<skyroute_msgs_ServiceStatus> wire(&skyroute_msgs_ServiceStatus_desc);
  skyroute_msgs_ServiceStatus& s = wire.msg();
  s.service_id = wireString(in);
  s.stamp_utc_ns = in.raw<std::int64_t>();
  s.terrain_loaded = in.flag();
  s.terrain_name = wireString(in);
  s.vehicles = in.raw<std::uint32_t>();
  s.replans = in.raw<std::uint32_t>();
  s.queue_length = in.raw<std::uint32_t>();
  s.service_version = wireString(in);
  s.idl_version = wireString(in);
  (void)dds::fromWire(s);
}

void fleetStatus(FuzzBytes& in) {
  dds::WireSample<skyroute_msgs_FleetStatus> wire(&skyroute_msgs_FleetStatus_desc);
  skyroute_msgs_FleetStatus& s = wire.msg();
  s.request_id = wireString(in);
  wireEnum(in, s.state, 6);
  wireEnum(in, s.error_code, 13);
  s.field = wireString(in);
  s.message = wireString(in);
  wireSequence<dds_sequence_skyroute_msgs_FleetVehicleAllocation, skyroute_msgs_FleetVehicleAllocation>(
      in, s.allocation, [](FuzzBytes& b, skyroute_msgs_FleetVehicleAllocation& a) {
        a.vehicle_id = wireString(b);
        wireUint32s(b, a.tasks);
        a.delay_s = b.number();
      });
  s.makespan_steps = in.raw<std::int32_t>();
  s.makespan_s = in.number();
  s.min_separation_m = in.number();
  s.achieved_separation_m = in.number();
  s.separation_repairs = in.raw<std::uint32_t>();
  s.planning_time_s = in.number();
  (void)dds::fromWire(s);
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  FuzzBytes in(data, size);
  switch (in.byte() % 8) {
    case 0: missionRequest(in); break;
    case 1: obstacleUpdate(in); break;
    case 2: cancelRequest(in); break;
    case 3: fleetRequest(in); break;
    case 4: trajectory(in); break;
    case 5: planStatus(in); break;
    case 6: serviceStatus(in); break;
    case 7: fleetStatus(in); break;
  }
  return 0;
}
