// Which daemons a client reaches, end to end: a second daemon with the same service_id on a domain
// refuses to start; `skyroute request` reaches every live service before it publishes; a client
// whose daemon is killed is told at once that its request is lost; and a host carries far more
// DDS processes on one domain than Cyclone's default allows.
#include <gtest/gtest.h>

#include <chrono>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "tests/daemon/daemon_fixture.hpp"

namespace skyroute {
namespace {

using testing::ChildProcess;
using Clock = std::chrono::steady_clock;

class ServicePresenceE2E : public testing::DaemonFixture {
 protected:
  ChildProcess request(int domain, const std::string& args, const std::string& name) {
    std::vector<std::string> argv{SKYROUTE_CLI, "request", "--domain", std::to_string(domain)};
    std::istringstream words(args);
    for (std::string w; words >> w;) argv.push_back(w);
    return ChildProcess::spawn(argv, name);
  }
  // A mission file with the simple mission (WGS84-free: ENU points) for `skyroute request --file`.
  std::string missionFile(const MissionRequestData& m, const std::string& name) const {
    const std::string path = testing::e2eTempPath(name + ".json");
    std::ofstream(path) << missionToJson(m).dump();
    return path;
  }
};

TEST_F(ServicePresenceE2E, ASecondDaemonWithTheSameServiceIdRefusesToStart) {
  startDaemon(177);
  ChildProcess second = ChildProcess::spawn({SKYROUTED, "--domain", "177"}, "skyrouted_177_second");
  ASSERT_TRUE(second.started());
  EXPECT_EQ(second.wait(20.0), 5) << second.err();
  EXPECT_NE(second.err().find("another skyrouted already serves service_id 'skyrouted' on domain 177"),
            std::string::npos)
      << second.err();
  EXPECT_NE(second.err().find(station_->last_heartbeat->instance_id), std::string::npos)
      << "the message should name the running instance: " << second.err();
  EXPECT_EQ(second.err().find("event=request_accepted"), std::string::npos);
  // The first one noticed it and serves on.
  EXPECT_TRUE(waitForLog("event=rival_instance", 10.0)) << daemon_.err();

  // One that does not listen before serving (no startup probe) starts, then meets the older one
  // through discovery and stops with the same verdict.
  const std::string config = testing::e2eTempPath("no_probe.toml");
  std::ofstream(config) << "[dds]\nstartup_probe_s = 0\n";
  ChildProcess late = ChildProcess::spawn({SKYROUTED, "--domain", "177", "--config", config}, "skyrouted_177_late");
  EXPECT_EQ(late.wait(20.0), 5) << late.err();
  EXPECT_NE(late.err().find("event=service_conflict"), std::string::npos) << late.err();
  EXPECT_NE(late.err().find("started before this one; stopping"), std::string::npos) << late.err();
  std::filesystem::remove(config);
  const MissionRequestData m = simpleMission("after-rival", "uav-r", 0.0);
  ASSERT_TRUE(station_->requests->write(m).ok());
  ASSERT_TRUE(station_->waitTerminal({m.request_id}, 120.0)) << daemon_.err();
  EXPECT_EQ(station_->terminal(m.request_id)->state, PlanState::kSucceeded);
}

TEST_F(ServicePresenceE2E, RequestReachesEveryLiveServiceBeforeItPublishes) {
  startDaemon(178);
  // Another service (its own service_id) on the same domain: the tool must reach both.
  const std::string config = testing::e2eTempPath("other_service.toml");
  std::ofstream(config) << "[dds]\nservice_id = \"skyrouted-b\"\n";
  ChildProcess other = ChildProcess::spawn({SKYROUTED, "--domain", "178", "--config", config}, "skyrouted_178_b");
  ASSERT_TRUE(station_->pumpUntil([&] { return other.err().find("event=ready") != std::string::npos || !other.running(); },
                                  30.0))
      << other.err();
  MissionRequestData m = simpleMission("both", "uav-b", 0.0);
  const std::string file = missionFile(m, "both");
  ChildProcess tool = request(178, "--file " + file + " --request-id both --wait 60", "request_both");
  EXPECT_EQ(tool.wait(90.0), 0) << tool.out() << tool.err();
  EXPECT_NE(tool.out().find("services=2"), std::string::npos) << tool.out();
  EXPECT_NE(daemon_.err().find("event=request_accepted request=both"), std::string::npos) << daemon_.err();
  EXPECT_NE(other.err().find("event=request_accepted request=both"), std::string::npos) << other.err();
  other.signal(SIGTERM);
  EXPECT_EQ(other.wait(10.0), 0);
  std::filesystem::remove(config);
  std::filesystem::remove(file);
}

TEST_F(ServicePresenceE2E, AClientWhoseDaemonIsKilledIsToldItsRequestIsLost) {
  startDaemonWithConfig(179, "[planning]\nleg_max_iterations = 2000000\n");
  const MissionRequestData m = slowMission("doomed", "uav-k");
  const std::string file = missionFile(m, "doomed");
  ChildProcess tool = request(179, "--file " + file + " --request-id doomed --wait 120", "request_doomed");
  ASSERT_TRUE(station_->pumpUntil(
      [&] { return tool.out().find("state=planning") != std::string::npos || !tool.running(); }, 30.0))
      << tool.out() << tool.err();
  const auto killed = Clock::now();
  daemon_.signal(SIGKILL);
  ASSERT_EQ(daemon_.wait(5.0), 128 + SIGKILL);
  const int code = tool.wait(30.0);
  const double told_s = std::chrono::duration<double>(Clock::now() - killed).count();
  std::printf("kill -9 of the daemon: the client knew after %.2f s\n", told_s);
  EXPECT_EQ(code, 5) << tool.out() << tool.err();
  EXPECT_NE(tool.err().find("service lost"), std::string::npos) << tool.err();
  EXPECT_LT(told_s, 5.0) << "the client waited instead of noticing the loss: " << tool.out() << tool.err();
  std::filesystem::remove(file);
}

TEST_F(ServicePresenceE2E, FortyToolProcessesOnOneDomainAllReachTheDaemon) {
  startDaemon(180);
  const MissionRequestData m = simpleMission("shared", "uav-s", 0.0);
  ASSERT_TRUE(station_->requests->write(m).ok());
  ASSERT_TRUE(station_->waitTerminal({m.request_id}, 120.0)) << daemon_.err();
  ASSERT_EQ(station_->terminal(m.request_id)->state, PlanState::kSucceeded);
  // Each ground station is a process of its own with a participant index of its own; with the
  // old limit (32) the daemon, this test and 31 tools used them all up.
  constexpr int kTools = 40;
  std::vector<ChildProcess> tools;
  for (int i = 0; i < kTools; ++i) {
    tools.push_back(ChildProcess::spawn({SKYROUTE_CLI, "gcs", "--domain", "180", "--count", "1", "--timeout", "60"},
                                        "gcs_" + std::to_string(i)));
  }
  int reached = 0;
  for (int i = 0; i < kTools; ++i) {
    const int code = tools[i].wait(90.0);
    EXPECT_EQ(code, 0) << "gcs " << i << ": " << tools[i].err();
    if (code == 0 && tools[i].out().find("vehicle=uav-s") != std::string::npos) ++reached;
  }
  EXPECT_EQ(reached, kTools);
}

}  // namespace
}  // namespace skyroute
