// What one request may cost the daemon, end to end: a near-zero speed, a trajectory longer than
// the caps or a request over its memory share is refused at once with a typed error, and the
// daemon's memory does not move; a request id names one plan per vehicle; numbers in messages are
// short, and a leg without a path is named one way.
#include <gtest/gtest.h>

#include <chrono>
#include <regex>
#include <set>
#include <string>

#include "tests/daemon/daemon_fixture.hpp"

namespace skyroute {
namespace {

using testing::Station;
using Clock = std::chrono::steady_clock;

class RequestBoundsE2E : public testing::DaemonFixture {
 protected:
  // Writes `m` and waits for its final status; returns it and how long it took to come back.
  std::pair<PlanStatusData, double> answer(const MissionRequestData& m, double timeout_s = 10.0) {
    const auto sent = Clock::now();
    EXPECT_TRUE(station_->requests->write(m).ok());
    EXPECT_TRUE(station_->waitTerminal({m.request_id}, timeout_s)) << daemon_.err();
    const double latency_s = std::chrono::duration<double>(Clock::now() - sent).count();
    return {station_->terminal(m.request_id).value_or(PlanStatusData{}), latency_s};
  }
};

TEST_F(RequestBoundsE2E, ANearZeroSpeedIsRefusedWithin100MsAndTheDaemonsMemoryDoesNotMove) {
  startDaemon(170);
  // A first refusal warms the answer path (log buffers, DDS caches) before memory is measured.
  MissionRequestData warm = simpleMission("warm", "uav-warm", 0.0);
  warm.limits.v_ref_mps = 0.0;
  ASSERT_EQ(answer(warm).first.state, PlanState::kFailed);
  ASSERT_TRUE(station_->freshHeartbeat(5.0));
  const long rss_before_kb = daemon_.rssKb();
  ASSERT_GT(rss_before_kb, 0);

  MissionRequestData slow = simpleMission("crawl", "uav-crawl", 0.0);
  slow.limits.v_ref_mps = 0.001;
  const auto [status, latency_s] = answer(slow);
  std::printf("v_ref_mps 0.001: refused in %.1f ms\n", latency_s * 1e3);
  EXPECT_EQ(status.state, PlanState::kFailed);
  EXPECT_EQ(status.error_code, PlanErrorCode::kLimitsOutOfRange) << status.message;
  EXPECT_EQ(status.field, "limits.v_ref_mps");
  EXPECT_NE(status.message.find("0.001"), std::string::npos) << status.message;
  EXPECT_LT(latency_s, 0.1);

  // A speed within the bounds over a route longer than the longest trajectory (10 km at 1 m/s
  // is 10,000 s; the cap is 7,200 s) is refused as too large, as fast: nothing is planned.
  MissionRequestData long_route = simpleMission("too-long", "uav-crawl", 0.0);
  long_route.limits.v_ref_mps = 1.0;
  const auto [too_long, too_long_s] = answer(long_route);
  EXPECT_EQ(too_long.error_code, PlanErrorCode::kTooLarge) << too_long.message;
  EXPECT_EQ(too_long.field, "limits.v_ref_mps");
  EXPECT_NE(too_long.message.find("7200 s"), std::string::npos) << too_long.message;
  EXPECT_LT(too_long_s, 0.1);

  // Two heartbeats later (a daemon sampling such a trajectory grows by hundreds of MB a second).
  ASSERT_TRUE(station_->freshHeartbeat(5.0));
  ASSERT_TRUE(station_->freshHeartbeat(5.0));
  const long rss_after_kb = daemon_.rssKb();
  std::printf("daemon RSS: %ld kB before, %ld kB after\n", rss_before_kb, rss_after_kb);
  EXPECT_LT(rss_after_kb - rss_before_kb, 1024) << "the refused requests cost the daemon memory";
  EXPECT_TRUE(daemon_.running());
}

TEST_F(RequestBoundsE2E, ARequestOverItsMemoryShareOrOverTheDurationCapIsRefusedTooLarge) {
  // 8 MiB shared by two planning threads: 4 MiB each. The ordering grid alone (200 x 200 cells
  // for three points) is estimated at 2.7 MiB, the samples of a 500 s trajectory at 1.5 MiB.
  startDaemonWithConfig(171,
                        "[planning]\nmemory_budget_mb = 8\nthreads = 2\n"
                        "[bounds]\nmax_trajectory_duration_s = 510\n");
  const auto [ordered, ordered_s] = answer(simpleMission("ordered", "uav-m", 0.0));
  EXPECT_EQ(ordered.error_code, PlanErrorCode::kTooLarge) << ordered.message;
  EXPECT_EQ(ordered.field, "points");
  EXPECT_NE(ordered.message.find("share of the memory budget"), std::string::npos) << ordered.message;
  EXPECT_LT(ordered_s, 0.1);

  // In the given order there is no ordering grid: within the share, and the route (10.07 km at
  // 20 m/s) lasts at least 503 s, under the 510 s cap, so it is planned. The trajectory built,
  // accelerating and braking, lasts 513 s: refused before any sample is made.
  MissionRequestData fixed = simpleMission("fixed", "uav-m", 0.0);
  fixed.fixed_order = true;
  const auto [built, built_s] = answer(fixed, 60.0);
  EXPECT_EQ(built.error_code, PlanErrorCode::kTooLarge) << built.message << "\n" << daemon_.err();
  EXPECT_EQ(built.field, "trajectory");
  EXPECT_NE(built.message.find("510 s"), std::string::npos) << built.message;
  EXPECT_EQ(station_->latest("uav-m"), nullptr) << "a refused plan published a trajectory";
}

TEST_F(RequestBoundsE2E, ARequestIdNamesOnePlanPerVehicle) {
  // One planning thread, busy with a slow mission (RRT* legs of up to 2,000,000 iterations), so
  // the request below waits in the queue: in flight when its duplicate comes.
  startDaemonWithConfig(172, "[planning]\nleg_max_iterations = 2000000\n");
  auto second = openMatchedStation(172);
  ASSERT_TRUE(second);
  const MissionRequestData blocker = slowMission("blocker", "uav-z");
  ASSERT_TRUE(station_->requests->write(blocker).ok());
  ASSERT_TRUE(station_->waitState("blocker", PlanState::kPlanning, 30.0));

  const MissionRequestData valid = simpleMission("dup-1", "uav-d", 0.0);
  ASSERT_TRUE(station_->requests->write(valid).ok());
  const std::string me = station_->requesterId();
  ASSERT_TRUE(station_->waitState("dup-1", PlanState::kAccepted, 10.0, /*mine=*/true));
  // Another client, the same id and vehicle, an impossible mission: refused, and only to it.
  MissionRequestData impossible = valid;
  impossible.points[0] = above(0, 200, -100);
  ASSERT_TRUE(second->requests->write(impossible).ok());
  ASSERT_TRUE(second->pumpUntil([&] { return second->terminalForMe("dup-1").has_value(); }, 10.0)) << daemon_.err();
  const PlanStatusData refused = *second->terminalForMe("dup-1");
  EXPECT_EQ(refused.state, PlanState::kFailed);
  EXPECT_EQ(refused.error_code, PlanErrorCode::kDuplicateRequest) << refused.message;
  EXPECT_EQ(refused.field, "request_id");

  ASSERT_TRUE(station_->cancels->write(CancelRequestData{"blocker", "uav-z"}).ok());
  // The first client gets its own plan's answer, and no failure addressed to it.
  ASSERT_TRUE(station_->pumpUntil([&] { return station_->terminalForMe("dup-1").has_value(); }, 120.0)) << daemon_.err();
  EXPECT_EQ(station_->terminalForMe("dup-1")->state, PlanState::kSucceeded) << station_->terminalForMe("dup-1")->message;
  for (const auto& s : station_->status_log) {
    if (s.request_id == "dup-1" && s.requester == me) {
      EXPECT_NE(s.state, PlanState::kFailed) << s.message;
    }
  }
  ASSERT_TRUE(station_->pumpUntil([&] { return station_->latest("uav-d") != nullptr; }, 10.0));
  const std::string plan_id = station_->latest("uav-d")->plan_id;

  // After completion the same id gets the stored answer: no new plan, whatever the mission says.
  auto third = openMatchedStation(172);
  ASSERT_TRUE(third);
  ASSERT_TRUE(third->requests->write(impossible).ok());
  ASSERT_TRUE(third->pumpUntil([&] { return third->terminalForMe("dup-1").has_value(); }, 10.0)) << daemon_.err();
  EXPECT_EQ(third->terminalForMe("dup-1")->state, PlanState::kSucceeded);
  EXPECT_TRUE(waitForLog("event=duplicate_request request=dup-1 vehicle=uav-d answered=stored", 5.0)) << daemon_.err();
  EXPECT_EQ(logCount("event=request_accepted request=dup-1"), 1u) << daemon_.err();
  station_->pumpUntil([] { return false; }, 0.5);
  EXPECT_EQ(station_->latest("uav-d")->plan_id, plan_id);

  // The id is per vehicle: another vehicle's request with it is a plan of its own.
  MissionRequestData other_vehicle = impossible;
  other_vehicle.vehicle_id = "uav-e";
  ASSERT_TRUE(second->requests->write(other_vehicle).ok());
  ASSERT_TRUE(second->pumpUntil(
      [&] {
        for (const auto& s : second->status_log)
          if (s.vehicle_id == "uav-e" && isTerminal(s.state)) return true;
        return false;
      },
      20.0));
  for (const auto& s : second->status_log) {
    if (s.vehicle_id == "uav-e" && isTerminal(s.state)) {
      EXPECT_EQ(s.error_code, PlanErrorCode::kUnderGround) << s.message;
    }
  }
}

// The point names a message uses: begin, end, points[k].
std::set<std::string> pointNamesIn(const std::string& message) {
  std::set<std::string> names;
  static const std::regex kName(R"(\bbegin\b|\bend\b|points\[\d+\])");
  for (auto it = std::sregex_iterator(message.begin(), message.end(), kName); it != std::sregex_iterator(); ++it)
    names.insert(it->str());
  return names;
}

TEST_F(RequestBoundsE2E, NumbersInMessagesAreShortAndANoPathMessageNamesOneLeg) {
  // Three RRT* iterations per leg: no leg finds a path.
  startDaemonWithConfig(173, "[planning]\nleg_max_iterations = 3\n");
  MissionRequestData huge = simpleMission("huge", "uav-n", 0.0);
  huge.points[0].enu_m.x() = 1e308;
  const PlanStatusData far = answer(huge).first;
  EXPECT_EQ(far.state, PlanState::kFailed);
  EXPECT_NE(far.message.find("1e+308"), std::string::npos) << far.message;
  EXPECT_LT(far.message.size(), 200u) << far.message;

  // Low over the hills, the legs' straight lines cut the terrain: RRT* must search, and cannot.
  MissionRequestData m = simpleMission("no-path", "uav-n", 0.0);
  m.begin = above(-5000, -3000, 50);
  m.points = {above(5000, 3000, 50)};
  m.end = above(5000, -3000, 50);
  m.fixed_order = true;
  const PlanStatusData none = answer(m, 60.0).first;
  EXPECT_EQ(none.error_code, PlanErrorCode::kUnreachable) << none.message;
  EXPECT_NE(none.message.find("no path found"), std::string::npos) << none.message;
  // It names the leg once, in the request's terms: the leg's two points, the field its end.
  EXPECT_EQ(pointNamesIn(none.message), (std::set<std::string>{"begin", "points[0]"})) << none.message;
  EXPECT_EQ(none.field, "points[0]");
  EXPECT_EQ(none.message.find("solution"), std::string::npos) << none.message;
}

}  // namespace
}  // namespace skyroute
