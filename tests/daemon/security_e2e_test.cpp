// DDS Security end to end, with real processes on loopback: skyrouted with its identity from
// scripts/make-pki.sh (made here, at test time, and deleted after), and `skyroute request` as a
// ground station with an identity, without one, with one that may not write, with an expired
// certificate and with another CA's. Domains 161-165.
#include <gtest/gtest.h>

#include <cstdlib>
#include <filesystem>
#include <string>

#include "service/dds/loopback.hpp"
#include "tests/cli_run.hpp"
#include "tests/daemon/daemon_process.hpp"
#include "tests/test_data.hpp"

namespace skyroute::testing {
namespace {

namespace fs = std::filesystem;

using CommandOutput = CliOutput;

std::string sourcePath(const std::string& relative) { return projectDataPath("../" + relative); }

class SecurityE2e : public ::testing::Test {
 protected:
  // One PKI for the suite, one foreign PKI (another CA) and an expired identity, all made now.
  static void SetUpTestSuite() {
    pki_ = tempPath("pki", "main");
    foreign_ = tempPath("pki", "foreign");
    for (const std::string& dir : {pki_, foreign_}) fs::remove_all(dir);
    made_ = runCommand("bash " + sourcePath("scripts/make-pki.sh") + " " + pki_ + " --days 2");
    if (made_.exit_code == 0) {
      made_ = runCommand("bash " + sourcePath("scripts/make-pki.sh") + " " + foreign_ + " --days 2 --cn-prefix elsewhere");
    }
    if (made_.exit_code == 0) {
      made_ = runCommand("bash " + sourcePath("tests/daemon/make_expired_identity.sh") + " " + pki_);
    }
  }
  static void TearDownTestSuite() {
    fs::remove_all(pki_);
    fs::remove_all(foreign_);
  }

  void SetUp() override {
    ASSERT_EQ(made_.exit_code, 0) << made_.text;
    dds::useLoopbackOnly();  // the daemon and the tools inherit it
  }
  void TearDown() override {
    if (daemon_.started() && daemon_.running()) {
      daemon_.signal(SIGTERM);
      EXPECT_EQ(daemon_.wait(15.0), 0) << daemon_.err();
    }
  }

  // A secured daemon on `domain`, serving once its log says so.
  void startDaemon(int domain) {
    domain_ = domain;
    daemon_ = ChildProcess::spawn({SKYROUTED, "--domain", std::to_string(domain), "--security", pki_ + "/daemon"},
                                  "secured_" + std::to_string(domain));
    ASSERT_TRUE(daemon_.started());
    for (int i = 0; i < 300 && daemon_.running() && daemon_.err().find("event=ready") == std::string::npos; ++i) {
      std::this_thread::sleep_for(std::chrono::milliseconds(100));
    }
    ASSERT_TRUE(daemon_.running()) << daemon_.err();
    ASSERT_NE(daemon_.err().find("event=ready"), std::string::npos) << daemon_.err();
  }

  // `skyroute gcs` waiting for one trajectory; `security` as for request().
  CommandOutput watch(const std::string& security, double timeout_s) const {
    std::string command = std::string(SKYROUTE_CLI) + " gcs --domain " + std::to_string(domain_) +
                          " --count 1 --timeout " + std::to_string(timeout_s);
    if (!security.empty()) command += " --security " + security;
    return runCommand(command);
  }

  // `skyroute request` with the demo mission; `security` is an identity folder or "" for none.
  CommandOutput request(const std::string& security, double wait_s) const {
    std::string command = std::string(SKYROUTE_CLI) + " request --domain " + std::to_string(domain_) + " --file " +
                          projectDataPath("missions/demo_mission.json") + " --wait " + std::to_string(wait_s);
    if (!security.empty()) command += " --security " + security;
    return runCommand(command);
  }

  int acceptedRequests() const {
    const std::string log = daemon_.err();
    int n = 0;
    for (std::size_t at = log.find("event=request_accepted"); at != std::string::npos;
         at = log.find("event=request_accepted", at + 1)) {
      ++n;
    }
    return n;
  }

