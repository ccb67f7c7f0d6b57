// A flood of obstacle updates, end to end: `skyroute replay --rate 10000` for 8 s against a daemon
// with 20 vehicles flying. The daemon's memory stays flat after the first seconds, the heartbeat
// keeps its period within 10 %, updates are coalesced per vehicle and cycle (the log counts
// them), and requests written during the flood still reach a terminal status. The 60 s flood is
// bench/daemon_soak_bench --flood 60 (docs/benchmarks.md). And a burst of 200 requests at once:
// each answered, busy beyond the queue, the heartbeat on time.
#include <gtest/gtest.h>

#include <algorithm>
#include <regex>
#include <string>
#include <vector>

#include "bench/latency_scenario.hpp"
#include "tests/daemon/daemon_fixture.hpp"
#include "tests/daemon/flood_feed.hpp"

namespace skyroute {
namespace {

using testing::ChildProcess;

class FloodE2E : public testing::DaemonFixture {};

// The largest N of the log's "updates_coalesced=N".
std::uint64_t mostCoalesced(const std::string& log) {
  static const std::regex pattern("updates_coalesced=([0-9]+)");
  std::uint64_t most = 0;
  for (std::sregex_iterator it(log.begin(), log.end(), pattern), end; it != end; ++it) {
    most = std::max<std::uint64_t>(most, std::stoull((*it)[1].str()));
  }
  return most;
}

TEST_F(FloodE2E, TenThousandUpdatesASecondLeaveMemoryFlatTheHeartbeatOnTimeAndRequestsAnswered) {
  constexpr int kDomain = 71;
  constexpr double kFloodS = 8.0;
  startDaemon(kDomain);
  for (int v = 0; v < 20; ++v) ASSERT_TRUE(station_->requests->write(bench::laneMission(*terrain_, "lane-" + std::to_string(v), v, 20)).ok());
  ASSERT_TRUE(station_->pumpUntil([&] { return station_->trajectory_log.size() >= 20; }, 60.0)) << daemon_.err();
  const std::string feed = testing::e2eTempPath("flood.jsonl");
  testing::writeFloodFeed(feed, *terrain_, 40, 7);

  // The daemon's reader and this station's echo.
  ChildProcess replay = ChildProcess::spawn({SKYROUTE_CLI, "replay", feed, "--domain", std::to_string(kDomain),
                                             "--readers", "2", "--rate", "10000", "--loop", "--duration",
                                             std::to_string(kFloodS)},
                                            "replay_flood");
  ASSERT_TRUE(replay.started());
  ASSERT_TRUE(station_->pumpUntil([&] { return !station_->obstacle_log.empty(); }, 20.0)) << replay.err();
  const auto flood_start = std::chrono::steady_clock::now();
  const std::size_t first_heartbeat = station_->heartbeat_stamps_ns.size();
  std::vector<long> rss_kb;
  std::vector<std::string> asked;
  while (replay.running() && std::chrono::steady_clock::now() - flood_start < std::chrono::duration<double>(kFloodS + 5)) {
    station_->pumpUntil([] { return false; }, 0.25);
    station_->obstacle_log.clear();  // the echo: only its arrival matters
    rss_kb.push_back(daemon_.rssKb());
    if (asked.size() < 5 && rss_kb.size() % 4 == 0) {  // a request every second during the flood
      const int v = static_cast<int>(asked.size());
      asked.push_back("flood-" + std::to_string(v));
      ASSERT_TRUE(station_->requests->write(bench::laneMission(*terrain_, asked.back(), v, 20)).ok());
    }
  }
  const std::size_t last_heartbeat = station_->heartbeat_stamps_ns.size();
  EXPECT_EQ(replay.wait(10.0), 0) << replay.err();
  // The rate held (at least half of it on a shared machine).
  std::smatch published;
  const std::string out = replay.out();
  ASSERT_TRUE(std::regex_search(out, published, std::regex("published ([0-9]+) obstacle updates"))) << out;
  EXPECT_GE(std::stod(published[1].str()), 0.5 * 10000 * kFloodS) << out;

  // Memory: after the first half of the flood it grows no more.
  ASSERT_GE(rss_kb.size(), 8u);
  const long first_half = *std::max_element(rss_kb.begin(), rss_kb.begin() + static_cast<long>(rss_kb.size() / 2));
  const long second_half = *std::max_element(rss_kb.begin() + static_cast<long>(rss_kb.size() / 2), rss_kb.end());
  EXPECT_LE(second_half, first_half + first_half / 20 + 2048) << "RSS kB, first half max " << first_half;
  std::printf("flood: daemon RSS max %ld kB, updates published %s\n", std::max(first_half, second_half),
              published[1].str().c_str());

  // The heartbeat (period 1 s) on time within 10 %, every one.
  ASSERT_GE(last_heartbeat - first_heartbeat, 6u);
  for (std::size_t i = first_heartbeat + 1; i < last_heartbeat; ++i) {
    const double interval_s = static_cast<double>(station_->heartbeat_stamps_ns[i] - station_->heartbeat_stamps_ns[i - 1]) * 1e-9;
    EXPECT_NEAR(interval_s, 1.0, 0.1) << "heartbeat " << i;
  }

  // Requests written during the flood are answered, and cycles took several updates at once.
  EXPECT_EQ(asked.size(), 5u);
  EXPECT_TRUE(station_->waitTerminal(asked, 30.0)) << daemon_.err().substr(0, 4000);
  for (const std::string& id : asked) {
    const auto done = station_->terminal(id);
    EXPECT_TRUE(done && done->state == PlanState::kSucceeded) << id << ": " << (done ? done->message : "no status");
  }
  EXPECT_GE(mostCoalesced(daemon_.err()), 2u);
  ASSERT_TRUE(daemon_.running());
  std::filesystem::remove(feed);
}

TEST_F(FloodE2E, TwoHundredRequestsAtOnceAreEachAnsweredAndBeyondTheQueueRefusedBusy) {
  constexpr int kDomain = 76;
  startDaemon(kDomain);
  const long rss_before_kb = daemon_.rssKb();
  std::vector<std::string> ids;
  for (int i = 0; i < 200; ++i) {
    ids.push_back("burst-" + std::to_string(i));
    ASSERT_TRUE(station_->requests->write(simpleMission(ids.back(), "uav-" + std::to_string(i % 20), 100.0 * (i % 20))).ok());
  }
  const std::size_t heartbeats_before = station_->heartbeat_stamps_ns.size();
  long rss_max_kb = 0;
  ASSERT_TRUE(station_->pumpUntil(
      [&] {
        rss_max_kb = std::max(rss_max_kb, daemon_.rssKb());
        return std::all_of(ids.begin(), ids.end(), [&](const std::string& id) { return station_->terminal(id).has_value(); });
      },
      25.0))
      << daemon_.err().substr(0, 4000);
  int busy = 0, succeeded = 0;
  for (const std::string& id : ids) {
    const PlanStatusData s = *station_->terminal(id);
    busy += s.error_code == PlanErrorCode::kBusy ? 1 : 0;
    succeeded += s.state == PlanState::kSucceeded ? 1 : 0;
  }
  EXPECT_GE(busy, 200 - 64 - 2) << "beyond planning.max_queue (64) the answer is busy";
  EXPECT_GE(succeeded, 20);
  EXPECT_EQ(busy + succeeded, 200) << "every other answer is busy or succeeded";
  EXPECT_LE(rss_max_kb, rss_before_kb + 200 * 1024) << "RSS kB before " << rss_before_kb;
  // The heartbeat went on through the burst.
  for (std::size_t i = heartbeats_before + 1; i < station_->heartbeat_stamps_ns.size(); ++i) {
    const double interval_s = static_cast<double>(station_->heartbeat_stamps_ns[i] - station_->heartbeat_stamps_ns[i - 1]) * 1e-9;
    EXPECT_NEAR(interval_s, 1.0, 0.1) << "heartbeat " << i;
  }
  EXPECT_TRUE(daemon_.running());
}

}  // namespace
}  // namespace skyroute
