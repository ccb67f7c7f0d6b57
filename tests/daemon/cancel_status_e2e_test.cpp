// `skyroute status` and `skyroute cancel` against skyrouted as a process: status reports the
// daemon's heartbeat (instance, pid, uptime, queue, active vehicles) as it changes; cancel stops a
// flying mission by vehicle or by request id alone, and a cancel for nothing is refused (exit 1).
// Without a daemon both exit 4.
#include <gtest/gtest.h>

#include <chrono>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "tests/daemon/daemon_fixture.hpp"

namespace skyroute {
namespace {

using testing::Ran;

Ran runCli(std::vector<std::string> args, const std::string& name, double timeout_s = 60.0) {
  args.insert(args.begin(), SKYROUTE_CLI);
  return testing::runToEnd(args, name, timeout_s);
}

// The run ended with this exit code and its stderr says this.
void expectExit(const Ran& r, int code, const std::string& says) {
  EXPECT_EQ(r.code, code) << r.out << r.err;
  EXPECT_NE(r.err.find(says), std::string::npos) << r.err;
}

class CancelStatusE2E : public testing::DaemonFixture {
 protected:
  // skyroute status --json on `domain`: its one service (the test fails when there is not one).
  nlohmann::json statusOfTheOneService(const std::string& domain, const std::string& name) {
    const Ran r = runCli({"status", "--domain", domain, "--json"}, name);
    EXPECT_EQ(r.code, 0) << r.err;
    const nlohmann::json j = nlohmann::json::parse(r.out, nullptr, false);
    if (j.is_discarded() || !j.contains("services") || j["services"].size() != 1) {
      ADD_FAILURE() << "not one service:\n" << r.out << r.err;
      return nlohmann::json::object();
    }
    return j["services"][0];
  }
  // Waits until the daemon's heartbeat says `vehicles` are flying.
  bool heartbeatSays(std::uint32_t vehicles) {
    for (int i = 0; i < 10; ++i) {
      auto h = station_->freshHeartbeat(5.0);
      if (h && h->vehicles == vehicles) return true;
    }
    return false;
  }
};

TEST_F(CancelStatusE2E, StatusShowsTheHeartbeatAndCancelStopsByVehicleOrByRequest) {
  startDaemon(213);
  const nlohmann::json idle = statusOfTheOneService("213", "status_idle");
  ASSERT_TRUE(station_->last_heartbeat);
  EXPECT_EQ(idle.value("instance_id", ""), station_->last_heartbeat->instance_id);
  EXPECT_EQ(idle.value("pid", 0), daemon_.pid());
  EXPECT_EQ(idle.value("vehicles", -1), 0);
  EXPECT_EQ(idle.value("queue_length", -1), 0);
  EXPECT_GT(idle.value("uptime_s", 0.0), 0.0);
  EXPECT_EQ(idle.value("terrain_loaded", false), true);

  // A flying vehicle shows in the heartbeat; the text form names it too.
  ASSERT_TRUE(station_->requests->write(simpleMission("fly-1", "uav-c", 0.0)).ok());
  ASSERT_TRUE(station_->waitState("fly-1", PlanState::kSucceeded, 120.0)) << daemon_.err();
  ASSERT_TRUE(heartbeatSays(1));
  const nlohmann::json flying = statusOfTheOneService("213", "status_flying");
  EXPECT_EQ(flying.value("vehicles", -1), 1);
  EXPECT_GT(flying.value("uptime_s", 0.0), idle.value("uptime_s", 0.0));
  const Ran text = runCli({"status", "--domain", "213"}, "status_text");
  EXPECT_EQ(text.code, 0) << text.err;
  EXPECT_NE(text.out.find("vehicles=1 "), std::string::npos) << text.out;
  EXPECT_NE(text.out.find("queue=0 "), std::string::npos) << text.out;
  EXPECT_NE(text.out.find("pid=" + std::to_string(daemon_.pid())), std::string::npos) << text.out;

  // By vehicle.
  const Ran by_vehicle = runCli({"cancel", "--domain", "213", "--vehicle", "uav-c"}, "cancel_vehicle");
  EXPECT_EQ(by_vehicle.code, 0) << by_vehicle.out << by_vehicle.err;
  EXPECT_NE(by_vehicle.out.find("cancelled 1 request"), std::string::npos) << by_vehicle.out;
  ASSERT_TRUE(station_->waitState("fly-1", PlanState::kCancelled, 10.0)) << daemon_.err();
  ASSERT_TRUE(heartbeatSays(0));

  // By request id alone: the service finds its vehicle.
  ASSERT_TRUE(station_->requests->write(simpleMission("fly-2", "uav-d", 0.0)).ok());
  ASSERT_TRUE(station_->waitState("fly-2", PlanState::kSucceeded, 120.0)) << daemon_.err();
  const Ran by_request = runCli({"cancel", "--domain", "213", "--request", "fly-2"}, "cancel_request");
  EXPECT_EQ(by_request.code, 0) << by_request.out << by_request.err;
  EXPECT_NE(by_request.out.find("vehicle=uav-d state=cancelled"), std::string::npos) << by_request.out;
  ASSERT_TRUE(station_->waitState("fly-2", PlanState::kCancelled, 10.0)) << daemon_.err();
  ASSERT_TRUE(heartbeatSays(0));
  EXPECT_EQ(statusOfTheOneService("213", "status_after").value("vehicles", -1), 0);

  // Nothing to cancel: the service's refusal, exit 1.
  expectExit(runCli({"cancel", "--domain", "213", "--request", "ghost"}, "cancel_ghost"),
             1, "cancel refused: no request 'ghost' is queued");
  expectExit(runCli({"cancel", "--domain", "213", "--vehicle", "uav-c", "--request", "fly-1"}, "cancel_done"),
             1, "of vehicle 'uav-c'");
}

TEST_F(CancelStatusE2E, WithoutADaemonBothExitFourAndCancelNeedsATarget) {
  expectExit(runCli({"status", "--domain", "214", "--wait", "1"}, "status_none"),
             4, "no planning service heartbeat on domain 214");
  expectExit(runCli({"cancel", "--domain", "214", "--vehicle", "uav-x", "--wait", "1"}, "cancel_none"),
             4, "no planning service is listening");
  expectExit(runCli({"cancel", "--domain", "214"}, "cancel_nothing"), 2, "--vehicle");
  // With --progress a request says what it waits for while it waits (here every 2 s of 5).
  const std::string mission = testing::projectDataPath("missions/demo_mission.json");
  expectExit(runCli({"request", "--domain", "214", "--file", mission, "--wait", "5", "--progress"}, "request_progress"),
             4, "waiting on domain 214: 0 planning services discovered, 0 with a heartbeat; ");
}

// A client's status reader and the daemon's status writer discover each other separately, and a
// volatile answer written before the daemon knows the reader is lost to it. The daemon holds the
// answer (up to 2 s) until its writer has matched a reader of the client's participant: here the
// client makes its reader only after the daemon has read its cancel, and still gets the answer.
TEST_F(CancelStatusE2E, TheAnswerWaitsForTheClientsStatusReader) {
  startDaemon(129);
  ASSERT_TRUE(station_->requests->write(simpleMission("fly-late", "uav-l", 0.0)).ok());
  ASSERT_TRUE(station_->waitState("fly-late", PlanState::kSucceeded, 120.0)) << daemon_.err();

  auto participant = dds::createParticipant(129);
  ASSERT_TRUE(participant.ok());
  auto cancels = dds::Writer<CancelRequestData>::create(participant->get());
  ASSERT_TRUE(cancels.ok());
  ASSERT_TRUE(cancels->waitForReaders(1, 20.0).ok());
  ASSERT_TRUE(cancels->write(CancelRequestData{"", "uav-l", ""}).ok());
  ASSERT_TRUE(cancels->waitForAcks(5.0).ok());  // the daemon has the cancel

  auto statuses = dds::Reader<PlanStatusData>::create(participant->get());
  ASSERT_TRUE(statuses.ok());
  auto loop = dds::WaitLoop::create(participant->get());
  ASSERT_TRUE(loop.ok());
  bool cancelled = false;
  ASSERT_TRUE(loop->add(
                      *statuses,
                      [&](PlanStatusData&& st) {
                        cancelled = cancelled || (st.request_id == "fly-late" && st.state == PlanState::kCancelled);
                      },
                      [](const Error&) {})
                  .ok());
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(10);
  while (!cancelled && std::chrono::steady_clock::now() < deadline) ASSERT_TRUE(loop->runOnce(0.05).ok());
  EXPECT_TRUE(cancelled) << "the answer to the cancel never reached the client's late reader\n" << daemon_.err();
  // The fixture's station saw it too: the mission was cancelled, not just answered.
  EXPECT_TRUE(station_->waitState("fly-late", PlanState::kCancelled, 5.0));
}

}  // namespace
}  // namespace skyroute
