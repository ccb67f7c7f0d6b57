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

TEST_F(PlanIdentityE2E, PlanWritesTheTrajectoryTheDaemonPublishesSampleForSample) {
  const std::string mission = testing::projectDataPath("missions/demo_mission.json");
  const std::string config = tempPath("config.toml");
  // A non-default seed and sample spacing, so both programs must take them from the same file.
  std::ofstream(config) << "[planning]\nseed = 11\nsample_dt_s = 0.25\n";
  const std::string from_cli = tempPath("plan.csv");
  const std::string from_daemon = tempPath("gcs.csv");
  ASSERT_EQ(run({SKYROUTE_CLI, "plan", "--config", config, "--mission", mission, "--out", from_cli}, "plan"), 0);

  const std::string domain = "131";
  ChildProcess daemon = ChildProcess::spawn({SKYROUTED, "--domain", domain, "--config", config}, "identity_daemon");
  ASSERT_TRUE(daemon.started());
  ChildProcess gcs = ChildProcess::spawn(
      {SKYROUTE_CLI, "gcs", "--domain", domain, "--count", "1", "--timeout", "120", "--csv", from_daemon},
      "identity_gcs");
  const int requested =
      run({SKYROUTE_CLI, "request", "--domain", domain, "--file", mission, "--wait", "120"}, "identity_request");
  EXPECT_EQ(requested, 0) << daemon.err();
  EXPECT_EQ(gcs.wait(120.0), 0) << gcs.err();
  daemon.signal(SIGTERM);
  EXPECT_EQ(daemon.wait(10.0), 0) << daemon.err();

  const std::string a = slurp(from_cli);
  const std::string b = slurp(from_daemon);
  ASSERT_GT(std::count(a.begin(), a.end(), '\n'), 100) << "too few samples from skyroute plan";
  EXPECT_EQ(a.substr(0, a.find('\n')), b.substr(0, b.find('\n'))) << "different columns";
  EXPECT_TRUE(a == b) << "skyroute plan and the daemon's trajectory differ";
  for (const std::string& path : {config, from_cli, from_daemon}) std::filesystem::remove(path);
}

}  // namespace
}  // namespace skyroute
