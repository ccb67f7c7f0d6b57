// The daemon under load, end to end: five vehicles flying and twenty obstacle updates, each
// crossing one vehicle's route; every vehicle an update will meet (decided here from its
// trajectory, tests/daemon/obstacle_reach.hpp) gets a new revision or a replan status within 1 s.
// The 20-vehicle, 100-update version is bench/e2e_latency_bench --vehicles 20 --updates 100.
#include <gtest/gtest.h>

#include <algorithm>
#include <string>
#include <vector>

#include "bench/latency_scenario.hpp"
#include "tests/daemon/daemon_fixture.hpp"
#include "tests/daemon/update_answers.hpp"

namespace skyroute {
namespace {

class LoadE2E : public testing::DaemonFixture {
 protected:
  // `count` vehicles on lanes across the terrain, each with its first trajectory.
  std::vector<std::string> flyVehicles(int count) {
    std::vector<std::string> names;
    for (int v = 0; v < count; ++v) {
      const MissionRequestData m = bench::laneMission(*terrain_, "lane-" + std::to_string(v), v, count);
      names.push_back(m.vehicle_id);
      EXPECT_TRUE(station_->requests->write(m).ok());
    }
    EXPECT_TRUE(station_->pumpUntil(
        [&] { return std::all_of(names.begin(), names.end(), [&](const std::string& v) { return station_->latest(v); }); },
        60.0))
        << daemon_.err();
    return names;
  }
};

TEST_F(LoadE2E, FiveVehiclesAndTwentyUpdatesEveryMetVehicleIsAnsweredWithinASecond) {
  startDaemon(70);
  const std::vector<std::string> vehicles = flyVehicles(5);
  ASSERT_TRUE(station_->obstacles->waitForReaders(1, 20.0).ok());
  std::uint64_t previous_id = 0;
  int answered = 0;
  for (int u = 0; u < 20; ++u) {
    const std::string& target = vehicles[static_cast<std::size_t>(u % 5)];
    if (previous_id != 0) {
      ObstacleUpdateData gone;
      gone.obstacle.id = previous_id;
      gone.remove = true;
      ASSERT_TRUE(station_->obstacles->write(gone).ok());
      station_->pumpUntil([] { return false; }, 0.2);
    }
    const ObstacleUpdateData update =
        bench::crossing(*station_->latest(target), utcNowNs(), 500 + u, 15.0 + (u % 4) * 5.0);
    previous_id = update.obstacle.id;
    const testing::UpdateAnswers answers = testing::writeAndAwaitAnswers(*station_, vehicles, update, 2.0);
    // The crossing is built to meet its vehicle: the independent check must agree.
    ASSERT_NE(std::find(answers.affected.begin(), answers.affected.end(), target), answers.affected.end())
        << "update " << u << " does not meet " << target;
    EXPECT_TRUE(answers.unanswered.empty()) << "update " << u << ": " << answers.unanswered.size()
                                            << " met vehicles unanswered, first " << answers.unanswered.front() << "\n"
                                            << daemon_.err();
    for (const auto& [vehicle, ms] : answers.answer_ms) {
      EXPECT_LE(ms, 1000.0) << "update " << u << " answered " << vehicle << " after " << ms << " ms";
      ++answered;
    }
  }
  EXPECT_GE(answered, 20);
  // Every answer was counted in the log with the updates its cycle took together.
  EXPECT_GE(logCount("updates_coalesced="), 1u) << daemon_.err();
  ASSERT_TRUE(daemon_.running()) << daemon_.err();
}

}  // namespace
}  // namespace skyroute
