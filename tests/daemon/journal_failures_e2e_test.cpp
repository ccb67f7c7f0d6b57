// The state journal when things go wrong, through the real daemon (docs/journal.md):
// - a second skyrouted on a state folder in use is refused naming the holder, and the folder is
//   free again once the holder is killed (kill -9 included);
// - on a full disk (a 2 MiB tmpfs mounted for the test; skipped when the test cannot mount) every
//   request is acknowledged only once recorded, refused journal_unavailable otherwise, a replan that
//   cannot be recorded is not published, the heartbeat says so, and after kill -9 and a restart
//   every acknowledged vehicle comes back with the revision and samples it had;
// - bytes flipped in one vehicle's samples in the file: that record is quarantined and named in
//   the log, never republished, and the other vehicle resumes; an empty (0-byte) journal is refused;
// - a mission in the journal that a new request would be refused for today is quarantined with
//   its trajectory, named in the log, and the good vehicle resumes.
// DDS domains 50-59.
#include <gtest/gtest.h>

#include <sys/mount.h>

#include <sqlite3.h>

#include <cerrno>
#include <csignal>
#include <cstring>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <map>
#include <regex>
#include <string>

#include "service/state_dir_lock.hpp"
#include "service/state_journal.hpp"
#include "tests/daemon/daemon_fixture.hpp"
#include "tests/same_trajectory.hpp"

namespace skyroute::testing {
namespace {

constexpr int kExitStateDirLocked = 6;  // service/cli/exit_codes.hpp

class JournalFailuresE2E : public DaemonFixture {
 protected:
  void SetUp() override {
    state_dir_ = e2eTempPath("journal_failures_" +
                             std::string(::testing::UnitTest::GetInstance()->current_test_info()->name()));
    std::filesystem::remove_all(state_dir_);
  }
  void TearDown() override {
    DaemonFixture::TearDown();
    if (mounted_) ::umount2(state_dir_.c_str(), MNT_DETACH);
    std::filesystem::remove_all(state_dir_);
  }
  // Makes the state folder a filesystem of its own of size_text (tmpfs "size=" syntax); false when
  // this process may not mount (not root, or no CAP_SYS_ADMIN in its namespace), with why.
  bool mountSmallStateDir(const std::string& size_text, std::string& why) {
    std::filesystem::create_directories(state_dir_);
    const std::string options = "size=" + size_text + ",mode=0700";
    if (::mount("skyroute_test", state_dir_.c_str(), "tmpfs", MS_NOSUID | MS_NODEV, options.c_str()) != 0) {
      why = std::strerror(errno);
      return false;
    }
    mounted_ = true;
    return true;
  }
  void killDaemon() {
    daemon_.signal(SIGKILL);
    ASSERT_EQ(daemon_.wait(10.0), 128 + SIGKILL);
    ChildProcess killed = std::move(daemon_);  // its output files go before a restart writes them again
  }
  // The instance id the running daemon logged when it became active.
  std::string instanceOfDaemon() const {
    std::smatch m;
    const std::string log = daemon_.err();
    if (!std::regex_search(log, m, std::regex("event=active [^\\n]* instance=([0-9a-f-]+)"))) return "";
    return m[1];
  }

