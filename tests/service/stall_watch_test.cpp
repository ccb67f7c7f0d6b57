// StallWatch: a gap between two of its ticks longer than the threshold is a stall, suspected from
// the moment the watch is overdue (before its thread has run again) until it is taken; regular
// ticks never are. The clock is the test's own, so a "stall" is a jump of it.
#include <gtest/gtest.h>

#include <atomic>
#include <chrono>
#include <condition_variable>
#include <mutex>

#include "service/stall_watch.hpp"

namespace skyroute {
namespace {

constexpr std::int64_t kMs = 1'000'000;

TEST(StallWatch, RegularTicksAreNoStall) {
  std::int64_t now = 1000 * kMs;
  StallWatch watch(0.25, {}, [&] { return now; });
  for (int i = 0; i < 100; ++i) {
    now += 200 * kMs;  // late ticks, but each within the threshold
    EXPECT_FALSE(watch.suspect()) << i;
    watch.tickForTest();
  }
  EXPECT_FALSE(watch.take().has_value());
}

TEST(StallWatch, AnOverdueWatchIsSuspectedBeforeItTicksAndTheGapIsTakenOnce) {
  std::int64_t now = 1000 * kMs;
  StallWatch watch(0.25, {}, [&] { return now; });
  watch.tickForTest();
  now += 3000 * kMs;  // the process stood still for 3 s
  EXPECT_TRUE(watch.suspect()) << "overdue: suspected before the watch's thread runs again";
  watch.tickForTest();
  EXPECT_TRUE(watch.suspect()) << "noticed and not yet taken";
  const std::optional<double> taken = watch.take();
  ASSERT_TRUE(taken.has_value());
  EXPECT_NEAR(*taken, 3.0, 1e-9);
  EXPECT_FALSE(watch.suspect());
  EXPECT_FALSE(watch.take().has_value()) << "a stall is taken once";
  now += 100 * kMs;
  watch.tickForTest();
  EXPECT_FALSE(watch.suspect());
}

TEST(StallWatch, TakenBeforeTheWatchTicksTheStallIsNotCountedTwice) {
  std::int64_t now = 1000 * kMs;
  StallWatch watch(0.25, {}, [&] { return now; });
  now += 2000 * kMs;
  const std::optional<double> taken = watch.take();  // the caller woke first
  ASSERT_TRUE(taken.has_value());
  EXPECT_NEAR(*taken, 2.0, 1e-9);
  now += 10 * kMs;
  watch.tickForTest();  // the watch wakes a moment later: it measures from the take
  EXPECT_FALSE(watch.suspect());
  EXPECT_FALSE(watch.take().has_value());
}

TEST(StallWatch, ItsThreadCallsBackOnAStallOfTheClock) {
  // A clock that follows the steady clock, plus a jump the test makes: the watch's thread ticks
  // for real and sees the jump as a stall.
  std::atomic<std::int64_t> jump_ns{0};
  std::mutex mutex;
  std::condition_variable called;
  int stalls = 0;
  StallWatch watch(
      0.2,
      [&] {
        std::lock_guard lock(mutex);
        ++stalls;
        called.notify_all();
      },
      [&] { return StallWatch::steadyNowNs() + jump_ns.load(); });
  watch.start();
  jump_ns = 5000 * kMs;
  {
    std::unique_lock lock(mutex);
    ASSERT_TRUE(called.wait_for(lock, std::chrono::seconds(30), [&] { return stalls > 0; }));
  }
  const std::optional<double> taken = watch.take();
  ASSERT_TRUE(taken.has_value());
  EXPECT_GE(*taken, 5.0);
  watch.stop();
  EXPECT_EQ(stalls, 1);
}

}  // namespace
}  // namespace skyroute
