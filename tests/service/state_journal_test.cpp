// The state journal on its own: trajectories come back bit for bit, a mission's rows follow it
// (accepted, flying, replaced, finished), what ended is pruned, a version-1 journal written by
// hand is migrated, and a damaged, foreign or newer file is refused naming the file. A shard's
// copies of the requests it read and its lives come back, bounded. The cost of recording one
// revision is measured.
#include <gtest/gtest.h>

#include <sqlite3.h>

#include <chrono>
#include <cmath>
#include <fstream>
#include <iostream>

#include "service/journal_codec.hpp"
#include "service/journal_schema.hpp"
#include "service/state_journal.hpp"
#include "tests/same_trajectory.hpp"
#include "tests/test_folder.hpp"

namespace skyroute {
namespace {

constexpr std::int64_t kNowNs = 1'800'000'000'000'000'000LL;

// A trajectory of `count` samples 0.2 s apart from kNowNs, with numbers that have no short
// decimal form (so a text round trip would show).
TrajectoryData trajectory(const std::string& vehicle, const std::string& plan_id, std::uint32_t revision,
                          const std::string& request_id, std::size_t count, double start_offset_s = 0.0) {
  TrajectoryData t;
  t.vehicle_id = vehicle;
  t.plan_id = plan_id;
  t.revision = revision;
  t.request_id = request_id;
  t.created_utc_ns = kNowNs + 17;
  t.visiting_order = {0, 2, 1, 3};
  t.legs = {{0, 2, 0.0, 10.0 / 3.0}, {2, 1, 10.0 / 3.0, 7.1}, {1, 3, 7.1, std::sqrt(90.0)}};
  for (std::size_t i = 0; i < count; ++i) {
    TrajectorySampleData s;
    const double k = static_cast<double>(i);
    s.t_rel_s = 0.2 * k;
    s.utc_ns = kNowNs + static_cast<std::int64_t>((start_offset_s + 0.2 * k) * 1e9);
    s.position_enu_m = Eigen::Vector3d(k / 3.0, -k / 7.0, 100.0 + std::sin(k));
    s.velocity_enu_mps = Eigen::Vector3d(1.0 / 3.0, std::cos(k), 0.1 * k);
    s.acceleration_enu_mps2 = Eigen::Vector3d(std::exp(-k), 0.0, -1e-300);
    s.heading_deg = std::fmod(k * 1.1, 360.0);
    s.geo = GeoPoint{44.1 + k * 1e-7, -71.9 - k * 1e-7, 300.0 + k / 9.0};
    t.samples.push_back(s);
  }
  return t;
}

void expectSameTrajectory(const TrajectoryData& a, const TrajectoryData& b) {
  EXPECT_TRUE(testing::sameTrajectory(a, b)) << "trajectory of " << a.vehicle_id << " revision " << a.revision
                                              << " differs from " << b.vehicle_id << " revision " << b.revision;
}

MissionRequestData mission(const std::string& id, const std::string& vehicle) {
  MissionRequestData r;
  r.request_id = id;
  r.vehicle_id = vehicle;
  r.begin = MissionPointData::wgs84(44.1, -71.9, 500.0);
  r.points = {MissionPointData::enu(Eigen::Vector3d(100.0 / 3.0, -250.5, 420.25))};
  r.end = MissionPointData::wgs84(44.2, -71.8, 510.0);
  r.limits.v_ref_mps = 17.5;
  r.planner = "rrt_star";
  r.fixed_order = true;
  return r;
}

ObstacleUpdateData sphere(std::uint64_t id, std::int64_t valid_until_utc_ns) {
  ObstacleUpdateData u;
  u.obstacle.id = id;
  u.obstacle.shape = ObstacleShape::kSphere;
  u.obstacle.size_m = Eigen::Vector3d::Constant(120.0);
  u.obstacle.center_m = Eigen::Vector3d(10.0, 20.0 / 3.0, 300.0);
  u.valid_from_utc_ns = kNowNs - 1'000'000'000;
  u.valid_until_utc_ns = valid_until_utc_ns;
  return u;
}

// Runs SQL on a file directly (as another program, or an older skyrouted, would have).
void runSql(const std::filesystem::path& file, const std::string& sql) {
  sqlite3* db = nullptr;
  ASSERT_EQ(sqlite3_open(file.c_str(), &db), SQLITE_OK);
  char* message = nullptr;
  const int rc = sqlite3_exec(db, sql.c_str(), nullptr, nullptr, &message);
  const std::string text = message ? message : "";
  sqlite3_free(message);
  sqlite3_close(db);
  ASSERT_EQ(rc, SQLITE_OK) << text;
}

class StateJournalTest : public testing::TestFolderTest {
 protected:
  StateJournalTest() : TestFolderTest("state_journal_") {}
  std::unique_ptr<StateJournal> open() {
    auto journal = StateJournal::open(dir_.string());
    EXPECT_TRUE(journal.ok()) << journal.error().describe();
    return journal.ok() ? std::move(*journal) : nullptr;
  }
  std::filesystem::path file() const { return dir_ / StateJournal::kFileName; }
  // The refusal of opening the journal file (which must fail).
  Error refusal() {
    auto journal = StateJournal::open(dir_.string());
    EXPECT_FALSE(journal.ok());
    return journal.ok() ? Error{} : journal.error();
  }
};

TEST(JournalCodecTest, TrajectoryRecordRoundTripsBitForBitAndRefusesCutRecords) {
  const TrajectoryData t = trajectory("uav-1", "uav-1-3", 4, "m1", 257);
  const std::string bytes = encodeTrajectory(t);
  auto back = decodeTrajectory(bytes);
  ASSERT_TRUE(back.ok()) << back.error().describe();
  expectSameTrajectory(t, *back);

  for (std::size_t cut : {std::size_t{0}, std::size_t{3}, bytes.size() / 2, bytes.size() - 1}) {
    auto cut_back = decodeTrajectory(bytes.substr(0, cut));
    ASSERT_FALSE(cut_back.ok()) << "cut at " << cut;
    EXPECT_NE(cut_back.error().message.find("trajectory"), std::string::npos);
  }
  EXPECT_FALSE(decodeTrajectory(bytes + "x").ok());
  std::string wrong_count = bytes;
  wrong_count[8 + 4 + 5] = '\x7f';  // the vehicle id's length byte: far longer than the record
  EXPECT_FALSE(decodeTrajectory(wrong_count).ok());
}

TEST(JournalCodecTest, ZoneObstacleAndFleetRoundTrip) {
  NoFlyZoneData zone;
  zone.zone_id = "tower";
  zone.ring = {{44.1, -71.9, 0.0}, {44.1 + 1.0 / 3.0, -71.9, 0.0}, {44.2, -71.8, 0.0}};
  zone.floor_amsl_m = 12.5;
  zone.ceiling_amsl_m = 800.0 / 3.0;
  zone.valid_until_utc_ns = kNowNs + 5;
  auto z = noFlyZoneFromJson(nlohmann::json::parse(noFlyZoneToJson(zone).dump()));
  ASSERT_TRUE(z.ok()) << z.error().describe();
  EXPECT_EQ(z->zone_id, "tower");
  ASSERT_EQ(z->ring.size(), 3u);
  EXPECT_EQ(z->ring[1].lat_deg, zone.ring[1].lat_deg);
  EXPECT_EQ(z->ceiling_amsl_m, zone.ceiling_amsl_m);
  EXPECT_EQ(z->valid_until_utc_ns, zone.valid_until_utc_ns);

  const ObstacleUpdateData u = sphere(9, kNowNs + 99);
  auto o = obstacleRecordFromJson(nlohmann::json::parse(obstacleRecordToJson(u).dump()));
  ASSERT_TRUE(o.ok()) << o.error().describe();
  EXPECT_EQ(o->obstacle.id, 9u);
  EXPECT_EQ(o->obstacle.center_m, u.obstacle.center_m);
  EXPECT_EQ(o->valid_from_utc_ns, u.valid_from_utc_ns);
  EXPECT_EQ(o->valid_until_utc_ns, u.valid_until_utc_ns);

  FleetStatusData f;
  f.request_id = "fleet-1";
  f.state = PlanState::kSucceeded;
  f.allocation = {{"uav-1", {2, 0}, 0.0}, {"uav-2", {1}, 1.0 / 3.0}};
  f.makespan_s = 123.25;
  auto fb = fleetStatusFromJson(nlohmann::json::parse(fleetStatusToJson(f).dump()));
  ASSERT_TRUE(fb.ok()) << fb.error().describe();
  ASSERT_EQ(fb->allocation.size(), 2u);
  EXPECT_EQ(fb->allocation[0].tasks, (std::vector<std::uint32_t>{2, 0}));
  EXPECT_EQ(fb->allocation[1].delay_s, 1.0 / 3.0);
  EXPECT_EQ(fb->state, PlanState::kSucceeded);
  EXPECT_FALSE(noFlyZoneFromJson(nlohmann::json{{"zone_id", "x"}}).ok());
}

TEST_F(StateJournalTest, EverythingRecordedComesBackAfterReopening) {
  const TrajectoryData t1 = trajectory("uav-1", "uav-1-1", 0, "m1", 300);
  const TrajectoryData t2 = trajectory("uav-2", "uav-2-7", 3, "m2", 300);
  {
    auto journal = open();
    ASSERT_TRUE(journal);
    EXPECT_EQ(journal->foundSchemaVersion(), 0);
    ASSERT_TRUE(journal->recordAccepted(mission("m1", "uav-1"), kNowNs).ok());
    ASSERT_TRUE(journal->recordAccepted(mission("m2", "uav-2"), kNowNs + 1).ok());
    ASSERT_TRUE(journal->recordAccepted(mission("m3", "uav-3"), kNowNs + 2).ok());
    ASSERT_TRUE(journal->recordTrajectory(t1, kNowNs).ok());
    ASSERT_TRUE(journal->recordTrajectory(trajectory("uav-2", "uav-2-7", 0, "m2", 300), kNowNs).ok());
    ASSERT_TRUE(journal->recordTrajectory(t2, kNowNs).ok());
    ASSERT_TRUE(journal->recordObstacle(sphere(5, 0)).ok());
    NoFlyZoneData zone;
    zone.zone_id = "tower";
    zone.ring = {{44.1, -71.9, 0.0}, {44.11, -71.9, 0.0}, {44.11, -71.89, 0.0}};
    zone.ceiling_amsl_m = 900.0;
    ASSERT_TRUE(journal->recordNoFlyZone(zone).ok());
    ASSERT_TRUE(journal->recordOwner("0000000000000123").ok());  // digits only: kept as text
    EXPECT_EQ(journal->writeStats().writes, 9u);
  }
  auto journal = open();
  ASSERT_TRUE(journal);
  EXPECT_EQ(journal->foundSchemaVersion(), kJournalSchemaVersion);
  auto state = journal->load(kNowNs + 1'000'000'000);
  ASSERT_TRUE(state.ok()) << state.error().describe();
  ASSERT_EQ(state->missions.size(), 3u);
  EXPECT_EQ(state->missions[0].request.request_id, "m1");
  EXPECT_TRUE(state->missions[0].flying);
  EXPECT_TRUE(state->missions[1].flying);
  EXPECT_FALSE(state->missions[2].flying);  // accepted, never planned
  const MissionRequestData& m = state->missions[0].request;
  EXPECT_EQ(m.points[0].enu_m, mission("m1", "uav-1").points[0].enu_m);
  EXPECT_EQ(m.limits.v_ref_mps, 17.5);
  EXPECT_TRUE(m.fixed_order);
  EXPECT_EQ(m.planner, "rrt_star");
  ASSERT_EQ(state->trajectories.size(), 2u);
  expectSameTrajectory(state->trajectories[0], t1);
  expectSameTrajectory(state->trajectories[1], t2);  // the current revision, not the first
  ASSERT_EQ(state->obstacles.size(), 1u);
  EXPECT_EQ(state->obstacles[0].obstacle.center_m, sphere(5, 0).obstacle.center_m);
  ASSERT_EQ(state->zones.size(), 1u);
  EXPECT_EQ(state->zones[0].zone_id, "tower");
  EXPECT_EQ(state->plan_counter, 7u);
  EXPECT_EQ(state->owner_instance_id, "0000000000000123");
}

TEST_F(StateJournalTest, MissionRowsFollowTheirMission) {
  auto journal = open();
  ASSERT_TRUE(journal);
  ASSERT_TRUE(journal->recordAccepted(mission("a", "uav-1"), kNowNs).ok());
  ASSERT_TRUE(journal->recordTrajectory(trajectory("uav-1", "uav-1-1", 0, "a", 50), kNowNs).ok());
  ASSERT_TRUE(journal->recordAccepted(mission("b", "uav-1"), kNowNs + 1).ok());  // queued behind a
  ASSERT_TRUE(journal->recordAccepted(mission("c", "uav-1"), kNowNs + 2).ok());
  ASSERT_TRUE(journal->recordFinished("uav-1", "c").ok());  // failed or cancelled
  auto state = journal->load(kNowNs);
  ASSERT_TRUE(state.ok());
  ASSERT_EQ(state->missions.size(), 2u);
  EXPECT_EQ(state->missions[1].request.request_id, "b");

  // b's plan replaces a: a has ended, b flies.
  ASSERT_TRUE(journal->recordTrajectory(trajectory("uav-1", "uav-1-2", 0, "b", 50), kNowNs).ok());
  state = journal->load(kNowNs);
  ASSERT_TRUE(state.ok());
  ASSERT_EQ(state->missions.size(), 1u);
  EXPECT_EQ(state->missions[0].request.request_id, "b");
  EXPECT_TRUE(state->missions[0].flying);

  // Cancelled while flying: its trajectory retracted and the request finished.
  ASSERT_TRUE(journal->recordRetracted("uav-1").ok());
  ASSERT_TRUE(journal->recordFinished("uav-1", "b").ok());
  state = journal->load(kNowNs);
  ASSERT_TRUE(state.ok());
  EXPECT_TRUE(state->missions.empty());
  EXPECT_TRUE(state->trajectories.empty());
  EXPECT_EQ(state->plan_counter, 2u);  // plan numbers are never given twice
}

TEST_F(StateJournalTest, WhatEndedIsPruned) {
  auto journal = open();
  ASSERT_TRUE(journal);
  // 20 samples 0.2 s apart: uav-1's trajectory ends 3.8 s after kNowNs; uav-2's an hour later.
  ASSERT_TRUE(journal->recordAccepted(mission("short", "uav-1"), kNowNs).ok());
  ASSERT_TRUE(journal->recordTrajectory(trajectory("uav-1", "uav-1-1", 0, "short", 20), kNowNs).ok());
  ASSERT_TRUE(journal->recordAccepted(mission("long", "uav-2"), kNowNs).ok());
  ASSERT_TRUE(journal->recordTrajectory(trajectory("uav-2", "uav-2-2", 0, "long", 20, 3600.0), kNowNs).ok());
  FleetStatusData fleet;
  fleet.request_id = "short";  // a fleet whose only trajectory is uav-1's
  fleet.state = PlanState::kSucceeded;
  ASSERT_TRUE(journal->recordFleet(fleet).ok());
  ASSERT_TRUE(journal->recordObstacle(sphere(1, kNowNs + 2'000'000'000)).ok());
  ASSERT_TRUE(journal->recordObstacle(sphere(2, 0)).ok());  // until removed
  ASSERT_TRUE(journal->recordObstacle(sphere(3, 0)).ok());
  ObstacleUpdateData removal;
  removal.obstacle.id = 3;
  removal.remove = true;
  ASSERT_TRUE(journal->recordObstacle(removal).ok());

  auto before = journal->load(kNowNs + 1'000'000'000);
  ASSERT_TRUE(before.ok());
  EXPECT_EQ(before->trajectories.size(), 2u);
  EXPECT_EQ(before->fleets.size(), 1u);
  EXPECT_EQ(before->obstacles.size(), 2u);

  auto after = journal->load(kNowNs + 10'000'000'000);
  ASSERT_TRUE(after.ok());
  ASSERT_EQ(after->trajectories.size(), 1u);
  EXPECT_EQ(after->trajectories[0].vehicle_id, "uav-2");
  ASSERT_EQ(after->missions.size(), 1u);
  EXPECT_EQ(after->missions[0].request.request_id, "long");
  EXPECT_TRUE(after->fleets.empty());
  ASSERT_EQ(after->obstacles.size(), 1u);
  EXPECT_EQ(after->obstacles[0].obstacle.id, 2u);
}

TEST_F(StateJournalTest, VersionOneJournalWrittenByHandIsMigrated) {
  const TrajectoryData t = trajectory("uav-1", "uav-1-4", 2, "old", 30);
  const std::string record = encodeTrajectory(t);
  std::string hex;
  for (unsigned char c : record) {
    static const char* digits = "0123456789abcdef";
    hex += digits[c >> 4];
    hex += digits[c & 15];
  }
  const std::string request_json = R"({"request_id":"old","vehicle_id":"uav-1","begin":{"east_m":0,"north_m":0,"up_m":400},)"
                                   R"("points":[],"end":{"east_m":900,"north_m":100,"up_m":420}})";
  const std::string obstacle_json = obstacleRecordToJson(sphere(8, kNowNs + 3'000'000'000)).dump();
  // Version 1's schema as an older skyrouted wrote it.
  runSql(file(), "CREATE TABLE schema_version(version INTEGER NOT NULL); INSERT INTO schema_version VALUES (1);"
                 "CREATE TABLE missions(vehicle_id TEXT NOT NULL, request_id TEXT NOT NULL, request_json TEXT NOT NULL,"
                 " state TEXT NOT NULL, PRIMARY KEY(vehicle_id, request_id));"
                 "CREATE TABLE trajectories(vehicle_id TEXT PRIMARY KEY, plan_id TEXT NOT NULL, revision INTEGER NOT NULL,"
                 " request_id TEXT NOT NULL, record BLOB NOT NULL);"
                 "CREATE TABLE obstacles(obstacle_id INTEGER PRIMARY KEY, update_json TEXT NOT NULL);"
                 "INSERT INTO missions VALUES ('uav-1', 'old', '" + request_json + "', 'flying');"
                 "INSERT INTO trajectories VALUES ('uav-1', 'uav-1-4', 2, 'old', x'" + hex + "');"
                 "INSERT INTO obstacles VALUES (8, '" + obstacle_json + "');");
  {
    auto journal = open();
    ASSERT_TRUE(journal);
    EXPECT_EQ(journal->foundSchemaVersion(), 1);
    auto state = journal->load(kNowNs);
    ASSERT_TRUE(state.ok()) << state.error().describe();
    ASSERT_EQ(state->missions.size(), 1u);
    EXPECT_TRUE(state->missions[0].flying);
    EXPECT_EQ(state->missions[0].request.end.enu_m, Eigen::Vector3d(900, 100, 420));
    ASSERT_EQ(state->trajectories.size(), 1u);
    expectSameTrajectory(state->trajectories[0], t);
    EXPECT_EQ(state->plan_counter, 4u);  // from the plan ids: version 1 kept no counter
    ASSERT_EQ(state->obstacles.size(), 1u);
    // The new tables work.
    NoFlyZoneData zone;
    zone.zone_id = "z";
    zone.ring = {{44.1, -71.9, 0.0}, {44.11, -71.9, 0.0}, {44.11, -71.89, 0.0}};
    ASSERT_TRUE(journal->recordNoFlyZone(zone).ok());
    // The migrated ends are real: after the trajectory's end (5.8 s) and the obstacle's (3 s) both go.
    auto later = journal->load(kNowNs + 6'000'000'000);
    ASSERT_TRUE(later.ok());
    EXPECT_TRUE(later->trajectories.empty());
    EXPECT_TRUE(later->missions.empty());
    EXPECT_TRUE(later->obstacles.empty());
    EXPECT_EQ(later->zones.size(), 1u);
  }
  auto reopened = open();
  ASSERT_TRUE(reopened);
  EXPECT_EQ(reopened->foundSchemaVersion(), kJournalSchemaVersion);
}

TEST_F(StateJournalTest, AShardsCopiesOfRequestsAndItsLivesComeBackBounded) {
  FleetRequestData fleet;
  fleet.request_id = "fleet-1";
  fleet.vehicle_ids = {"f-1", "f-2"};
  fleet.begins = {MissionPointData::wgs84(44.1, -71.9, 500.0), MissionPointData::enu(Eigen::Vector3d(1.0 / 3.0, 2, 3))};
  fleet.ends = fleet.begins;
  fleet.tasks = {MissionPointData::enu(Eigen::Vector3d(10, 20.5, 300))};
  fleet.planner = "rrt_star";
  {
    auto journal = open();
    ASSERT_TRUE(journal);
    const auto copy = [](const std::string& key, std::int64_t seen, std::optional<MissionRequestData> m,
                         std::optional<FleetRequestData> f) { return JournaledRequest{key, seen, std::move(m), std::move(f)}; };
    ASSERT_TRUE(journal->recordShardRequest(copy("vehicle:uav-1", kNowNs + 3, mission("old", "uav-1"), std::nullopt)).ok());
    ASSERT_TRUE(journal->recordShardRequest(copy("vehicle:uav-2", kNowNs + 2, mission("two", "uav-2"), std::nullopt)).ok());
    ASSERT_TRUE(journal->recordShardRequest(copy("vehicle:uav-3", kNowNs + 4, mission("three", "uav-3"), std::nullopt)).ok());
    ASSERT_TRUE(journal->recordShardRequest(copy("fleet:fleet-1", kNowNs + 5, std::nullopt, fleet)).ok());
    ASSERT_TRUE(journal->recordShardRequest(copy("fleet:fleet-0", kNowNs + 1, std::nullopt, fleet)).ok());
    // The vehicle's newer request replaces its copy; a cancel and a dropped fleet forget theirs.
    ASSERT_TRUE(journal->recordShardRequest(copy("vehicle:uav-1", kNowNs + 6, mission("new", "uav-1"), std::nullopt)).ok());
    ASSERT_TRUE(journal->forgetShardMission("", "three").ok());
    ASSERT_TRUE(journal->forgetShardMission("uav-2", "not-its-request").ok());
    ASSERT_TRUE(journal->forgetShardRequests({"fleet:fleet-0"}).ok());
    // Seven lives: the newest kMaxPastCoverage + 1 are kept.
    for (std::int64_t life = 1; life <= 7; ++life) {
      ASSERT_TRUE(journal->beginShardLife(life * 100).ok());
      ASSERT_TRUE(journal->recordShardCoverage(life * 100, life * 100 + 50).ok());
      ASSERT_TRUE(journal->recordShardCoverage(life * 100, life * 100 + 40).ok()) << "coverage never goes back";
    }
  }
  auto journal = open();
  ASSERT_TRUE(journal);
  auto state = journal->load(kNowNs);
  ASSERT_TRUE(state.ok()) << state.error().describe();
  ASSERT_EQ(state->shard_requests.size(), 3u);
  // In the order they arrived: uav-2 (2), the fleet (5), uav-1's newer request (6).
  EXPECT_EQ(state->shard_requests[0].key, "vehicle:uav-2");
  EXPECT_EQ(state->shard_requests[0].seen_utc_ns, kNowNs + 2);
  ASSERT_TRUE(state->shard_requests[0].mission);
  EXPECT_EQ(state->shard_requests[0].mission->request_id, "two");
  EXPECT_EQ(state->shard_requests[0].mission->points[0].enu_m, Eigen::Vector3d(100.0 / 3.0, -250.5, 420.25));
  EXPECT_EQ(state->shard_requests[0].mission->limits.v_ref_mps, 17.5);
  EXPECT_EQ(state->shard_requests[1].key, "fleet:fleet-1");
  ASSERT_TRUE(state->shard_requests[1].fleet);
  EXPECT_FALSE(state->shard_requests[1].mission);
  EXPECT_EQ(state->shard_requests[1].fleet->vehicle_ids, fleet.vehicle_ids);
  EXPECT_EQ(state->shard_requests[1].fleet->begins[1].enu_m, Eigen::Vector3d(1.0 / 3.0, 2, 3));
  EXPECT_EQ(state->shard_requests[2].key, "vehicle:uav-1");
  EXPECT_EQ(state->shard_requests[2].mission->request_id, "new");
  EXPECT_EQ(state->shard_requests[2].mission->vehicle_id, "uav-1");
  ASSERT_EQ(state->shard_lives.size(), kMaxPastCoverage + 1);
  for (std::size_t i = 0; i < state->shard_lives.size(); ++i) {
    const auto life = static_cast<std::int64_t>(i + 3) * 100;
    EXPECT_EQ(state->shard_lives[i], (CoverageInterval{life, life + 50}));
  }
}

TEST_F(StateJournalTest, VersionTwoJournalIsMigratedAndKeepsItsRows) {
  {
    auto journal = open();
    ASSERT_TRUE(journal);
    ASSERT_TRUE(journal->recordAccepted(mission("kept", "uav-1"), kNowNs).ok());
  }
  // What a version-2 skyrouted wrote: no shard tables.
  runSql(file(), "DROP TABLE shard_requests; DROP TABLE shard_lives; UPDATE schema_version SET version = 2;");
  {
    auto journal = open();
    ASSERT_TRUE(journal);
    EXPECT_EQ(journal->foundSchemaVersion(), 2);
    auto state = journal->load(kNowNs);
    ASSERT_TRUE(state.ok()) << state.error().describe();
    ASSERT_EQ(state->missions.size(), 1u);
    EXPECT_TRUE(state->shard_requests.empty());
    EXPECT_TRUE(state->shard_lives.empty());
    ASSERT_TRUE(journal->recordShardRequest(JournaledRequest{"vehicle:uav-1", kNowNs, mission("kept", "uav-1"), std::nullopt}).ok());
    ASSERT_TRUE(journal->beginShardLife(kNowNs).ok());
  }
  auto journal = open();
  ASSERT_TRUE(journal);
  EXPECT_EQ(journal->foundSchemaVersion(), kJournalSchemaVersion);
  auto state = journal->load(kNowNs);
  ASSERT_TRUE(state.ok());
  EXPECT_EQ(state->shard_requests.size(), 1u);
  EXPECT_EQ(state->shard_lives.size(), 1u);
}

TEST_F(StateJournalTest, NewerSchemaIsRefusedNamingTheFileAndTheVersion) {
  runSql(file(), "CREATE TABLE schema_version(version INTEGER NOT NULL); INSERT INTO schema_version VALUES (" +
                     std::to_string(kJournalSchemaVersion + 1) + ");");
  const Error e = refusal();
  EXPECT_EQ(e.code, ErrorCode::kParseError);
  EXPECT_NE(e.message.find(file().string()), std::string::npos) << e.message;
  EXPECT_NE(e.message.find("newer skyrouted"), std::string::npos) << e.message;
  EXPECT_NE(e.message.find("version " + std::to_string(kJournalSchemaVersion + 1)), std::string::npos) << e.message;
}

TEST_F(StateJournalTest, GarbageFileIsRefusedNamingTheFile) {
  {
    std::ofstream out(file(), std::ios::binary);
    for (int i = 0; i < 4096; ++i) out.put(static_cast<char>((i * 131 + 7) % 251));
  }
  const Error e = refusal();
  EXPECT_NE(e.message.find(file().string()), std::string::npos) << e.message;
  EXPECT_NE(e.message.find("not a readable SQLite database"), std::string::npos) << e.message;
}

TEST_F(StateJournalTest, DamagedPagesAreRefused) {
  {
    auto journal = open();
    ASSERT_TRUE(journal);
    for (int i = 0; i < 20; ++i) {
      const std::string v = "uav-" + std::to_string(i);
      ASSERT_TRUE(journal->recordTrajectory(trajectory(v, v + "-1", 0, "m", 400, 3600.0), kNowNs).ok());
    }
  }
  runSql(file(), "PRAGMA wal_checkpoint(TRUNCATE);");
  {
    // Overwrite a page in the middle of the file (past the header and schema page).
    std::fstream io(file(), std::ios::in | std::ios::out | std::ios::binary);
    io.seekp(4096 * 3);
    for (int i = 0; i < 4096; ++i) io.put(static_cast<char>(0xA5));
  }
  const Error e = refusal();
  EXPECT_NE(e.message.find(file().string()), std::string::npos) << e.message;
  EXPECT_NE(e.message.find("will not start"), std::string::npos) << e.message;
}

TEST_F(StateJournalTest, AnotherDatabaseIsNotAJournal) {
  runSql(file(), "CREATE TABLE photos(name TEXT);");
  const Error e = refusal();
  EXPECT_NE(e.message.find("not a skyroute state journal"), std::string::npos) << e.message;
}

// The number of rows of `table` in the journal file.
std::int64_t rowCount(const std::filesystem::path& file, const std::string& table) {
  sqlite3* db = nullptr;
  std::int64_t n = -1;
  if (sqlite3_open(file.c_str(), &db) == SQLITE_OK) {
    sqlite3_stmt* q = nullptr;
    if (sqlite3_prepare_v2(db, ("SELECT count(*) FROM " + table).c_str(), -1, &q, nullptr) == SQLITE_OK &&
        sqlite3_step(q) == SQLITE_ROW) {
      n = sqlite3_column_int64(q, 0);
    }
    sqlite3_finalize(q);
  }
  sqlite3_close(db);
  return n;
}

TEST_F(StateJournalTest, ADamagedRecordIsQuarantinedNamingItsRowAndTheRestComesBack) {
  {
    auto journal = open();
    ASSERT_TRUE(journal);
    ASSERT_TRUE(journal->recordAccepted(mission("m9", "uav-9"), kNowNs).ok());
    ASSERT_TRUE(journal->recordTrajectory(trajectory("uav-9", "uav-9-1", 0, "m9", 10, 3600.0), kNowNs).ok());
    ASSERT_TRUE(journal->recordTrajectory(trajectory("uav-8", "uav-8-2", 0, "m8", 10, 3600.0), kNowNs).ok());
    ASSERT_TRUE(journal->recordObstacle(sphere(5, 0)).ok());
  }
  // One byte of one sample changed behind the journal's back (its checksum stays as it was), and
  // an obstacle's record cut.
  runSql(file(), "UPDATE trajectories SET record = substr(record, 1, 40) || x'7f' || substr(record, 42) "
                 "WHERE vehicle_id = 'uav-9'; UPDATE obstacles SET update_json = substr(update_json, 1, 20);");
  auto journal = open();
  ASSERT_TRUE(journal);
  auto state = journal->load(kNowNs);
  ASSERT_TRUE(state.ok()) << state.error().describe();
  ASSERT_EQ(state->trajectories.size(), 1u);
  EXPECT_EQ(state->trajectories[0].vehicle_id, "uav-8");
  EXPECT_TRUE(state->missions.empty()) << "the flight of a quarantined trajectory cannot be resumed";
  EXPECT_TRUE(state->obstacles.empty());
  ASSERT_EQ(state->quarantined.size(), 3u);
  EXPECT_EQ(state->quarantined[0].table, "trajectories");
  EXPECT_EQ(state->quarantined[0].key, std::vector<std::string>{"uav-9"});
  EXPECT_NE(state->quarantined[0].reason.find("checksum"), std::string::npos) << state->quarantined[0].reason;
  EXPECT_EQ(state->quarantined[1].table, "obstacles");
  EXPECT_EQ(state->quarantined[2].table, "missions");
  // Moved, not lost: the quarantine table holds them, the next load finds the rest only.
  EXPECT_EQ(rowCount(file(), "quarantine"), 3);
  auto again = journal->load(kNowNs);
  ASSERT_TRUE(again.ok());
  EXPECT_TRUE(again->quarantined.empty());
  EXPECT_EQ(again->trajectories.size(), 1u);
}

TEST_F(StateJournalTest, VersionThreeJournalGetsChecksumsThatHold) {
  {
    auto journal = open();
    ASSERT_TRUE(journal);
    ASSERT_TRUE(journal->recordAccepted(mission("m1", "uav-1"), kNowNs).ok());
    ASSERT_TRUE(journal->recordTrajectory(trajectory("uav-1", "uav-1-3", 2, "m1", 10, 3600.0), kNowNs).ok());
  }
  // What a version-3 skyrouted wrote: no checksums (zero here), no quarantine table.
  runSql(file(), "UPDATE missions SET checksum = 0; UPDATE trajectories SET checksum = 0; UPDATE meta SET checksum = 0;"
                 "DROP TABLE quarantine; UPDATE schema_version SET version = 3;");
  auto journal = open();
  ASSERT_TRUE(journal);
  EXPECT_EQ(journal->foundSchemaVersion(), 3);
  auto state = journal->load(kNowNs);
  ASSERT_TRUE(state.ok()) << state.error().describe();
  EXPECT_TRUE(state->quarantined.empty()) << state->quarantined.front().reason;
  ASSERT_EQ(state->trajectories.size(), 1u);
  expectSameTrajectory(state->trajectories[0], trajectory("uav-1", "uav-1-3", 2, "m1", 10, 3600.0));
  EXPECT_EQ(state->missions.size(), 1u);
  EXPECT_EQ(state->plan_counter, 3u);
}

TEST_F(StateJournalTest, AnEmptyFileIsRefusedNamingItButAMissingOneStartsEmpty) {
  std::filesystem::create_directories(dir_);
  std::ofstream(file()).close();
  const Error e = refusal();
  EXPECT_EQ(e.code, ErrorCode::kParseError);
  EXPECT_NE(e.message.find(file().string()), std::string::npos) << e.message;
  EXPECT_NE(e.message.find("empty (0 bytes)"), std::string::npos) << e.message;
  std::filesystem::remove(file());
  auto journal = open();
  ASSERT_TRUE(journal);
  EXPECT_EQ(journal->foundSchemaVersion(), 0);
}

// The replanning loop waits for a revision's record before publishing it: how long is that?
// A 10-minute trajectory at 0.2 s is 3000 samples (about 400 kB).
TEST_F(StateJournalTest, RecordingARevisionIsCheap) {
  auto journal = open();
  ASSERT_TRUE(journal);
  const int vehicles = 20;
  const int rounds = 10;
  std::vector<TrajectoryData> revisions;
  for (int v = 0; v < vehicles; ++v) {
    const std::string id = "uav-" + std::to_string(v);
    revisions.push_back(trajectory(id, id + "-1", 0, "m", 3000, 3600.0));
  }
  const auto started = std::chrono::steady_clock::now();
  for (int round = 0; round < rounds; ++round) {
    for (TrajectoryData& t : revisions) {
      t.revision = static_cast<std::uint32_t>(round);
      ASSERT_TRUE(journal->recordTrajectory(t, kNowNs + round * 100'000'000LL).ok());
    }
  }
  const double mean_ms =
      std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - started).count() / (vehicles * rounds);
  const JournalWriteStats stats = journal->writeStats();
  std::cout << "journal: 3000-sample revision recorded in " << mean_ms << " ms on average (max " << stats.max_ms
            << " ms, " << stats.writes << " writes)\n";
  RecordProperty("revision_write_mean_ms", std::to_string(mean_ms));
  // A replanning cycle is 100 ms: a revision's record must take a small part of it.
  EXPECT_LT(mean_ms, 20.0);
  auto state = journal->load(kNowNs + 1'000'000'000);
  ASSERT_TRUE(state.ok());
  ASSERT_EQ(state->trajectories.size(), static_cast<std::size_t>(vehicles));  // one row per vehicle
  EXPECT_EQ(state->trajectories[0].revision, static_cast<std::uint32_t>(rounds - 1));
}

}  // namespace
}  // namespace skyroute
