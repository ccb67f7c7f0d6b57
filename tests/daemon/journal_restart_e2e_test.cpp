// skyrouted with --state-dir killed with SIGKILL and started again on the same folder: a mission
// that was being planned is planned; a vehicle's trajectory comes back within 2 s, to a ground
// station that joins only after the restart, with the same plan, revision and samples, and the
// daemon goes on replanning it with the journal's obstacles in force. A damaged journal and one
// from a newer skyrouted are refused (exit code 3, a message naming the file).
// DDS domains 60-63.
#include <gtest/gtest.h>

#include <sqlite3.h>

#include <chrono>
#include <csignal>
#include <filesystem>
#include <fstream>
#include <iostream>

#include "service/journal_schema.hpp"
#include "service/state_journal.hpp"
#include "tests/daemon/daemon_fixture.hpp"
#include "tests/same_trajectory.hpp"

namespace skyroute::testing {
namespace {

constexpr int kExitBadInput = 3;  // service/cli/exit_codes.hpp

class JournalRestartE2E : public DaemonFixture {
 protected:
  void SetUp() override {
    state_dir_ = e2eTempPath("journal_" + std::string(::testing::UnitTest::GetInstance()->current_test_info()->name()));
    std::filesystem::remove_all(state_dir_);
  }
  void TearDown() override {
    DaemonFixture::TearDown();
    std::filesystem::remove_all(state_dir_);
  }
  std::filesystem::path journalFile() const { return std::filesystem::path(state_dir_) / StateJournal::kFileName; }
  void killDaemon() {
    daemon_.signal(SIGKILL);
    ASSERT_EQ(daemon_.wait(10.0), 128 + SIGKILL);
    // Its output files go now, before a restart under the same name writes them again.
    ChildProcess killed = std::move(daemon_);
  }
  // Starts skyrouted on a journal that must be refused; returns what it printed and exited with.
  Ran startRefused(int domain, std::vector<std::string> extra) {
    std::vector<std::string> argv{SKYROUTED, "--domain", std::to_string(domain)};
    argv.insert(argv.end(), extra.begin(), extra.end());
    return runToEnd(argv, "skyrouted_refused_" + std::to_string(domain), 30.0);
  }

