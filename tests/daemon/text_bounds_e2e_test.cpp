// Every string a client sends is bounded (service/text_bounds.hpp), end to end over DDS with the
// raw generated types: a 70,000-character vehicle id once crashed the daemon in libddsc (the ROS 2
// mirror made a topic name of it), and an id with a newline forged a line of its log. Each is now
// refused naming its field, echoed safely, and the daemon serves on.
#include <gtest/gtest.h>

#include <string>

#include "service/dds/typed_io.hpp"
#include "tests/daemon/daemon_fixture.hpp"

namespace skyroute {
namespace {

class TextBoundsE2E : public testing::DaemonFixture {
 protected:
  // A mission request written as any DDS program may write it: the generated type, filled from a
  // valid mission, then its vehicle id replaced.
  void writeRawMission(const std::string& request_id, const std::string& vehicle_id) {
    dds::WireSample<skyroute_msgs_MissionRequest> raw(&skyroute_msgs_MissionRequest_desc);
    dds::toWire(simpleMission(request_id, "uav-ok", 0.0), raw.msg());
    dds_string_free(raw.msg().vehicle_id);
    raw.msg().vehicle_id = dds_string_dup(vehicle_id.c_str());
    ASSERT_EQ(dds_write(station_->requests->handle(), &raw.msg()), DDS_RETCODE_OK);
  }
  void expectRefusedNaming(const std::string& request_id, const std::string& field, const std::string& words) {
    ASSERT_TRUE(station_->waitTerminal({request_id}, 20.0)) << daemon_.err();
    const PlanStatusData s = *station_->terminal(request_id);
    EXPECT_EQ(s.state, PlanState::kFailed) << request_id;
    EXPECT_EQ(s.error_code, PlanErrorCode::kInvalidArgument) << request_id << ": " << s.message;
    EXPECT_EQ(s.field, field) << request_id << ": " << s.message;
    EXPECT_NE(s.message.find(words), std::string::npos) << request_id << ": " << s.message;
    EXPECT_LT(s.vehicle_id.size(), 200u) << "the refusal echoes the whole id";
  }
};

TEST_F(TextBoundsE2E, AHugeOrForgingVehicleIdIsRefusedNamingItAndTheDaemonServesOn) {
  startDaemon(21);  // the ROS 2 mirror is on by default: it made a topic of every vehicle id
  writeRawMission("huge-vehicle", std::string(70000, 'a'));
  expectRefusedNaming("huge-vehicle", "vehicle_id", "70000 characters, more than the limit of 64");
  writeRawMission("forging-vehicle", "uav\nevent=forged_line vehicle=x");
  expectRefusedNaming("forging-vehicle", "vehicle_id", "may hold only A-Z a-z 0-9 _ - .");
  writeRawMission("formula-vehicle", "=HYPERLINK(\"x\"),1");
  expectRefusedNaming("formula-vehicle", "vehicle_id", "must start with a letter, a digit or _");
  EXPECT_TRUE(waitForLog("event=bad_request request=huge-vehicle vehicle=aaaa", 10.0)) << daemon_.err();
  EXPECT_EQ(logCount("\nevent=forged_line"), 0u) << "an id forged a log line:\n" << daemon_.err();

  // A request id over its own bound (128), and a planner name with a control character.
  MissionRequestData long_request = simpleMission(std::string(129, 'r'), "uav-r", 0.0);
  ASSERT_TRUE(station_->requests->write(long_request).ok());
  MissionRequestData bad_planner = simpleMission("bad-planner", "uav-p", 0.0);
  bad_planner.planner = "rrt\x1b[2J";
  ASSERT_TRUE(station_->requests->write(bad_planner).ok());
  expectRefusedNaming("bad-planner", "planner", "printable ASCII");
  EXPECT_TRUE(waitForLog("field=request_id message=\"request_id has 129 characters, more than the limit of 128", 10.0))
      << daemon_.err();

  // A zone whose id no topic or log could carry: refused by name, never in force.
  auto zones = dds::Writer<NoFlyZoneData>::create(station_->participant.get());
  ASSERT_TRUE(zones.ok()) << zones.error().describe();
  NoFlyZoneData zone;
  zone.zone_id = std::string(70000, 'z');
  for (const auto& [east_m, north_m] : {std::pair{-4000.0, -4000.0}, {-3000.0, -4000.0}, {-3000.0, -3000.0}})
    zone.ring.push_back(terrain_->frame().toGeo(Eigen::Vector3d(east_m, north_m, 0.0)));
  zone.floor_amsl_m = -1000.0;
  zone.ceiling_amsl_m = 4000.0;
  ASSERT_TRUE(zones->write(zone).ok());
  EXPECT_TRUE(waitForLog("event=bad_nofly_zone field=zone_id message=\"zone_id has 70000 characters", 20.0))
      << daemon_.err();

  // The daemon is still up and plans a valid mission, which the mirror publishes.
  const MissionRequestData valid = simpleMission("after-bad-ids", "uav-after", 0.0);
  ASSERT_TRUE(station_->requests->write(valid).ok());
  ASSERT_TRUE(station_->waitTerminal({valid.request_id}, 120.0)) << daemon_.err();
  EXPECT_EQ(station_->terminal(valid.request_id)->state, PlanState::kSucceeded)
      << station_->terminal(valid.request_id)->message;
  EXPECT_TRUE(daemon_.running()) << daemon_.err();
  EXPECT_EQ(station_->latest(std::string(70000, 'a')), nullptr);
}

}  // namespace
}  // namespace skyroute
