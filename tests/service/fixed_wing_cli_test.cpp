// `skyroute plan --mission` with a fixed-wing mission file, run as a user would on the embedded
// terrain: the written trajectory (its ENU samples) passes the independent fixed-wing sampler and
// starts and ends at cruise speed; a file with an unknown model is refused naming limits.model.
#include <filesystem>
#include <fstream>
#include <string>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "service/mission_json.hpp"
#include "terrain/heightfield.hpp"
#include "tests/cli_run.hpp"
#include "tests/fixed_wing_sampler.hpp"
#include "tests/terrain_data.hpp"
#include "tests/test_data.hpp"
#include "tests/test_folder.hpp"
#include "tests/text_file.hpp"

namespace skyroute {
namespace {

class FixedWingCli : public testing::TestFolderTest {
 protected:
  FixedWingCli() : TestFolderTest("skyroute_fixed_wing_cli_test_") {}

  static void SetUpTestSuite() { terrain_ = testing::defaultTerrainHeightfield(); }

  MissionPointData above(double e, double n, double agl_m) const {
    return MissionPointData::enu(Eigen::Vector3d(e, n, terrain_->heightAt(e, n) + agl_m));
  }

  static inline std::shared_ptr<const Heightfield> terrain_;
};

TEST_F(FixedWingCli, PlanWritesAFixedWingTrajectoryWithinItsLimits) {
  ASSERT_TRUE(terrain_);
  MissionRequestData m;
  m.vehicle_id = "fw-cli";
  m.begin = above(-4500, -4500, 200);
  m.points = {above(-1500, 1500, 250), above(1500, -1500, 250)};
  m.end = above(4500, 4500, 200);
  m.fixed_order = true;
  nlohmann::json j = missionToJson(m);
  j["limits"]["model"] = "fixed_wing";
  j["limits"]["v_ref_mps"] = 25.0;
  j["limits"]["max_speed_mps"] = 35.0;
  j["limits"]["max_accel_mps2"] = 10.0;
  j["limits"]["max_climb_rate_mps"] = 8.0;
  j["limits"]["max_descent_rate_mps"] = 8.0;
  j["limits"]["stall_speed_mps"] = 15.0;
  j["limits"]["stall_margin"] = 1.3;
  j["limits"]["max_bank_deg"] = 35.0;
  j["limits"]["max_climb_angle_deg"] = 15.0;
  j["limits"]["max_descent_angle_deg"] = 15.0;
  const std::string mission = (dir_ / "fixed_wing.json").string();
  std::ofstream(mission) << j.dump(1);
  const std::string out = (dir_ / "trajectory.json").string();
  const auto r = testing::runCli("plan --dem " + testing::projectDataPath("default_terrain.tif") + " --mission " +
                                 mission + " --dt 0.05 --out " + out);
  ASSERT_EQ(r.exit_code, 0) << r.text;
  const nlohmann::json written = nlohmann::json::parse(testing::readTextFile(out));
  TrajectoryData t;
  for (const auto& s : written.at("samples")) {
    TrajectorySampleData sample;
    sample.t_rel_s = s.at("time_s").get<double>();
    const auto& p = s.at("enu_m");
    sample.position_enu_m = {p[0].get<double>(), p[1].get<double>(), p[2].get<double>()};
    const auto& v = s.at("velocity_mps");
    sample.velocity_enu_mps = {v[0].get<double>(), v[1].get<double>(), v[2].get<double>()};
    t.samples.push_back(sample);
  }
  ASSERT_GT(t.samples.size(), 100u);
  auto parsed = missionFromJson(j);
  ASSERT_TRUE(parsed.ok());
  const testing::FixedWingFlight f = testing::sampleFixedWing(
      t, testing::envelopeOf(parsed->limits), [&](double e, double n) { return terrain_->heightAt(e, n); });
  EXPECT_TRUE(f.violations.empty()) << testing::joined(f.violations);
  EXPECT_NEAR(t.samples.front().velocity_enu_mps.norm(), 25.0, 1e-6);
  EXPECT_NEAR(t.samples.back().velocity_enu_mps.norm(), 25.0, 1e-6);

  j["limits"]["model"] = "glider";
  std::ofstream(mission) << j.dump(1);
  const auto refused = testing::runCli("plan --dem " + testing::projectDataPath("default_terrain.tif") + " --mission " +
                                       mission + " --out " + out);
  EXPECT_NE(refused.exit_code, 0);
  EXPECT_NE(refused.text.find("limits.model"), std::string::npos) << refused.text;
}

}  // namespace
}  // namespace skyroute
