// A fixed wing end to end over DDS (domains 190-192): skyrouted plans a fixed-wing MissionRequest
// into a trajectory that an independent sampler of the published samples accepts (minimum
// airspeed, bank angle, path angles, clearance), starting and ending at cruise speed; a bad
// fixed-wing value and an unknown model on the wire are refused naming the field; the daemon's
// [vehicle] section makes a request that leaves the model to it a fixed wing. A fixed wing whose
// way is blocked (domain 192) holds by loitering: the revision the ground station gets never
// drops below the minimum airspeed.
#include <gtest/gtest.h>

#include "service/dds/conversions.hpp"
#include "service/mission_types.hpp"
#include "tests/daemon/daemon_fixture.hpp"
#include "tests/fixed_wing_sampler.hpp"

namespace skyroute {
namespace {

class FixedWingE2E : public testing::DaemonFixture {
 protected:
  // Corner to corner through two turning points, 200-250 m up.
  MissionRequestData fixedWingMission(const std::string& id) const {
    MissionRequestData m;
    m.request_id = id;
    m.vehicle_id = "fw-" + id;
    m.begin = above(-4500, -4500, 200);
    m.points = {above(-1500, 1500, 250), above(1500, -1500, 250)};
    m.end = above(4500, 4500, 200);
    m.fixed_order = true;
    m.limits = testing::fixedWingTestLimits();
    return m;
  }

  // The published trajectory of an accepted mission (the test fails when there is none).
  std::optional<TrajectoryData> planned(const MissionRequestData& m) {
    EXPECT_TRUE(station_->requests->write(m).ok());
    if (!station_->waitTerminal({m.request_id}, 60.0)) return std::nullopt;
    const auto status = *station_->terminal(m.request_id);
    EXPECT_EQ(status.state, PlanState::kSucceeded) << status.field << ": " << status.message;
    if (status.state != PlanState::kSucceeded) return std::nullopt;
    if (!station_->pumpUntil([&] { return station_->latest(m.vehicle_id) != nullptr; }, 10.0)) return std::nullopt;
    return *station_->latest(m.vehicle_id);
  }

