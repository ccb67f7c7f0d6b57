// Validation at the DDS boundary and of requests: every rejection names the offending field.
#include <cmath>
#include <limits>

#include <gtest/gtest.h>

#include "service/dds/conversions.hpp"
#include "service/mission_json.hpp"

namespace skyroute {
namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

MissionRequestData validMission() {
  MissionRequestData m;
  m.request_id = "r1";
  m.vehicle_id = "v1";
  m.begin = MissionPointData::wgs84(44.2, -71.3, 1000);
  m.points = {MissionPointData::wgs84(44.21, -71.31, 1100), MissionPointData::enu({10, 20, 1200}),
              MissionPointData::wgs84(44.22, -71.29, 1150)};
  m.end = MissionPointData::wgs84(44.23, -71.28, 1000);
  return m;
}

// Converts to the wire form, lets `corrupt` damage it, converts back.
template <class Corrupt>
Result<MissionRequestData> missionThroughWire(const MissionRequestData& m, Corrupt corrupt) {
  dds::WireSample<skyroute_msgs_MissionRequest> wire(&skyroute_msgs_MissionRequest_desc);
  dds::toWire(m, wire.msg());
  corrupt(wire.msg());
  return dds::fromWire(wire.msg());
}

TEST(DdsConversion, ValidMissionPassesAndKeepsValues) {
  auto r = missionThroughWire(validMission(), [](skyroute_msgs_MissionRequest&) {});
  ASSERT_TRUE(r.ok()) << r.error().describe();
  EXPECT_EQ(r->points.size(), 3u);
  EXPECT_EQ(r->points[1].frame, MissionPointData::Frame::kEnu);
  EXPECT_EQ(r->points[1].enu_m.y(), 20.0);
  EXPECT_FALSE(validateMissionRequest(*r).has_value());
}

TEST(DdsConversion, MissionErrorsNameTheField) {
  struct Case {
    const char* field;
    void (*corrupt)(skyroute_msgs_MissionRequest&);
  };
  const Case cases[] = {
      {"points[1].north_m", [](skyroute_msgs_MissionRequest& w) { w.points._buffer[1].north_m = kNaN; }},
      {"points[2].lon_deg", [](skyroute_msgs_MissionRequest& w) { w.points._buffer[2].lon_deg = kNaN; }},
      {"begin.alt_amsl_m",
       [](skyroute_msgs_MissionRequest& w) { w.begin.alt_amsl_m = std::numeric_limits<double>::infinity(); }},
      {"end.frame", [](skyroute_msgs_MissionRequest& w) { w.end.frame = static_cast<skyroute_msgs_PointFrame>(7); }},
      {"limits.max_speed_mps", [](skyroute_msgs_MissionRequest& w) { w.limits.max_speed_mps = kNaN; }},
      {"request_id", [](skyroute_msgs_MissionRequest& w) { w.request_id[0] = '\0'; }},
      {"vehicle_id", [](skyroute_msgs_MissionRequest& w) { w.vehicle_id[0] = '\0'; }},
  };
  for (const Case& c : cases) {
    auto r = missionThroughWire(validMission(), c.corrupt);
    ASSERT_FALSE(r.ok()) << c.field;
    EXPECT_EQ(r.error().field, c.field);
    EXPECT_EQ(r.error().code, ErrorCode::kInvalidArgument);
    EXPECT_NE(r.error().message.find(c.field), std::string::npos) << r.error().message;
    EXPECT_EQ(toPlanError(r.error()).code, PlanErrorCode::kInvalidArgument);
  }
}

TEST(DdsConversion, TrajectorySampleErrorNamesSampleAndAxis) {
  TrajectoryData t;
  t.vehicle_id = "v";
  t.plan_id = "p";
  t.samples.resize(5);
  dds::WireSample<skyroute_msgs_Trajectory> wire(&skyroute_msgs_Trajectory_desc);
  dds::toWire(t, wire.msg());
  ASSERT_TRUE(dds::fromWire(wire.msg()).ok());
  wire.msg().samples._buffer[3].velocity_enu_mps.z = kNaN;
  auto r = dds::fromWire(wire.msg());
  ASSERT_FALSE(r.ok());
  EXPECT_EQ(r.error().field, "samples[3].velocity_enu_mps.z");
  wire.msg().samples._buffer[3].velocity_enu_mps.z = 0.0;
  wire.msg().samples._buffer[4].lat_deg = kNaN;
  r = dds::fromWire(wire.msg());
  ASSERT_FALSE(r.ok());
  EXPECT_EQ(r.error().field, "samples[4].lat_deg");
}

TEST(DdsConversion, ObstacleErrorsNameTheField) {
  ObstacleUpdateData u;
  u.obstacle.id = 3;
  u.obstacle.shape = ObstacleShape::kBox;
  u.obstacle.size_m = {10, 20, 30};
  u.obstacle.motion = BackAndForth{{0, 0, 0}, {100, 0, 0}, 5.0, 0.0};
  u.valid_from_utc_ns = 1'000'000'000;
  dds::WireSample<skyroute_msgs_ObstacleUpdate> wire(&skyroute_msgs_ObstacleUpdate_desc);
  dds::toWire(u, wire.msg());
  ASSERT_TRUE(dds::fromWire(wire.msg(), 5).ok());

  auto expectField = [&](const char* field) {
    auto r = dds::fromWire(wire.msg(), 5);
    ASSERT_FALSE(r.ok()) << field;
    EXPECT_EQ(r.error().field, field);
  };
  wire.msg().speed_mps = 0.0;
  expectField("speed_mps");
  wire.msg().speed_mps = 5.0;
  wire.msg().size_m.y = -1.0;
  expectField("size_m.y");
  wire.msg().size_m.y = 20.0;
  wire.msg().to_enu_m.x = kNaN;
  expectField("to_enu_m.x");
  wire.msg().to_enu_m.x = 100.0;
  wire.msg().shape = static_cast<skyroute_msgs_ObstacleShapeKind>(9);
  expectField("shape");
  // A removal ignores the geometry altogether.
  wire.msg().remove = true;
  auto removal = dds::fromWire(wire.msg(), 5);
  ASSERT_TRUE(removal.ok());
  EXPECT_TRUE(removal->remove);
  // valid_from 0 means "now".
  wire.msg().valid_from_utc_ns = 0;
  EXPECT_EQ(dds::fromWire(wire.msg(), 12345)->valid_from_utc_ns, 12345);
}

// The holding and reordered states (a hold, a new order, published as a new revision) cross the
// wire as themselves; a state past the last one is refused naming the field.
TEST(DdsConversion, HoldingStatusCrossesTheWireAndUnknownStatesAreRefused) {
  PlanStatusData hold;
  hold.request_id = "r1";
  hold.vehicle_id = "v1";
  hold.state = PlanState::kHolding;
  hold.error_code = PlanErrorCode::kUnreachable;
  hold.stage = PlanStage::kReplan;
  hold.message = "holding: revision 3 keeps the trajectory as far as it is clear, then stops and waits";
  dds::WireSample<skyroute_msgs_PlanStatus> wire(&skyroute_msgs_PlanStatus_desc);
  dds::toWire(hold, wire.msg());
  EXPECT_EQ(wire.msg().state, skyroute_msgs_STATE_HOLDING);
  auto back = dds::fromWire(wire.msg());
  ASSERT_TRUE(back.ok()) << back.error().describe();
  EXPECT_EQ(back->state, PlanState::kHolding);
  EXPECT_EQ(back->message, hold.message);
  EXPECT_EQ(to_string(PlanState::kHolding), "holding");
  EXPECT_FALSE(isTerminal(PlanState::kHolding));
  PlanStatusData reordered = hold;
  reordered.state = PlanState::kReordered;
  reordered.error_code = PlanErrorCode::kNone;
  reordered.message = "reordered: visiting order 0,1,2,3 -> 0,2,1,3";
  dds::WireSample<skyroute_msgs_PlanStatus> reordered_wire(&skyroute_msgs_PlanStatus_desc);
  dds::toWire(reordered, reordered_wire.msg());
  EXPECT_EQ(reordered_wire.msg().state, skyroute_msgs_STATE_REORDERED);
  auto reordered_back = dds::fromWire(reordered_wire.msg());
  ASSERT_TRUE(reordered_back.ok()) << reordered_back.error().describe();
  EXPECT_EQ(reordered_back->state, PlanState::kReordered);
  EXPECT_EQ(to_string(PlanState::kReordered), "reordered");
  EXPECT_FALSE(isTerminal(PlanState::kReordered));
  wire.msg().state = static_cast<skyroute_msgs_PlanState>(skyroute_msgs_STATE_REORDERED + 1);
  auto bad = dds::fromWire(wire.msg());
  ASSERT_FALSE(bad.ok());
  EXPECT_EQ(bad.error().field, "state");
}

TEST(MissionValidation, EachBadRequestGetsItsCodeAndField) {
  struct Case {
    PlanErrorCode code;
    const char* field;
    void (*mutate)(MissionRequestData&);
  };
  const Case cases[] = {
      {PlanErrorCode::kMissionTooLarge, "points", [](MissionRequestData& m) { m.points.resize(65, m.points[0]); }},
      {PlanErrorCode::kInvalidArgument, "points[0].lat_deg", [](MissionRequestData& m) { m.points[0].geo.lat_deg = 95.0; }},
      {PlanErrorCode::kInvalidArgument, "end.lon_deg", [](MissionRequestData& m) { m.end.geo.lon_deg = kNaN; }},
      {PlanErrorCode::kInvalidArgument, "vehicle_id", [](MissionRequestData& m) { m.vehicle_id.clear(); }},
      {PlanErrorCode::kLimitsOutOfRange, "limits.v_ref_mps",
       [](MissionRequestData& m) { m.limits.v_ref_mps = m.limits.max_speed_mps + 1.0; }},
      {PlanErrorCode::kLimitsOutOfRange, "limits.max_accel_mps2", [](MissionRequestData& m) { m.limits.max_accel_mps2 = 0.0; }},
      {PlanErrorCode::kLimitsOutOfRange, "limits.min_clearance_agl_m",
       [](MissionRequestData& m) { m.limits.min_clearance_agl_m = -5.0; }},
  };
  for (const Case& c : cases) {
    MissionRequestData m = validMission();
    c.mutate(m);
    auto problem = validateMissionRequest(m);
    ASSERT_TRUE(problem.has_value()) << c.field;
    EXPECT_EQ(problem->code, c.code) << c.field << ": " << to_string(problem->code);
    EXPECT_EQ(problem->field, c.field);
    EXPECT_NE(problem->message.find(c.field), std::string::npos) << problem->message;
    const PlanStatusData status = PlanStatusData::failed(m, *problem, 0.001);
    EXPECT_EQ(status.state, PlanState::kFailed);
    EXPECT_EQ(status.error_code, c.code);
    EXPECT_EQ(status.field, c.field);
  }
}

TEST(MissionJson, RoundTripAndFieldErrors) {
  const MissionRequestData m = validMission();
  auto back = missionFromJson(missionToJson(m));
  ASSERT_TRUE(back.ok()) << back.error().describe();
  EXPECT_EQ(back->request_id, "r1");
  ASSERT_EQ(back->points.size(), 3u);
  EXPECT_EQ(back->points[1].enu_m, m.points[1].enu_m);
  EXPECT_EQ(back->points[2].geo.lon_deg, m.points[2].geo.lon_deg);

  nlohmann::json j = missionToJson(m);
  j["points"][2]["lat_deg"] = "north";
  auto r = missionFromJson(j);
  ASSERT_FALSE(r.ok());
  EXPECT_EQ(r.error().field, "points[2].lat_deg");

  j = missionToJson(m);
  j["limits"]["ceiling_amsl_m"] = nullptr;
  r = missionFromJson(j);
  ASSERT_FALSE(r.ok());
  EXPECT_EQ(r.error().field, "limits.ceiling_amsl_m");

  j = missionToJson(m);
  j.erase("end");
  r = missionFromJson(j);
  ASSERT_FALSE(r.ok());
  EXPECT_EQ(r.error().field, "end");

  // A DDS string cannot carry a NUL: such an id would reach the daemon cut short.
  j = missionToJson(m);
  j["vehicle_id"] = std::string("uav\0-2", 6);
  r = missionFromJson(j);
  ASSERT_FALSE(r.ok());
  EXPECT_EQ(r.error().field, "vehicle_id");
}

}  // namespace
}  // namespace skyroute
