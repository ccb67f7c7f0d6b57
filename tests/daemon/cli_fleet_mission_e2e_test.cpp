// `skyroute mission` and `skyroute fleet` against a real skyrouted (separate processes, DDS on
// loopback): the order `mission` prints is the visiting order of the daemon's trajectory for the
// same mission; `fleet --file` writes, vehicle for vehicle, the trajectories the daemon publishes
// for the same fleet request (as `skyroute gcs --csv` writes them); `fleet --domain` sends that
// request and exits with the table's code for a success, a failed plan and no service.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "service/dds/loopback.hpp"
#include "tests/daemon/daemon_process.hpp"
#include "tests/test_data.hpp"

namespace skyroute {
namespace {

using testing::ChildProcess;
using testing::readTextFile;

std::string tempPath(const std::string& name) { return testing::tempPath("cli_e2e", name); }

using testing::Ran;

Ran run(const std::vector<std::string>& argv, const std::string& name, double timeout_s = 180.0) {
  return testing::runToEnd(argv, name, timeout_s);
}

// A CSV's rows grouped by their first column (the vehicle), header left out.
std::map<std::string, std::string> rowsByVehicle(const std::string& csv) {
  std::map<std::string, std::string> rows;
  std::istringstream in(csv);
  std::string line;
  std::getline(in, line);
  while (std::getline(in, line)) rows[line.substr(0, line.find(','))] += line + "\n";
  return rows;
}

class CliDaemonE2E : public ::testing::Test {
 protected:
  static void SetUpTestSuite() { dds::useLoopbackOnly(); }  // inherited by every child process

  // skyrouted on `domain`; the tools wait until they match it, so no readiness check is needed.
  static ChildProcess daemon(const std::string& domain, const std::string& config = "") {
    std::vector<std::string> argv{SKYROUTED, "--domain", domain};
    if (!config.empty()) argv.insert(argv.end(), {"--config", config});
    ChildProcess d = ChildProcess::spawn(argv, "daemon_" + domain);
    EXPECT_TRUE(d.started());
    return d;
  }
  static void stop(ChildProcess& d) {
    d.signal(SIGTERM);
    EXPECT_EQ(d.wait(20.0), 0) << d.err();
  }
};

TEST_F(CliDaemonE2E, MissionOrderIsTheDaemonsVisitingOrder) {
  const std::string mission = tempPath("mission.json");
  std::ofstream(mission) << R"({"vehicle_id": "uav-order", "request_id": "order-1",
    "begin": {"lat_deg": 46.90, "lon_deg": 15.03, "alt_amsl_m": 1100},
    "points": [{"lat_deg": 46.95, "lon_deg": 15.06, "alt_amsl_m": 1150},
               {"lat_deg": 46.92, "lon_deg": 15.10, "alt_amsl_m": 1100},
               {"lat_deg": 46.96, "lon_deg": 15.04, "alt_amsl_m": 1200}],
    "end": {"lat_deg": 46.97, "lon_deg": 15.12, "alt_amsl_m": 1100}})";
  const Ran ordered = run({SKYROUTE_CLI, "mission", "--mission", mission, "--json"}, "mission");
  ASSERT_EQ(ordered.code, 0) << ordered.err;
  const nlohmann::json j = nlohmann::json::parse(ordered.out);
  std::string order;
  for (const auto& k : j["order"]) order += (order.empty() ? "" : ",") + std::to_string(k.get<int>());

  // A smaller leg budget keeps the daemon quick; the order stage does not depend on it.
  const std::string config = tempPath("quick.toml");
  std::ofstream(config) << "[planning]\nleg_max_iterations = 400\n";
  ChildProcess d = daemon("210", config);
  ChildProcess gcs = ChildProcess::spawn(
      {SKYROUTE_CLI, "gcs", "--domain", "210", "--vehicle", "uav-order", "--count", "1", "--timeout", "180"}, "order_gcs");
  const Ran requested = run({SKYROUTE_CLI, "request", "--domain", "210", "--file", mission, "--wait", "180"}, "order_request");
  EXPECT_EQ(requested.code, 0) << requested.out << requested.err << d.err();
  ASSERT_EQ(gcs.wait(180.0), 0) << gcs.err();
  const std::string published = gcs.out();
  const auto at = published.find(" order=");
  ASSERT_NE(at, std::string::npos) << published;
  EXPECT_EQ(published.substr(at + 7, published.find_first_of(" \n", at + 7) - at - 7), order) << published;
  EXPECT_EQ(j["method"], "mmdstar");
  stop(d);
  std::filesystem::remove(mission);
  std::filesystem::remove(config);
}

