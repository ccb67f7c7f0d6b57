// A fixed-wing mission through the engine on the embedded terrain: planned, and its published
// samples, checked by an independent sampler (tests/fixed_wing_sampler.hpp), keep the minimum
// airspeed, the largest bank, the path angles and the clearance; it starts and ends at cruise
// speed and passes its points. The same points for a multirotor still hover at both ends. Bad
// fixed-wing values are refused naming the field, the configuration's [vehicle] section fills in
// what a request leaves to the service, and the mission JSON carries the model.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <string>

#include "service/daemon_config.hpp"
#include "service/engine.hpp"
#include "service/mission_json.hpp"
#include "tests/fixed_wing_sampler.hpp"
#include "tests/service/default_world_fixture.hpp"
#include "tests/service/recording_sink.hpp"

namespace skyroute {
namespace {

using testing::RecordingSink;

constexpr std::int64_t kStartNs = 1'800'000'000'000'000'000LL;

VehicleLimitsData fixedWingLimits() { return testing::fixedWingTestLimits(); }

class FixedWingMissionTest : public testing::DefaultWorldTest {
 protected:
  // Corner to corner with two turning points of about 90 degrees and more, 200-250 m up.
  MissionRequestData mission(const std::string& id) const {
    MissionRequestData r;
    r.request_id = id;
    r.vehicle_id = "uav-" + id;
    r.begin = enu(-4500, -4500, 200);
    r.points = {enu(-1500, 1500, 250), enu(1500, -1500, 250)};
    r.end = enu(4500, 4500, 200);
    r.fixed_order = true;
    r.limits = fixedWingLimits();
    return r;
  }

  // Plans r through a fresh engine; the last status and (when it succeeded) the trajectory.
  std::pair<PlanStatusData, TrajectoryData> plan(const MissionRequestData& r, EngineOptions options = {}) {
    options.pipeline.sample_dt_s = 0.05;
    RecordingSink sink;
    auto engine = Engine::create(world_, options, sink, [] { return kStartNs; });
    EXPECT_TRUE(engine.ok());
    if (!engine.ok()) return {};
    if (auto refused = (*engine)->submit(r)) {
      PlanStatusData status;
      status.state = PlanState::kFailed;
      status.field = refused->field;
      status.message = refused->message;
      return {status, {}};
    }
    EXPECT_TRUE((*engine)->planNext());
    EXPECT_FALSE(sink.statuses.empty());
    if (sink.statuses.empty()) return {};
    return {sink.statuses.back(), sink.trajectories.empty() ? TrajectoryData{} : sink.trajectories.back()};
  }

