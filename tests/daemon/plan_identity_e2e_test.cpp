// One pipeline, one configuration: `skyroute plan` and skyrouted print the same configuration and
// accept it back, and for the same DEM, mission, configuration and seed the trajectory the CLI
// writes equals, sample for sample, the one the daemon publishes (as `skyroute gcs` writes it).
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "service/dds/loopback.hpp"
#include "tests/daemon/daemon_process.hpp"
#include "tests/test_data.hpp"
#include "tests/text_file.hpp"

namespace skyroute {
namespace {

using testing::ChildProcess;

std::string tempPath(const std::string& name) {
  return (std::filesystem::temp_directory_path() / ("skyroute_identity_" + std::to_string(::getpid()) + "_" + name))
      .string();
}

std::string slurp(const std::string& path) { return skyroute::testing::readTextFile(path); }

// Runs a program to its end (at most timeout_s) and returns its exit code; stdout in *out.
int run(const std::vector<std::string>& argv, const std::string& name, std::string* out = nullptr,
        double timeout_s = 120.0) {
  ChildProcess child = ChildProcess::spawn(argv, name);
  const int code = child.wait(timeout_s);
  if (out) *out = child.out();
  if (code != 0) std::cerr << name << " stderr:\n" << child.err() << std::endl;
  return code;
}

class PlanIdentityE2E : public ::testing::Test {
 protected:
  static void SetUpTestSuite() { dds::useLoopbackOnly(); }  // inherited by every child process
};

TEST_F(PlanIdentityE2E, PrintConfigIsTheSameTextInBothProgramsAndParsesBack) {
  std::string from_cli, from_daemon;
  ASSERT_EQ(run({SKYROUTE_CLI, "plan", "--print-config"}, "cli_print", &from_cli), 0);
  ASSERT_EQ(run({SKYROUTED, "--print-config"}, "daemon_print", &from_daemon), 0);
  ASSERT_FALSE(from_cli.empty());
  EXPECT_EQ(from_cli, from_daemon);
  EXPECT_NE(from_cli.find("[planning]"), std::string::npos);
  EXPECT_NE(from_cli.find("leg_time_cap_s"), std::string::npos);

  // Both take the printed text back unchanged, and print it again identically.
  const std::string path = tempPath("printed.toml");
  std::ofstream(path) << from_cli;
  std::string again_cli, again_daemon;
  ASSERT_EQ(run({SKYROUTE_CLI, "plan", "--config", path, "--print-config"}, "cli_again", &again_cli), 0);
  ASSERT_EQ(run({SKYROUTED, "--config", path, "--print-config"}, "daemon_again", &again_daemon), 0);
  EXPECT_EQ(again_cli, from_cli);
  EXPECT_EQ(again_daemon, from_cli);
  std::filesystem::remove(path);
}

TEST_F(PlanIdentityE2E, CommandLineOverridesNameTheirKeyAndShowInThePrintedConfig) {
  std::string printed, help;
  ASSERT_EQ(run({SKYROUTE_CLI, "plan", "--seed", "7", "--budget-s", "2.5", "--print-config"}, "override", &printed), 0);
  EXPECT_NE(printed.find("seed = 7\n"), std::string::npos) << printed;
  EXPECT_NE(printed.find("leg_time_cap_s = 2.5\n"), std::string::npos) << printed;
  ASSERT_EQ(run({SKYROUTE_CLI, "plan", "--help"}, "help", &help), 0);
  for (const char* key : {"planning.seed", "planning.leg_max_iterations", "planning.leg_time_cap_s",
                          "planning.sample_dt_s", "planning.default_planner", "terrain.dem"}) {
    EXPECT_NE(help.find(key), std::string::npos) << "--help does not name " << key;
  }
}

// `skyroute plan --config` and the daemon with the same configuration, the demo mission requested
// over DDS and its trajectory taken by `skyroute gcs`: the two CSV files, as text.
std::pair<std::string, std::string> planAndPublish(const std::string& config_text, const std::string& domain,
                                                   const std::string& tag) {
  const std::string mission = testing::projectDataPath("missions/demo_mission.json");
  const std::string config = tempPath(tag + "_config.toml");
  std::ofstream(config) << config_text;
  const std::string from_cli = tempPath(tag + "_plan.csv");
  const std::string from_daemon = tempPath(tag + "_gcs.csv");
  EXPECT_EQ(run({SKYROUTE_CLI, "plan", "--config", config, "--mission", mission, "--out", from_cli}, tag + "_plan"), 0);

  ChildProcess daemon = ChildProcess::spawn({SKYROUTED, "--domain", domain, "--config", config}, tag + "_daemon");
  EXPECT_TRUE(daemon.started());
  ChildProcess gcs = ChildProcess::spawn(
      {SKYROUTE_CLI, "gcs", "--domain", domain, "--count", "1", "--timeout", "120", "--csv", from_daemon}, tag + "_gcs");
  const int requested =
      run({SKYROUTE_CLI, "request", "--domain", domain, "--file", mission, "--wait", "120"}, tag + "_request");
  EXPECT_EQ(requested, 0) << daemon.err();
  EXPECT_EQ(gcs.wait(120.0), 0) << gcs.err();
  daemon.signal(SIGTERM);
  EXPECT_EQ(daemon.wait(10.0), 0) << daemon.err();
  std::pair<std::string, std::string> both{slurp(from_cli), slurp(from_daemon)};
  for (const std::string& path : {config, from_cli, from_daemon}) std::filesystem::remove(path);
  return both;
}

void expectSameSamples(const std::string& a, const std::string& b) {
  ASSERT_GT(std::count(a.begin(), a.end(), '\n'), 100) << "too few samples from skyroute plan";
  EXPECT_EQ(a.substr(0, a.find('\n')), b.substr(0, b.find('\n'))) << "different columns";
  EXPECT_TRUE(a == b) << "skyroute plan and the daemon's trajectory differ";
}

TEST_F(PlanIdentityE2E, PlanWritesTheTrajectoryTheDaemonPublishesSampleForSample) {
  // A non-default seed and sample spacing, so both programs must take them from the same file.
  const auto [a, b] = planAndPublish("[planning]\nseed = 11\nsample_dt_s = 0.25\n", "131", "identity");
  expectSameSamples(a, b);
}

// The same with a no-fly zone across the mission's first leg, from the configuration's
// terrain.nofly: both programs fly round it the same way, and not the way they fly without it.
TEST_F(PlanIdentityE2E, NoFlyZoneFromTheConfigurationShapesBothTrajectoriesAlike) {
  const std::string zones = tempPath("zones.geojson");
  std::ofstream(zones) << R"({"type": "FeatureCollection", "features": [{"type": "Feature", "id": "range",
    "properties": {"floor_m": 0, "ceiling_m": 9000}, "geometry": {"type": "Polygon", "coordinates":
    [[[15.064, 46.934], [15.078, 46.934], [15.078, 46.946], [15.064, 46.946], [15.064, 46.934]]]}}]})";
  const std::string planning = "[planning]\nseed = 11\nsample_dt_s = 0.25\n";
  const auto [a, b] = planAndPublish("[terrain]\nnofly = \"" + zones + "\"\n" + planning, "132", "zoned");
  expectSameSamples(a, b);
  const auto [free_a, free_b] = planAndPublish(planning, "132", "free");
  EXPECT_NE(a, free_a) << "the zone changed nothing";
  std::filesystem::remove(zones);
}

// Seed 003's timing (equation 3: each segment's length over V_ref) chosen in the configuration:
// both programs fly it alike, and not as they fly the default trapezoidal profile.
TEST_F(PlanIdentityE2E, SeedThreeTimingFromTheConfigurationGivesBothTheSameTrajectory) {
  const std::string planning = "[planning]\nseed = 11\nsample_dt_s = 0.25\n";
  const auto [a, b] = planAndPublish(planning + "time_allocation = \"constant_speed\"\n", "135", "eq3");
  expectSameSamples(a, b);
  const auto [trapezoidal_a, trapezoidal_b] = planAndPublish(planning, "135", "trapezoidal");
  EXPECT_NE(a, trapezoidal_a) << "the timing changed nothing";
}

}  // namespace
}  // namespace skyroute
