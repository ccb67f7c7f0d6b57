// skyrouted --log-format json: every line of its log is a JSON object whose fields are the
// event's own (event, vehicle, request, duration_s, ...), typed, as a log collector reads them.
#include <sstream>

#include "tests/daemon/daemon_fixture.hpp"

namespace skyroute {
namespace {

class JsonLogE2E : public testing::DaemonFixture {};

// Domain 222 belongs to this test.
TEST_F(JsonLogE2E, EveryLineIsAnObjectWithTheEventsFields) {
  startDaemon(222, {"--log-format", "json"});
  const MissionRequestData mission = simpleMission("json-log-1", "uav-json", 0.0);
  ASSERT_TRUE(station_->requests->write(mission).ok());
  ASSERT_TRUE(station_->pumpUntil([&] { return station_->terminal("json-log-1").has_value(); }, 60.0));
  ASSERT_EQ(station_->terminal("json-log-1")->state, PlanState::kSucceeded);
  ASSERT_TRUE(waitForLog("plan_succeeded", 10.0)) << daemon_.err();
  daemon_.signal(SIGTERM);
  ASSERT_EQ(daemon_.wait(10.0), 0);

  std::istringstream log(daemon_.err());
  std::string line;
  int lines = 0;
  bool saw_ready = false, saw_succeeded = false;
  while (std::getline(log, line)) {
    if (line.empty()) continue;
    ++lines;
    nlohmann::json j;
    ASSERT_NO_THROW(j = nlohmann::json::parse(line)) << line;
    ASSERT_TRUE(j.is_object()) << line;
    EXPECT_TRUE(j["time"].is_string()) << line;
    EXPECT_TRUE(j["level"].is_string()) << line;
    ASSERT_TRUE(j.contains("event")) << line;
    if (j.contains("msg")) {  // free text after the fields, never the event line itself
      EXPECT_EQ(j["msg"].get<std::string>().find("event="), std::string::npos) << line;
    }
    if (j["event"] == "ready") {
      saw_ready = true;
      EXPECT_EQ(j["domain"], 222) << line;
    }
    if (j["event"] == "plan_succeeded") {
      saw_succeeded = true;
      EXPECT_EQ(j["vehicle"], "uav-json") << line;
      EXPECT_EQ(j["request"], "json-log-1") << line;
      ASSERT_TRUE(j["duration_s"].is_number()) << line;
      EXPECT_GT(j["duration_s"].get<double>(), 10.0) << line;
      EXPECT_TRUE(j["samples"].is_number_integer()) << line;
    }
  }
  EXPECT_GT(lines, 2);
  EXPECT_TRUE(saw_ready) << daemon_.err();
  EXPECT_TRUE(saw_succeeded) << daemon_.err();
}

}  // namespace
}  // namespace skyroute
