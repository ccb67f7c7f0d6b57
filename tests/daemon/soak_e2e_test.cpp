// The soak of bench/daemon_soak_bench (an hour in docs/benchmarks.md) for two minutes, in CI:
// skyrouted as a process with 20 vehicles flying and a crossing obstacle update every 0.1 s
// (tests/daemon/soak_scenario.hpp). It runs alone (RUN_SERIAL in tests/CMakeLists.txt): it keeps
// both cores busy, and the other end-to-end tests time their answers.
#include <gtest/gtest.h>

#include <cstdio>

#include "tests/daemon/daemon_fixture.hpp"
#include "tests/daemon/soak_scenario.hpp"

namespace skyroute {
namespace {

class SoakE2E : public testing::DaemonFixture {};

TEST_F(SoakE2E, TwoMinutesOfTwentyVehiclesAndTenUpdatesASecondLoseNothingAndHoldMemory) {
  constexpr int kDomain = 125;
  startDaemon(kDomain);
  const testing::SoakSummary soak = testing::runSoak(*station_, daemon_, *terrain_, 2.0, 30.0);

  ASSERT_TRUE(soak.daemon_running) << daemon_.err();
  ASSERT_EQ(soak.windows.size(), 4u);
  std::size_t answered = 0;
  for (const testing::SoakWindow& w : soak.windows) {
    answered += w.answer_ms.size();
    std::printf("soak window: %zu answered, p99 %.1f ms, %d missing, RSS max %.1f MiB, heartbeat gap %.2f s\n",
                w.answer_ms.size(), testing::soakPercentile(w.answer_ms, 0.99), w.missing,
                static_cast<double>(w.rss_max_kb) / 1024.0, w.heartbeat_gap_s);
  }
  // The load was real: updates met vehicles and were answered in every window.
  for (const testing::SoakWindow& w : soak.windows) EXPECT_GT(w.answer_ms.size(), 0u);
  EXPECT_GT(answered, 100u);
  EXPECT_GT(soak.revisions_published, 0u);
  // Nothing lost: every update that met a vehicle answered within 5 s, the newest revision of
  // every plan at the station, every request ended.
  EXPECT_EQ(soak.missing(), 0);
  EXPECT_EQ(soak.revisions_lost, 0) << soak.revisions_published << " revisions published";
  EXPECT_EQ(soak.requests_unanswered, 0u) << soak.requests << " requests";
  // Memory held after the warm-up, and no thread stalled (heartbeat period 1 s).
  EXPECT_LT(soak.rssGrowth(), 0.05) << "RSS " << soak.rssBaseWindow().rss_max_kb << " -> "
                                    << soak.windows.back().rss_max_kb << " kB";
  EXPECT_LE(soak.longestHeartbeatGapS(), 3.0);
}

}  // namespace
}  // namespace skyroute
