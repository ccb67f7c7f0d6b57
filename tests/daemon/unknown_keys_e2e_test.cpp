// Misspelt keys never reach the daemon (DDS domain 80): `skyroute request --file` refuses a mission
// file with an unknown key before it publishes anything, naming the key and the closest known one
// (before, "point" for "points" was planned begin -> end and answered succeeded); the same file
// spelt right is planned through its point, and so is a mission written as a raw DDS sample, whose
// fields are typed (no keys to misspell). The daemon's TOML configuration names the closest known
// key of an unknown one too.
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <limits>
#include <string>

#include <nlohmann/json.hpp>

#include "service/dds/conversions.hpp"
#include "service/mission_json.hpp"
#include "tests/cli_run.hpp"
#include "tests/daemon/daemon_fixture.hpp"

namespace skyroute {
namespace {

using nlohmann::json;

class UnknownKeysE2E : public testing::DaemonFixture {
 protected:
  // The closest sample of the vehicle's latest trajectory to `point`, horizontally, in metres.
  double closestApproachM(const std::string& vehicle, const Eigen::Vector3d& point) const {
    double closest_m = std::numeric_limits<double>::infinity();
    for (const TrajectoryData& t : station_->trajectory_log) {
      if (t.vehicle_id != vehicle) continue;
      closest_m = std::numeric_limits<double>::infinity();
      for (const TrajectorySampleData& s : t.samples)
        closest_m = std::min(closest_m, (s.position_enu_m - point).head<2>().norm());
    }
    return closest_m;
  }
};

TEST_F(UnknownKeysE2E, ARequestFileWithAMisspeltKeyIsRefusedBeforeAnythingIsSent) {
  startDaemon(80);
  // Ten kilometres west to east through a point 200 m north of the straight line.
  const MissionRequestData spelt = simpleMission("spelt", "uav-k", 0.0);
  const Eigen::Vector3d via = spelt.points.front().enu_m;
  json wrong = missionToJson(spelt);
  wrong["request_id"] = "misspelt";
  wrong["point"] = wrong["points"];
  wrong.erase("points");
  const std::string wrong_file = testing::e2eTempPath("misspelt_mission.json");
  const std::string right_file = testing::e2eTempPath("spelt_mission.json");
  std::ofstream(wrong_file) << wrong.dump();
  std::ofstream(right_file) << missionToJson(spelt).dump();

  const std::string request = std::string(SKYROUTE_CLI) + " request --domain 80 --wait 120 --file ";
  const testing::CliOutput refused = testing::runCommand(request + wrong_file);
  EXPECT_EQ(refused.exit_code, 3) << refused.text;
  EXPECT_NE(refused.text.find("--file " + wrong_file + ": unknown key \"point\" in mission (did you mean \"points\"?)"),
            std::string::npos)
      << refused.text;

  // The daemon was there to hear: the file spelt right is planned, through its point.
  const testing::CliOutput sent = testing::runCommand(request + right_file);
  EXPECT_EQ(sent.exit_code, 0) << sent.text;
  ASSERT_TRUE(station_->waitTerminal({"spelt"}, 120.0)) << daemon_.err();
  EXPECT_EQ(station_->terminal("spelt")->state, PlanState::kSucceeded) << station_->terminal("spelt")->message;
  ASSERT_TRUE(station_->pumpUntil([&] { return closestApproachM("uav-k", via) < 10.0; }, 10.0))
      << closestApproachM("uav-k", via);
  // Nothing of the misspelt one ever reached it.
  for (const PlanStatusData& s : station_->status_log) EXPECT_NE(s.request_id, "misspelt");
  EXPECT_EQ(daemon_.err().find("misspelt"), std::string::npos) << daemon_.err();

  // A raw DDS sample has typed fields: its point is planned through as ever.
  MissionRequestData raw = simpleMission("raw", "uav-r", 3000.0);
  const Eigen::Vector3d raw_via = raw.points.front().enu_m;
  dds::WireSample<skyroute_msgs_MissionRequest> sample(&skyroute_msgs_MissionRequest_desc);
  dds::toWire(raw, sample.msg());
  ASSERT_EQ(dds_write(station_->requests->handle(), &sample.msg()), DDS_RETCODE_OK);
  ASSERT_TRUE(station_->waitTerminal({"raw"}, 120.0)) << daemon_.err();
  EXPECT_EQ(station_->terminal("raw")->state, PlanState::kSucceeded) << station_->terminal("raw")->message;
  ASSERT_TRUE(station_->pumpUntil([&] { return closestApproachM("uav-r", raw_via) < 10.0; }, 10.0))
      << closestApproachM("uav-r", raw_via);
  std::filesystem::remove(wrong_file);
  std::filesystem::remove(right_file);
}

TEST(UnknownKeysConfig, AnUnknownConfigurationKeyOrSectionNamesTheClosestKnownOne) {
  const std::string config = testing::e2eTempPath("unknown_key.toml");
  std::ofstream(config) << "[bounds]\nmax_sped_mps = 30\n";
  const testing::CliOutput key = testing::runCommand(std::string(SKYROUTED) + " --print-config --config " + config);
  EXPECT_EQ(key.exit_code, 3) << key.text;
  EXPECT_NE(key.text.find("bounds.max_sped_mps: unknown key (did you mean max_speed_mps?; skyrouted --print-config "
                          "lists every key)"),
            std::string::npos)
      << key.text;
  std::ofstream(config) << "[bound]\nmax_speed_mps = 30\n";
  const testing::CliOutput section = testing::runCommand(std::string(SKYROUTED) + " --print-config --config " + config);
  EXPECT_EQ(section.exit_code, 3) << section.text;
  EXPECT_NE(section.text.find("unknown section [bound] (did you mean [bounds]?; known: terrain, "), std::string::npos)
      << section.text;
  std::filesystem::remove(config);
}

}  // namespace
}  // namespace skyroute