  double ground(double e, double n) const { return heightfield_->heightAt(e, n); }
};

TEST_F(FixedWingMissionTest, FliesWithinItsLimitsByAnIndependentSampler) {
  const MissionRequestData r = mission("fw");
  const auto [status, t] = plan(r);
  ASSERT_EQ(status.state, PlanState::kSucceeded) << status.field << ": " << status.message;
  ASSERT_GT(t.samples.size(), 100u);
  const testing::FixedWingFlight f =
      testing::sampleFixedWing(t, testing::envelopeOf(r.limits), [&](double e, double n) { return ground(e, n); });
  EXPECT_GE(f.checked, t.samples.size() - 3);  // the last sample may be closer
  EXPECT_TRUE(f.violations.empty()) << testing::joined(f.violations);
  EXPECT_GE(f.min_speed_mps, 19.5 * 0.99);
  std::printf("fixed wing: speed %.2f..%.2f m/s, bank <= %.2f deg, climb <= %.2f deg, descent <= %.2f deg, "
              "clearance >= %.1f m\n",
              f.min_speed_mps, f.max_speed_mps, f.max_bank_deg, f.max_climb_angle_deg, f.max_descent_angle_deg,
              f.min_clearance_m);
  EXPECT_GT(f.max_bank_deg, 5.0);  // it does turn
  // Cruise speed at both ends, and through every point (no stop anywhere).
  EXPECT_NEAR(t.samples.front().velocity_enu_mps.norm(), r.limits.v_ref_mps, 1e-6);
  EXPECT_NEAR(t.samples.back().velocity_enu_mps.norm(), r.limits.v_ref_mps, 1e-6);
  EXPECT_EQ(status.message.find("stops there"), std::string::npos) << status.message;
  for (const MissionPointData& point : r.points) {
    double nearest = std::numeric_limits<double>::infinity();
    for (const TrajectorySampleData& s : t.samples) nearest = std::min(nearest, (s.position_enu_m - point.enu_m).norm());
    EXPECT_LT(nearest, 35.0 * 0.05);
  }
}

TEST_F(FixedWingMissionTest, AMultirotorOnTheSamePointsStillHovers) {
  MissionRequestData r = mission("mr");
  r.limits = VehicleLimitsData{};
  const auto [status, t] = plan(r);
  ASSERT_EQ(status.state, PlanState::kSucceeded) << status.field << ": " << status.message;
  ASSERT_FALSE(t.samples.empty());
  EXPECT_NEAR(t.samples.front().velocity_enu_mps.norm(), 0.0, 1e-6);
  EXPECT_NEAR(t.samples.back().velocity_enu_mps.norm(), 0.0, 1e-6);
  // The sampler is no formality: the hovering trajectory breaks the fixed wing's envelope.
  const testing::FixedWingFlight f = testing::sampleFixedWing(t, testing::envelopeOf(fixedWingLimits()),
                                                              [&](double e, double n) { return ground(e, n); });
  ASSERT_FALSE(f.violations.empty());
  EXPECT_EQ(f.violations.front().rfind("below_min_airspeed", 0), 0u) << testing::joined(f.violations);
}

TEST_F(FixedWingMissionTest, BadFixedWingValuesAreRefusedByName) {
  const std::pair<const char*, void (*)(VehicleLimitsData&)> cases[] = {
      {"limits.stall_speed_mps", [](VehicleLimitsData& l) { l.stall_speed_mps = 0.0; }},  // none configured
      {"limits.stall_speed_mps", [](VehicleLimitsData& l) { l.stall_speed_mps = -3.0; }},
      {"limits.stall_margin", [](VehicleLimitsData& l) { l.stall_margin = 0.5; }},
      {"limits.max_bank_deg", [](VehicleLimitsData& l) { l.max_bank_deg = 85.0; }},
      {"limits.max_climb_angle_deg", [](VehicleLimitsData& l) { l.max_climb_angle_deg = 70.0; }},
      {"limits.v_ref_mps", [](VehicleLimitsData& l) { l.v_ref_mps = 18.0; }},  // under 15 x 1.3
  };
  for (const auto& [field, spoil] : cases) {
    MissionRequestData r = mission("bad");
    spoil(r.limits);
    const auto [status, t] = plan(r);
    EXPECT_EQ(status.state, PlanState::kFailed) << field;
    EXPECT_EQ(status.field, field) << status.message;
    EXPECT_TRUE(t.samples.empty()) << field;
  }
}

TEST_F(FixedWingMissionTest, TheConfigurationsVehicleSectionFillsInWhatARequestLeaves) {
  auto config = parseDaemonConfig(
      "[vehicle]\nmodel = \"fixed_wing\"\nstall_speed_mps = 15.0\nmax_bank_deg = 35.0\n", "test.toml");
  ASSERT_TRUE(config.ok()) << config.error().describe();
  const VehicleModelDefaults& v = config->engine.pipeline.vehicle;
  EXPECT_EQ(v.model, VehicleModel::kFixedWing);
  EXPECT_EQ(v.stall_speed_mps, 15.0);
  EXPECT_NE(describeDaemonConfig(*config).find("[vehicle]\n"), std::string::npos);
  MissionRequestData r = mission("configured");
  r.limits.model.reset();
  r.limits.stall_speed_mps = 0.0;
  r.limits.max_bank_deg = 0.0;
  const auto [status, t] = plan(r, config->engine);
  ASSERT_EQ(status.state, PlanState::kSucceeded) << status.field << ": " << status.message;
  ASSERT_FALSE(t.samples.empty());
  EXPECT_NEAR(t.samples.front().velocity_enu_mps.norm(), r.limits.v_ref_mps, 1e-6);  // never hovers

  auto bad = parseDaemonConfig("[vehicle]\nmodel = \"glider\"\n", "test.toml");
  ASSERT_FALSE(bad.ok());
  EXPECT_EQ(bad.error().field, "vehicle.model");
  bad = parseDaemonConfig("[vehicle]\nmax_bank_deg = 85.0\n", "test.toml");
  ASSERT_FALSE(bad.ok());
  EXPECT_EQ(bad.error().field, "vehicle.max_bank_deg");
}

// The grid planners lift their paths to the flight band over the legs' ends, far steeper than a
// fixed wing climbs: such a mission is refused naming the planner option (and the way out), not
// handed to a trajectory stage that cannot fly it. A multirotor flies the same request
// (engine_test's HabPpPlannersGoThroughTheSameTrajectoryStage).
TEST_F(FixedWingMissionTest, AGridPlannersPathSteeperThanTheFixedWingClimbsIsRefusedNamingThePlanner) {
  for (const std::string planner : {"hab-pp", "hab-pp-rrt"}) {
    SCOPED_TRACE(planner);
    MissionRequestData r = mission("grid-" + planner);
    r.planner = planner;
    r.begin = enu(-5000, -2000, 60);
    r.points = {enu(0, -5500, 150)};
    r.end = enu(5000, 2000, 60);
    const auto [status, t] = plan(r);
    ASSERT_EQ(status.state, PlanState::kFailed) << status.field << ": " << status.message;
    EXPECT_EQ(status.field, "planner") << status.message;
    EXPECT_NE(status.message.find(planner + "'s path of legs["), std::string::npos) << status.message;
    EXPECT_NE(status.message.find("steeper than the fixed wing's 13.5 deg path angle"), std::string::npos)
        << status.message;
    EXPECT_NE(status.message.find("rrtstar-lospo"), std::string::npos) << status.message;
    EXPECT_TRUE(t.samples.empty());
  }
}

TEST_F(FixedWingMissionTest, TheMissionJsonCarriesTheModel) {
  const MissionRequestData r = mission("json");
  auto back = missionFromJson(missionToJson(r));
  ASSERT_TRUE(back.ok());
  EXPECT_EQ(back->limits.model, VehicleModel::kFixedWing);
  EXPECT_EQ(back->limits.stall_speed_mps, 15.0);
  EXPECT_EQ(back->limits.max_bank_deg, 35.0);
  EXPECT_EQ(back->limits.max_descent_angle_deg, 15.0);
  auto absent = missionFromJson(nlohmann::json::parse(
      R"({"begin": {"east_m": 0, "north_m": 0, "up_m": 500}, "end": {"east_m": 900, "north_m": 0, "up_m": 500}})"));
  ASSERT_TRUE(absent.ok());
  EXPECT_FALSE(absent->limits.model);  // the service's
  auto wrong = missionFromJson(nlohmann::json::parse(
      R"({"begin": {"east_m": 0, "north_m": 0, "up_m": 500}, "end": {"east_m": 900, "north_m": 0, "up_m": 500},
          "limits": {"model": "glider"}})"));
  ASSERT_FALSE(wrong.ok());
  EXPECT_EQ(wrong.error().field, "limits.model");
}

}  // namespace
}  // namespace skyroute