  double ground(double e, double n) const { return terrain_->heightAt(e, n); }
};

TEST_F(FixedWingE2E, AFixedWingMissionFliesWithinItsLimitsAndBadValuesAreNamed) {
  startDaemon(190);
  const MissionRequestData m = fixedWingMission("fw1");
  const auto t = planned(m);
  ASSERT_TRUE(t) << daemon_.err();
  ASSERT_GT(t->samples.size(), 100u);
  const testing::FixedWingFlight f =
      testing::sampleFixedWing(*t, testing::envelopeOf(m.limits), [&](double e, double n) { return ground(e, n); });
  EXPECT_TRUE(f.violations.empty()) << testing::joined(f.violations);
  EXPECT_GT(f.checked, t->samples.size() / 2);
  EXPECT_NEAR(t->samples.front().velocity_enu_mps.norm(), m.limits.v_ref_mps, 1e-6);
  EXPECT_NEAR(t->samples.back().velocity_enu_mps.norm(), m.limits.v_ref_mps, 1e-6);

  // Refused over the wire, naming the field: a bank out of range, and a model no enumerator has.
  MissionRequestData steep = fixedWingMission("fw-bank");
  steep.limits.max_bank_deg = 85.0;
  ASSERT_TRUE(station_->requests->write(steep).ok());
  MissionRequestData unknown = fixedWingMission("fw-model");
  dds::WireSample<skyroute_msgs_MissionRequest> raw(&skyroute_msgs_MissionRequest_desc);
  dds::toWire(unknown, raw.msg());
  raw.msg().limits.model = 7;
  ASSERT_EQ(dds_write(station_->requests->handle(), &raw.msg()), DDS_RETCODE_OK);
  ASSERT_TRUE(station_->waitTerminal({"fw-bank", "fw-model"}, 20.0)) << daemon_.err();
  EXPECT_EQ(station_->terminal("fw-bank")->error_code, PlanErrorCode::kLimitsOutOfRange);
  EXPECT_EQ(station_->terminal("fw-bank")->field, "limits.max_bank_deg");
  EXPECT_EQ(station_->terminal("fw-model")->error_code, PlanErrorCode::kInvalidArgument);
  EXPECT_EQ(station_->terminal("fw-model")->field, "limits.model");
}

TEST_F(FixedWingE2E, TheDaemonsVehicleSectionMakesADefaultRequestAFixedWing) {
  startDaemonWithConfig(191, "[vehicle]\nmodel = \"fixed_wing\"\nstall_speed_mps = 15.0\nmax_bank_deg = 35.0\n");
  MissionRequestData m = fixedWingMission("fw2");
  m.limits.model.reset();
  m.limits.stall_speed_mps = 0.0;
  m.limits.max_bank_deg = 0.0;
  const auto t = planned(m);
  ASSERT_TRUE(t) << daemon_.err();
  ASSERT_FALSE(t->samples.empty());
  EXPECT_NEAR(t->samples.front().velocity_enu_mps.norm(), m.limits.v_ref_mps, 1e-6);
  VehicleLimitsData configured = m.limits;
  configured.stall_speed_mps = 15.0;
  configured.max_bank_deg = 35.0;
  const testing::FixedWingFlight f =
      testing::sampleFixedWing(*t, testing::envelopeOf(configured), [&](double e, double n) { return ground(e, n); });
  EXPECT_TRUE(f.violations.empty()) << testing::joined(f.violations);
}

// The goal closed by an obstacle half a minute ahead: no plan can help, so the daemon answers with
// a hold, and for a fixed wing the hold is a loiter, checked here from the published samples
// alone: never under the minimum airspeed, within the bank and path angles, above the clearance,
// clear of the obstacle, and circling (it never comes to rest).
TEST_F(FixedWingE2E, ABlockedWayIsAnsweredByALoiterThatNeverDropsBelowTheMinimumAirspeed) {
  startDaemon(192);
  MissionRequestData m = fixedWingMission("fw-loiter");
  m.begin = above(-700, 0, 250);
  m.points.clear();
  m.end = above(700, 0, 250);  // 1.4 km: about a minute at cruise speed
  const auto first = planned(m);
  ASSERT_TRUE(first) << daemon_.err();
  ObstacleUpdateData over_goal;
  over_goal.obstacle.id = 31;
  over_goal.obstacle.shape = ObstacleShape::kSphere;
  over_goal.obstacle.size_m = Eigen::Vector3d(400.0, 0.0, 0.0);
  over_goal.obstacle.center_m = m.end.enu_m;
  over_goal.valid_from_utc_ns = utcNowNs();
  ASSERT_TRUE(station_->obstacles->write(over_goal).ok());
  auto holding = [&] {
    for (const PlanStatusData& s : station_->status_log)
      if (s.request_id == m.request_id && s.state == PlanState::kHolding) return true;
    return false;
  };
  ASSERT_TRUE(station_->pumpUntil([&] { return holding() && station_->latest(m.vehicle_id)->revision > first->revision; },
                                  30.0))
      << daemon_.err();
  const TrajectoryData hold = *station_->latest(m.vehicle_id);
  for (const PlanStatusData& s : station_->status_log) {
    if (s.request_id == m.request_id && s.state == PlanState::kHolding) {
      EXPECT_NE(s.message.find("loiters"), std::string::npos) << s.message;
    }
  }
  ASSERT_GT(hold.samples.size(), 100u);
  const testing::FixedWingFlight f =
      testing::sampleFixedWing(hold, testing::envelopeOf(m.limits), [&](double e, double n) { return ground(e, n); });
  EXPECT_TRUE(f.violations.empty()) << testing::joined(f.violations);
  EXPECT_GT(f.checked, hold.samples.size() / 2);
  EXPECT_GE(f.min_speed_mps, m.limits.stall_speed_mps * m.limits.stall_margin);
  EXPECT_GT(f.max_bank_deg, 15.0);  // it circles
  EXPECT_GE(hold.samples.back().velocity_enu_mps.norm(), m.limits.stall_speed_mps * m.limits.stall_margin);
  for (const TrajectorySampleData& s : hold.samples)
    ASSERT_GT((s.position_enu_m - over_goal.obstacle.center_m).norm(), 400.0) << s.t_rel_s;
}

}  // namespace
}  // namespace skyroute