  std::filesystem::path journalFile() const { return std::filesystem::path(state_dir_) / StateJournal::kFileName; }
  // Flies `missions` (each to success) and returns each vehicle's trajectory as the station got it.
  std::map<std::string, TrajectoryData> fly(const std::vector<MissionRequestData>& missions) {
    std::map<std::string, TrajectoryData> published;
    for (const MissionRequestData& m : missions) {
      EXPECT_TRUE(station_->requests->write(m).ok());
      EXPECT_TRUE(station_->waitTerminal({m.request_id}, 180.0)) << daemon_.err();
      const auto answer = station_->terminal(m.request_id);
      EXPECT_TRUE(answer && answer->state == PlanState::kSucceeded) << (answer ? answer->message : daemon_.err());
      EXPECT_TRUE(station_->pumpUntil([&] { return station_->latest(m.vehicle_id) != nullptr; }, 20.0));
      if (const TrajectoryData* t = station_->latest(m.vehicle_id)) published[m.vehicle_id] = *t;
    }
    return published;
  }
  // Stops the daemon cleanly (its journal is checkpointed into the file) and makes sure no
  // write-ahead log is left beside it, so the file holds every record.
  void stopDaemonCleanly() {
    daemon_.signal(SIGTERM);
    ASSERT_EQ(daemon_.wait(30.0), 0) << daemon_.err();
    ChildProcess stopped = std::move(daemon_);
    station_.reset();
    sqlite3* db = nullptr;
    ASSERT_EQ(sqlite3_open(journalFile().c_str(), &db), SQLITE_OK);
    ASSERT_EQ(sqlite3_exec(db, "PRAGMA wal_checkpoint(TRUNCATE)", nullptr, nullptr, nullptr), SQLITE_OK);
    sqlite3_close(db);
  }
  // The rows of the journal's quarantine table as "table key" lines.
  std::vector<std::string> quarantineRows() const {
    std::vector<std::string> rows;
    sqlite3* db = nullptr;
    if (sqlite3_open_v2(journalFile().c_str(), &db, SQLITE_OPEN_READONLY, nullptr) == SQLITE_OK) {
      sqlite3_stmt* q = nullptr;
      if (sqlite3_prepare_v2(db, "SELECT source_table, record_key FROM quarantine ORDER BY id", -1, &q, nullptr) ==
          SQLITE_OK) {
        while (sqlite3_step(q) == SQLITE_ROW) {
          rows.push_back(std::string(reinterpret_cast<const char*>(sqlite3_column_text(q, 0))) + " " +
                         reinterpret_cast<const char*>(sqlite3_column_text(q, 1)));
        }
      }
      sqlite3_finalize(q);
    }
    sqlite3_close(db);
    return rows;
  }
  // Restarts the daemon on the journal with a new station, until it has recovered.
  void restartOnJournal(int domain) {
    startDaemon(domain, {"--state-dir", state_dir_});
    ASSERT_TRUE(waitForLog("event=recovered", 30.0)) << daemon_.err();
  }