TEST_F(CliDaemonE2E, FleetFileGivesTheTrajectoriesTheDaemonPublishesAndFleetDomainSendsIt) {
  const std::string fleet = testing::projectDataPath("missions/demo_fleet.json");
  const std::string local = tempPath("fleet_local.csv"), gcs_csv = tempPath("fleet_gcs.csv"),
                    remote = tempPath("fleet_remote.csv");
  const Ran planned = run({SKYROUTE_CLI, "fleet", "--file", fleet, "--out", local}, "fleet_local");
  ASSERT_EQ(planned.code, 0) << planned.err;

  ChildProcess d = daemon("211");
  ChildProcess gcs = ChildProcess::spawn(
      {SKYROUTE_CLI, "gcs", "--domain", "211", "--count", "3", "--timeout", "180", "--csv", gcs_csv}, "fleet_gcs");
  const Ran sent = run({SKYROUTE_CLI, "fleet", "--domain", "211", "--file", fleet, "--out", remote, "--wait", "180"},
                       "fleet_domain");
  ASSERT_EQ(sent.code, 0) << sent.out << sent.err << d.err();
  EXPECT_NE(sent.out.find("state=accepted"), std::string::npos) << sent.out;
  EXPECT_NE(sent.out.find("state=succeeded"), std::string::npos) << sent.out;
  for (const char* vehicle : {"uav-1", "uav-2", "uav-3"}) {
    EXPECT_NE(sent.out.find(std::string("trajectory vehicle=") + vehicle), std::string::npos) << sent.out;
  }
  EXPECT_NE(sent.out.find("makespan"), std::string::npos) << sent.out;
  ASSERT_EQ(gcs.wait(180.0), 0) << gcs.err();

  const std::string a = readTextFile(local), b = readTextFile(gcs_csv);
  EXPECT_EQ(a.substr(0, a.find('\n')), b.substr(0, b.find('\n'))) << "different columns";
  const auto here = rowsByVehicle(a), there = rowsByVehicle(b);
  ASSERT_EQ(here.size(), 3u);
  for (const auto& [vehicle, rows] : here) {
    EXPECT_GT(std::count(rows.begin(), rows.end(), '\n'), 1000) << vehicle;
    EXPECT_TRUE(there.count(vehicle) && there.at(vehicle) == rows) << vehicle << ": skyroute fleet and the daemon differ";
  }
  EXPECT_TRUE(readTextFile(remote) == a) << "fleet --domain --out wrote other trajectories";

  // A plan the daemon refuses (a task under the ground) is exit 1, its status printed.
  const Ran refused = run({SKYROUTE_CLI, "fleet", "--domain", "211", "--vehicles", "a@46.97,15.04,1000;b@46.91,15.13,1000",
                           "--tasks", "46.95,15.07,100", "--wait", "60"},
                          "fleet_refused");
  EXPECT_EQ(refused.code, 1) << refused.out << refused.err;
  EXPECT_NE(refused.out.find("state=failed"), std::string::npos) << refused.out;
  EXPECT_NE(refused.err.find("under_ground"), std::string::npos) << refused.err;
  stop(d);
  for (const std::string& path : {local, gcs_csv, remote}) std::filesystem::remove(path);
}

TEST_F(CliDaemonE2E, FleetDomainWithoutAServiceIsExitFour) {
  const Ran r = run({SKYROUTE_CLI, "fleet", "--domain", "212", "--file", testing::projectDataPath("missions/demo_fleet.json"),
                     "--wait", "2"},
                    "fleet_nobody");
  EXPECT_EQ(r.code, 4) << r.out << r.err;
  EXPECT_NE(r.err.find("domain 212"), std::string::npos) << r.err;
}

}  // namespace
}  // namespace skyroute