  static inline std::string pki_, foreign_;
  static inline CommandOutput made_;
  ChildProcess daemon_;
  int domain_ = 0;
};

TEST_F(SecurityE2e, AuthenticatedStationGetsItsTrajectory) {
  startDaemon(161);
  const CommandOutput r = request(pki_ + "/station", 60.0);
  EXPECT_EQ(r.exit_code, 0) << r.text << "\n--- daemon ---\n" << daemon_.err();
  EXPECT_NE(r.text.find("state=succeeded"), std::string::npos) << r.text;
  EXPECT_EQ(acceptedRequests(), 1) << daemon_.err();
  // Every authenticated identity reads: the observer gets the trajectory the station asked for.
  const CommandOutput seen = watch(pki_ + "/observer", 30.0);
  EXPECT_EQ(seen.exit_code, 0) << seen.text;
  EXPECT_NE(seen.text.find("trajectory vehicle=uav-demo"), std::string::npos) << seen.text;
}

TEST_F(SecurityE2e, UnauthenticatedParticipantGetsNothingPlanned) {
  startDaemon(162);
  // An authenticated station's mission is planned and published...
  ASSERT_EQ(request(pki_ + "/station", 60.0).exit_code, 0) << daemon_.err();
  // ...but an unauthenticated participant never finds the service (its heartbeat is encrypted),
  // gets nothing planned, and reads no trajectory.
  const CommandOutput r = request("", 6.0);
  EXPECT_EQ(r.exit_code, 4) << r.text;
  EXPECT_EQ(acceptedRequests(), 1) << daemon_.err();
  const CommandOutput seen = watch("", 4.0);
  EXPECT_NE(seen.exit_code, 0) << seen.text;
  EXPECT_EQ(seen.text.find("trajectory vehicle="), std::string::npos) << seen.text;
  // Nor does it learn who the daemon is: a secured daemon's participant names no instance.
  const CommandOutput status = runCommand(std::string(SKYROUTE_CLI) + " status --domain 162 --wait 2");
  EXPECT_NE(status.exit_code, 0) << status.text;
  EXPECT_EQ(status.text.find("instance"), std::string::npos) << status.text;
}

TEST_F(SecurityE2e, IdentityWithoutTheWriteGrantCannotCreateItsWriter) {
  startDaemon(163);
  const CommandOutput r = request(pki_ + "/observer", 10.0);
  EXPECT_NE(r.exit_code, 0) << r.text;
  EXPECT_NE(r.text.find("grant no publish on topic 'skyroute_mission_request'"), std::string::npos) << r.text;
  EXPECT_EQ(acceptedRequests(), 0) << daemon_.err();
}

TEST_F(SecurityE2e, ExpiredCertificateIsRefusedBeforeJoining) {
  const CommandOutput r = request(pki_ + "/expired", 5.0);
  EXPECT_EQ(r.exit_code, 3) << r.text;
  EXPECT_NE(r.text.find("identity.pem"), std::string::npos) << r.text;
  EXPECT_NE(r.text.find("expired on"), std::string::npos) << r.text;
  // The daemon refuses its own bad identity the same way, and does not start.
  const CommandOutput daemon = runCommand(std::string(SKYROUTED) + " --domain 164 --security " + pki_ + "/expired");
  EXPECT_EQ(daemon.exit_code, 3) << daemon.text;
  EXPECT_NE(daemon.text.find("security.dir"), std::string::npos) << daemon.text;
}

TEST_F(SecurityE2e, AnotherAuthoritysIdentityIsNotAuthenticated) {
  startDaemon(165);
  const CommandOutput r = request(foreign_ + "/station", 6.0);
  EXPECT_EQ(r.exit_code, 4) << r.text;  // its participant is valid, but the daemon never authenticates it
  EXPECT_EQ(r.text.find("trajectory vehicle="), std::string::npos) << r.text;
  EXPECT_EQ(acceptedRequests(), 0) << daemon_.err();
}

}  // namespace
}  // namespace skyroute::testing