  std::string state_dir_;
  bool mounted_ = false;
};

TEST_F(JournalFailuresE2E, ASecondDaemonOnTheStateFolderIsRefusedNamingTheHolderUntilItIsKilled) {
  startDaemon(50, {"--state-dir", state_dir_});
  ASSERT_TRUE(waitForLog("event=active", 30.0)) << daemon_.err();
  const std::string holder_instance = instanceOfDaemon();
  ASSERT_FALSE(holder_instance.empty()) << daemon_.err();

  // Another domain, so nothing but the folder is shared: the folder alone must refuse it.
  const Ran second = runToEnd({SKYROUTED, "--domain", "51", "--state-dir", state_dir_}, "skyrouted_second_51", 60.0);
  EXPECT_EQ(second.code, kExitStateDirLocked) << second.err;
  EXPECT_NE(second.err.find("in use by another skyrouted"), std::string::npos) << second.err;
  EXPECT_NE(second.err.find("pid=" + std::to_string(daemon_.pid())), std::string::npos) << second.err;
  EXPECT_NE(second.err.find("instance=" + holder_instance), std::string::npos) << second.err;
  EXPECT_NE(second.err.find((std::filesystem::path(state_dir_) / StateDirLock::kFileName).string()), std::string::npos)
      << second.err;
  EXPECT_EQ(second.err.find("event=active"), std::string::npos) << second.err;
  ASSERT_TRUE(daemon_.running()) << "the holder stopped: " << daemon_.err();

  // kill -9 frees the folder: the next daemon on it starts and serves.
  killDaemon();
  station_.reset();
  startDaemon(51, {"--state-dir", state_dir_});
  EXPECT_TRUE(waitForLog("event=active", 30.0)) << daemon_.err();
}

TEST_F(JournalFailuresE2E, OnAFullDiskOnlyWhatTheJournalStoredIsAcknowledgedOrPublishedAndSurvivesKill9) {
  std::string why;
  if (!mountSmallStateDir("2m", why)) {
    GTEST_SKIP() << "cannot mount a 2 MiB tmpfs on " << state_dir_ << " (" << why
                 << "): this test needs root with CAP_SYS_ADMIN to make a full disk";
  }
  startDaemon(52, {"--state-dir", state_dir_});
  // Requests until the disk is full: each answer is succeeded (then its trajectory is out) or a
  // refusal with journal_unavailable; two refusals in a row mean the disk stays full.
  std::vector<std::string> succeeded_vehicles;
  std::vector<std::string> refused_vehicles;
  std::map<std::string, TrajectoryData> published;  // vehicle -> its trajectory as the station got it
  int refusals_in_a_row = 0;
  for (int i = 0; i < 40 && refusals_in_a_row < 2; ++i) {
    const std::string id = "full-" + std::to_string(i);
    const std::string vehicle = "uav-f" + std::to_string(i);
    ASSERT_TRUE(station_->requests->write(simpleMission(id, vehicle, 0.0)).ok());
    ASSERT_TRUE(station_->waitTerminal({id}, 180.0)) << daemon_.err();
    const PlanStatusData answer = *station_->terminal(id);
    if (answer.state == PlanState::kSucceeded) {
      ASSERT_TRUE(station_->pumpUntil([&] { return station_->latest(vehicle) != nullptr; }, 20.0)) << vehicle;
      published[vehicle] = *station_->latest(vehicle);
      succeeded_vehicles.push_back(vehicle);
      refusals_in_a_row = 0;
      continue;
    }
    ASSERT_EQ(answer.state, PlanState::kFailed) << answer.message;
    EXPECT_EQ(answer.error_code, PlanErrorCode::kJournalUnavailable) << answer.message;
    EXPECT_EQ(answer.field, "service.state_dir") << answer.message;
    refused_vehicles.push_back(vehicle);
    ++refusals_in_a_row;
  }
  std::cout << "full disk: " << succeeded_vehicles.size() << " missions recorded, " << refused_vehicles.size()
            << " refused\n";
  ASSERT_FALSE(succeeded_vehicles.empty()) << daemon_.err();
  ASSERT_EQ(refusals_in_a_row, 2) << "the 2 MiB disk never filled: " << daemon_.err();
  auto beat = station_->freshHeartbeat(10.0);
  ASSERT_TRUE(beat);
  EXPECT_FALSE(beat->journal_ok) << "the heartbeat does not say the journal fails";
  EXPECT_NE(daemon_.err().find("event=journal_unavailable"), std::string::npos) << daemon_.err();

  // What flies keeps flying: an obstacle on the first vehicle's route 30 s ahead needs a new
  // revision, which cannot be recorded, so none is published and the requester is told.
  const TrajectoryData& first = published[succeeded_vehicles.front()];
  const std::int64_t ahead_ns = utcNowNs() + 30'000'000'000LL;
  const TrajectorySampleData* target = nullptr;
  for (const TrajectorySampleData& s : first.samples) {
    if (s.utc_ns >= ahead_ns) {
      target = &s;
      break;
    }
  }
  ASSERT_NE(target, nullptr) << "the flight ends within 30 s";
  ObstacleUpdateData blocking;
  blocking.obstacle.id = 52;
  blocking.obstacle.size_m = Eigen::Vector3d::Constant(250.0);
  blocking.obstacle.center_m = target->position_enu_m;
  blocking.valid_from_utc_ns = utcNowNs();
  ASSERT_TRUE(station_->obstacles->waitForReaders(1, 20.0).ok());
  ASSERT_TRUE(station_->obstacles->write(blocking).ok());
  const auto told = [&] {
    return std::any_of(station_->status_log.begin(), station_->status_log.end(), [&](const PlanStatusData& s) {
      return s.request_id == first.request_id && s.error_code == PlanErrorCode::kJournalUnavailable &&
             !isTerminal(s.state);
    });
  };
  ASSERT_TRUE(station_->pumpUntil(told, 60.0)) << daemon_.err();
  EXPECT_NE(daemon_.err().find("event=revision_not_journaled request=" + first.request_id), std::string::npos)
      << daemon_.err();
  ASSERT_TRUE(station_->freshHeartbeat(10.0));  // what was written before the answer has arrived
  EXPECT_EQ(station_->lastReceived(first.vehicle_id)->revision, first.revision)
      << "a revision the journal could not record was published";
  for (const std::string& vehicle : refused_vehicles) {
    EXPECT_EQ(station_->latest(vehicle), nullptr) << "a refused request's trajectory was published: " << vehicle;
  }

  // kill -9 and a restart on the same, still full, folder: every acknowledged vehicle is back
  // with the revision and samples published, and nothing refused is.
  killDaemon();
  station_.reset();
  startDaemon(52, {"--state-dir", state_dir_});
  ASSERT_TRUE(station_->pumpUntil(
      [&] {
        return std::all_of(succeeded_vehicles.begin(), succeeded_vehicles.end(),
                           [&](const std::string& v) { return station_->latest(v) != nullptr; });
      },
      30.0))
      << daemon_.err();
  for (const std::string& vehicle : succeeded_vehicles) {
    const TrajectoryData& before = published[vehicle];
    const TrajectoryData& after = *station_->latest(vehicle);
    EXPECT_EQ(after.plan_id, before.plan_id) << vehicle;
    EXPECT_EQ(after.revision, before.revision) << vehicle;
    EXPECT_TRUE(sameSamples(after, before)) << vehicle << ": the republished samples differ";
  }
  for (const std::string& vehicle : refused_vehicles) {
    EXPECT_EQ(station_->latest(vehicle), nullptr) << "a refused request came back: " << vehicle;
  }
  // The disk is still full: new work is refused, typed.
  ASSERT_TRUE(station_->requests->write(simpleMission("after-restart", "uav-after", 0.0)).ok());
  ASSERT_TRUE(station_->waitTerminal({"after-restart"}, 60.0)) << daemon_.err();
  EXPECT_EQ(station_->terminal("after-restart")->error_code, PlanErrorCode::kJournalUnavailable)
      << station_->terminal("after-restart")->message;
}

TEST_F(JournalFailuresE2E, AFlippedByteInARecordIsQuarantinedAndNeverRepublished) {
  startDaemon(54, {"--state-dir", state_dir_});
  std::map<std::string, TrajectoryData> published =
      fly({simpleMission("hurt", "uav-hurt", 0.0), simpleMission("whole", "uav-whole", 1500.0)});
  ASSERT_EQ(published.size(), 2u);
  stopDaemonCleanly();

  // Twenty bytes flipped in the file: one in the latitude of each of twenty samples of one vehicle
  // (found in the file by their bits), enough for jumps of hundreds of metres.
  std::string bytes;
  {
    std::ifstream in(journalFile(), std::ios::binary);
    bytes.assign(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
  }
  const TrajectoryData& hurt = published["uav-hurt"];
  ASSERT_GT(hurt.samples.size(), 140u);
  int flipped = 0;
  for (std::size_t i = 100; i < 120; ++i) {
    char lat[sizeof(double)];
    std::memcpy(lat, &hurt.samples[i].geo.lat_deg, sizeof lat);
    const std::size_t at = bytes.find(std::string(lat, sizeof lat));
    ASSERT_NE(at, std::string::npos) << "sample " << i << "'s latitude is not in the file as published";
    bytes[at + 4] = static_cast<char>(bytes[at + 4] ^ 0x80);  // some 430 m north or south
    ++flipped;
  }
  ASSERT_EQ(flipped, 20);
  std::ofstream(journalFile(), std::ios::binary | std::ios::trunc) << bytes;

  restartOnJournal(54);
  ASSERT_TRUE(station_->pumpUntil([&] { return station_->latest("uav-whole") != nullptr; }, 20.0)) << daemon_.err();
  EXPECT_TRUE(sameTrajectory(*station_->latest("uav-whole"), published["uav-whole"]));
  ASSERT_TRUE(station_->freshHeartbeat(10.0));
  EXPECT_EQ(station_->latest("uav-hurt"), nullptr) << "the damaged trajectory was republished";
  EXPECT_NE(daemon_.err().find("event=journal_record_quarantined table=trajectories key=\"uav-hurt\" reason=\"checksum"),
            std::string::npos)
      << daemon_.err();
  EXPECT_NE(daemon_.err().find("event=journal_record_quarantined table=missions key=\"uav-hurt/hurt\""),
            std::string::npos)
      << daemon_.err();
  const std::vector<std::string> kept = quarantineRows();
  EXPECT_NE(std::find(kept.begin(), kept.end(), "trajectories [\"uav-hurt\"]"), kept.end()) << ::testing::PrintToString(kept);
}

TEST_F(JournalFailuresE2E, AnEmptyJournalIsRefusedNamingTheFile) {
  std::filesystem::create_directories(state_dir_);
  std::ofstream(journalFile()).close();
  const Ran ran = runToEnd({SKYROUTED, "--domain", "55", "--state-dir", state_dir_}, "skyrouted_empty_55", 30.0);
  EXPECT_EQ(ran.code, 3) << ran.err;
  EXPECT_NE(ran.err.find(journalFile().string() + " is empty (0 bytes)"), std::string::npos) << ran.err;
  EXPECT_EQ(ran.err.find("event=active"), std::string::npos) << ran.err;
}

TEST_F(JournalFailuresE2E, ARecordRefusedTodayIsQuarantinedAndTheRestResumes) {
  startDaemon(56, {"--state-dir", state_dir_});
  std::map<std::string, TrajectoryData> published = fly({simpleMission("good", "uav-good", 0.0)});
  ASSERT_EQ(published.size(), 1u);
  stopDaemonCleanly();

  // A mission no request could bring in today (more points than the bound of 64), flying, as an
  // older or laxer skyrouted would have journaled it.
  MissionRequestData bad = simpleMission("bad-1", "uav-bad", 1500.0);
  bad.points.clear();
  for (int i = 0; i < 70; ++i) bad.points.push_back(above(-3500 + 100 * i, 1700, 400));
  TrajectoryData bad_flight = published["uav-good"];
  bad_flight.vehicle_id = "uav-bad";
  bad_flight.request_id = "bad-1";
  bad_flight.plan_id = "uav-bad-9";
  {
    auto journal = StateJournal::open(state_dir_);
    ASSERT_TRUE(journal.ok()) << journal.error().describe();
    ASSERT_TRUE((*journal)->recordAccepted(bad, utcNowNs()).ok());
    ASSERT_TRUE((*journal)->recordTrajectory(bad_flight, utcNowNs()).ok());
  }

  restartOnJournal(56);
  ASSERT_TRUE(station_->pumpUntil([&] { return station_->latest("uav-good") != nullptr; }, 20.0)) << daemon_.err();
  EXPECT_TRUE(sameTrajectory(*station_->latest("uav-good"), published["uav-good"]));
  ASSERT_TRUE(waitForLog("event=flight_resumed request=good", 60.0)) << daemon_.err();
  ASSERT_TRUE(station_->freshHeartbeat(10.0));
  EXPECT_EQ(station_->latest("uav-bad"), nullptr) << "the refused mission's trajectory was republished";
  EXPECT_NE(daemon_.err().find("event=journal_record_quarantined table=missions key=\"uav-bad/bad-1\" reason=\"refused "
                               "today: mission_too_large points"),
            std::string::npos)
      << daemon_.err();
  EXPECT_NE(daemon_.err().find("event=journal_record_quarantined table=trajectories key=\"uav-bad\""), std::string::npos)
      << daemon_.err();
  EXPECT_EQ(daemon_.err().find("request=bad-1"), std::string::npos) << "the refused mission was planned: " << daemon_.err();
  const std::vector<std::string> kept = quarantineRows();
  EXPECT_NE(std::find(kept.begin(), kept.end(), "missions [\"uav-bad\",\"bad-1\"]"), kept.end())
      << ::testing::PrintToString(kept);
  // It serves: a new request is planned.
  ASSERT_TRUE(station_->requests->write(simpleMission("after", "uav-after", -1500.0)).ok());
  ASSERT_TRUE(station_->waitTerminal({"after"}, 180.0)) << daemon_.err();
  EXPECT_EQ(station_->terminal("after")->state, PlanState::kSucceeded) << station_->terminal("after")->message;
}

// The record that crash-looped the daemon (issue 29): a mission whose vehicle id has 70,000
// characters, journaled before the id had a bound. The ROS 2 mirror made a topic name of it and
// libddsc crashed, at every restart on the folder. Now it is quarantined, named by a cut key, and
// the daemon serves, its mirror on.
TEST_F(JournalFailuresE2E, AJournaledVehicleIdOf70000CharactersIsQuarantinedAndTheDaemonServes) {
  startDaemon(57, {"--state-dir", state_dir_});
  std::map<std::string, TrajectoryData> published = fly({simpleMission("good", "uav-good", 0.0)});
  ASSERT_EQ(published.size(), 1u);
  stopDaemonCleanly();

  const std::string huge_id(70000, 'v');
  MissionRequestData bad = simpleMission("huge-1", huge_id, 1500.0);
  TrajectoryData bad_flight = published["uav-good"];
  bad_flight.vehicle_id = huge_id;
  bad_flight.request_id = "huge-1";
  bad_flight.plan_id = "huge-9";
  {
    auto journal = StateJournal::open(state_dir_);
    ASSERT_TRUE(journal.ok()) << journal.error().describe();
    ASSERT_TRUE((*journal)->recordAccepted(bad, utcNowNs()).ok());
    ASSERT_TRUE((*journal)->recordTrajectory(bad_flight, utcNowNs()).ok());
  }

  restartOnJournal(57);
  ASSERT_TRUE(station_->pumpUntil([&] { return station_->latest("uav-good") != nullptr; }, 20.0)) << daemon_.err();
  ASSERT_TRUE(waitForLog("event=flight_resumed request=good", 60.0)) << daemon_.err().substr(0, 4000);
  ASSERT_TRUE(station_->freshHeartbeat(10.0));
  EXPECT_EQ(station_->latest(huge_id), nullptr) << "the refused mission's trajectory was republished";
  EXPECT_NE(daemon_.err().find("event=journal_record_quarantined table=missions key=\"vvvv"), std::string::npos)
      << daemon_.err().substr(0, 4000);
  EXPECT_NE(daemon_.err().find("vehicle_id has 70000 characters, more than the limit of 64"), std::string::npos)
      << daemon_.err().substr(0, 4000);
  EXPECT_EQ(daemon_.err().find(std::string(1000, 'v')), std::string::npos) << "a log line holds the whole id";
  // It serves, its ROS 2 mirror too: a new request is planned and published.
  ASSERT_TRUE(station_->requests->write(simpleMission("after", "uav-after", -1500.0)).ok());
  ASSERT_TRUE(station_->waitTerminal({"after"}, 180.0)) << daemon_.err().substr(0, 4000);
  EXPECT_EQ(station_->terminal("after")->state, PlanState::kSucceeded) << station_->terminal("after")->message;
  EXPECT_TRUE(daemon_.running());
}

}  // namespace
}  // namespace skyroute::testing