  std::string state_dir_;
};

TEST_F(JournalRestartE2E, KilledWhilePlanningTheMissionIsPlannedAfterTheRestart) {
  // A plan that takes many seconds: a huge RRT* budget per leg.
  startDaemonWithConfig(60, "[planning]\nleg_max_iterations = 2000000\n", {"--state-dir", state_dir_});
  const MissionRequestData slow = slowMission("slow", "uav-s");
  ASSERT_TRUE(station_->requests->write(slow).ok());
  ASSERT_TRUE(station_->waitState("slow", PlanState::kPlanning, 30.0)) << daemon_.err();
  ASSERT_FALSE(station_->terminal("slow").has_value()) << "planning finished too fast to interrupt";
  killDaemon();

  // Started again with the usual budget; the ground station here is a new one.
  startDaemonWithConfig(60, "", {"--state-dir", state_dir_});
  ASSERT_TRUE(station_->waitTerminal({"slow"}, 180.0)) << daemon_.err();
  EXPECT_EQ(station_->terminal("slow")->state, PlanState::kSucceeded) << station_->terminal("slow")->message;
  ASSERT_TRUE(station_->pumpUntil([&] { return station_->latest("uav-s") != nullptr; }, 10.0));
  EXPECT_EQ(station_->latest("uav-s")->request_id, "slow");
  EXPECT_NE(daemon_.err().find("missions_replanned=1"), std::string::npos) << daemon_.err();
  EXPECT_NE(daemon_.err().find("event=plan_succeeded request=slow"), std::string::npos) << daemon_.err();
}

TEST_F(JournalRestartE2E, KilledAfterPublishingTheSameRevisionAndSamplesComeBackWithinTwoSeconds) {
  startDaemon(61, {"--state-dir", state_dir_});
  const MissionRequestData m = simpleMission("flying", "uav-p", 0.0);
  ASSERT_TRUE(station_->requests->write(m).ok());
  ASSERT_TRUE(station_->waitTerminal({"flying"}, 120.0)) << daemon_.err();
  ASSERT_EQ(station_->terminal("flying")->state, PlanState::kSucceeded);
  ASSERT_TRUE(station_->pumpUntil([&] { return station_->latest("uav-p") != nullptr; }, 10.0));
  const TrajectoryData before = *station_->latest("uav-p");
  // An obstacle far off the route, in force until removed.
  ASSERT_TRUE(station_->obstacles->waitForReaders(1, 20.0).ok());
  ObstacleUpdateData aside;
  aside.obstacle.id = 11;
  aside.obstacle.size_m = Eigen::Vector3d::Constant(100.0);
  aside.obstacle.center_m = Eigen::Vector3d(-4000, 4000, terrain_->heightAt(-4000, 4000) + 1500);
  aside.valid_from_utc_ns = utcNowNs();
  ASSERT_TRUE(station_->obstacles->write(aside).ok());
  ASSERT_TRUE(station_->pumpUntil(
      [&] {
        auto beat = station_->freshHeartbeat(2.0);
        return beat && beat->obstacles == 1;
      },
      10.0));
  killDaemon();
  station_.reset();

  // The restart, timed to the trajectory's arrival at a ground station that joins after it.
  const auto restarted = std::chrono::steady_clock::now();
  daemon_ = ChildProcess::spawn({SKYROUTED, "--domain", "61", "--state-dir", state_dir_}, "skyrouted_61_restarted");
  ASSERT_TRUE(daemon_.started());
  station_ = Station::open(61);
  ASSERT_TRUE(station_);
  ASSERT_TRUE(station_->pumpUntil([&] { return station_->latest("uav-p") != nullptr; }, 10.0)) << daemon_.err();
  const double republish_s =
      std::chrono::duration<double>(station_->trajectory_times.front() - restarted).count();
  std::cout << "journal e2e: restart to republished trajectory " << republish_s << " s\n";
  RecordProperty("restart_to_republish_s", std::to_string(republish_s));
  EXPECT_LT(republish_s, 2.0) << daemon_.err();
  const TrajectoryData after = station_->trajectory_log.front();
  EXPECT_EQ(after.plan_id, before.plan_id);
  EXPECT_EQ(after.revision, before.revision);
  EXPECT_EQ(after.request_id, before.request_id);
  EXPECT_EQ(after.visiting_order, before.visiting_order);
  EXPECT_TRUE(sameSamples(after, before)) << "the republished samples differ from the published ones";

  // The journal's obstacle is in force, and replanning goes on: an obstacle on the route 30 s
  // ahead makes the next revision of the same plan.
  auto beat = station_->freshHeartbeat(5.0);
  ASSERT_TRUE(beat);
  EXPECT_EQ(beat->obstacles, 1u);
  ASSERT_TRUE(waitForLog("event=flight_resumed", 30.0)) << daemon_.err();
  EXPECT_NE(daemon_.err().find("same_samples=true"), std::string::npos) << daemon_.err();
  ASSERT_TRUE(station_->obstacles->waitForReaders(1, 20.0).ok());
  const std::int64_t ahead_ns = utcNowNs() + 30'000'000'000LL;
  const TrajectorySampleData* target = nullptr;
  for (const TrajectorySampleData& s : before.samples) {
    if (s.utc_ns >= ahead_ns) {
      target = &s;
      break;
    }
  }
  ASSERT_NE(target, nullptr) << "the flight ends within 30 s";
  ObstacleUpdateData blocking;
  blocking.obstacle.id = 12;
  blocking.obstacle.size_m = Eigen::Vector3d::Constant(250.0);
  blocking.obstacle.center_m = target->position_enu_m;
  blocking.valid_from_utc_ns = utcNowNs();
  ASSERT_TRUE(station_->obstacles->write(blocking).ok());
  ASSERT_TRUE(station_->pumpUntil(
      [&] {
        const TrajectoryData* t = station_->latest("uav-p");
        return t && t->revision == before.revision + 1;
      },
      30.0))
      << daemon_.err();
  EXPECT_EQ(station_->latest("uav-p")->plan_id, before.plan_id);
}

TEST_F(JournalRestartE2E, DamagedJournalIsRefusedNamingTheFile) {
  std::filesystem::create_directories(state_dir_);
  {
    std::ofstream out(journalFile(), std::ios::binary);
    for (int i = 0; i < 8192; ++i) out.put(static_cast<char>((i * 37 + 11) % 253));
  }
  const Ran ran = startRefused(62, {"--state-dir", state_dir_});
  EXPECT_EQ(ran.code, kExitBadInput) << ran.err;
  EXPECT_NE(ran.err.find(journalFile().string()), std::string::npos) << ran.err;
  EXPECT_NE(ran.err.find("not a readable SQLite database"), std::string::npos) << ran.err;
  EXPECT_EQ(ran.err.find("event=ready"), std::string::npos) << ran.err;
}

TEST_F(JournalRestartE2E, JournalOfANewerSkyroutedIsRefusedFromTheConfiguration) {
  std::filesystem::create_directories(state_dir_);
  sqlite3* db = nullptr;
  ASSERT_EQ(sqlite3_open(journalFile().c_str(), &db), SQLITE_OK);
  const std::string sql = "CREATE TABLE schema_version(version INTEGER NOT NULL); INSERT INTO schema_version VALUES (" +
                          std::to_string(kJournalSchemaVersion + 1) + ");";
  ASSERT_EQ(sqlite3_exec(db, sql.c_str(), nullptr, nullptr, nullptr), SQLITE_OK);
  sqlite3_close(db);
  const std::string config = e2eTempPath("journal_newer.toml");
  std::ofstream(config) << "[service]\nstate_dir = \"" << state_dir_ << "\"\n";
  const Ran ran = startRefused(63, {"--config", config});
  std::filesystem::remove(config);
  EXPECT_EQ(ran.code, kExitBadInput) << ran.err;
  EXPECT_NE(ran.err.find(journalFile().string()), std::string::npos) << ran.err;
  EXPECT_NE(ran.err.find("newer skyrouted"), std::string::npos) << ran.err;
  EXPECT_EQ(ran.err.find("event=ready"), std::string::npos) << ran.err;
}

}  // namespace
}  // namespace skyroute::testing
