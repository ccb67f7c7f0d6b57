// The engine behind a JournalingSink, "crashed" (its sink cut, so nothing more reaches the journal)
// and a new engine recovering from the journal: the flying mission's trajectory comes back with
// the same plan, revision and samples, its flight is rebuilt and replans on the journal's
// obstacles with the next revision; a request accepted but never planned is planned; plan ids do
// not repeat; a queued recovered flight that is cancelled is retracted. A standby taking over
// numbers its revisions on from the primary's (followRevision).
#include <gtest/gtest.h>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <filesystem>
#include <mutex>

#include "service/engine.hpp"
#include "service/journaling_sink.hpp"
#include "service/state_journal.hpp"
#include "tests/service/default_world_fixture.hpp"
#include "tests/same_trajectory.hpp"
#include "tests/service/recording_sink.hpp"

namespace skyroute {
namespace {

using testing::RecordingSink;

// Passes everything on until cut(): then drops it, as a killed process would write nothing more.
class CuttableSink : public EngineSink {
 public:
  explicit CuttableSink(EngineSink& next) : next_(next) {}
  void cut() { cut_ = true; }
  void publishStatus(const PlanStatusData& s) override {
    if (!cut_) next_.publishStatus(s);
  }
  void publishTrajectory(const TrajectoryData& t) override {
    if (!cut_) next_.publishTrajectory(t);
  }
  void retractTrajectory(const std::string& v) override {
    if (!cut_) next_.retractTrajectory(v);
  }
  Status recordAccepted(const MissionRequestData& r) override { return cut_ ? Status::success() : next_.recordAccepted(r); }
  Status recordTrajectory(const TrajectoryData& t) override { return cut_ ? Status::success() : next_.recordTrajectory(t); }
  Status recordFleetPlan(const std::vector<TrajectoryData>& ts, const FleetStatusData& s) override {
    return cut_ ? Status::success() : next_.recordFleetPlan(ts, s);
  }
  Status recordCancel(const CancelRequestData& c) override { return cut_ ? Status::success() : next_.recordCancel(c); }
  bool recordsTrajectories() const override { return next_.recordsTrajectories(); }
  void recordObstacle(const ObstacleUpdateData& u) override {
    if (!cut_) next_.recordObstacle(u);
  }

 private:
  EngineSink& next_;
  std::atomic<bool> cut_{false};
};

using testing::sameSamples;

class EngineRecoveryTest : public testing::DefaultWorldTest {
 protected:
  void SetUp() override {
    DefaultWorldTest::SetUp();
    dir_ = std::filesystem::path(::testing::TempDir()) /
           ("engine_recovery_" + std::string(::testing::UnitTest::GetInstance()->current_test_info()->name()));
    std::filesystem::remove_all(dir_);
  }
  void TearDown() override { std::filesystem::remove_all(dir_); }

  // One daemon's life: a journal, a sink in front of `published`, an engine on a fresh world.
  struct Life {
    std::shared_ptr<StateJournal> journal;
    std::unique_ptr<JournalingSink> journaling;
    std::unique_ptr<CuttableSink> cuttable;
    std::shared_ptr<WorldModel> world;
    std::unique_ptr<Engine> engine;
  };
  Life start(RecordingSink& published) {
    Life life;
    auto journal = StateJournal::open(dir_.string());
    EXPECT_TRUE(journal.ok()) << journal.error().describe();
    life.journal = std::move(*journal);
    life.journaling = std::make_unique<JournalingSink>(published, life.journal, [this] { return now_ns_; });
    life.cuttable = std::make_unique<CuttableSink>(*life.journaling);
    auto world = WorldModel::create(heightfield_, WorldModelOptions{}, "default_terrain");
    EXPECT_TRUE(world.ok());
    life.world = *world;
    EngineOptions options;
    options.pipeline.sample_dt_s = 0.05;
    auto engine = Engine::create(life.world, options, *life.cuttable, [this] { return now_ns_; });
    EXPECT_TRUE(engine.ok()) << engine.error().describe();
    life.engine = std::move(*engine);
    return life;
  }
  static void crash(Life& life) {
    life.cuttable->cut();
    life.engine.reset();
  }
  MissionRequestData request(const std::string& id, const std::string& vehicle) const {
    MissionRequestData r;
    r.request_id = id;
    r.vehicle_id = vehicle;
    r.begin = enu(-4500, -4500, 200);
    r.points = {enu(0, 0, 200)};
    r.end = enu(4500, 4500, 200);
    return r;
  }

  std::filesystem::path dir_;
  std::int64_t now_ns_ = 1'800'000'000'000'000'000LL;
};

TEST_F(EngineRecoveryTest, FlyingMissionComesBackWithItsSamplesAndReplansOnTheJournalsObstacles) {
  RecordingSink before;
  Life first = start(before);
  ASSERT_FALSE(first.engine->submit(request("m1", "uav-1")).has_value());
  ASSERT_TRUE(first.engine->planNext());
  ASSERT_EQ(before.trajectories.size(), 1u);
  const TrajectoryData published = before.trajectories.front();
  // An obstacle off the route, in force until removed.
  ObstacleUpdateData aside;
  aside.obstacle.id = 3;
  aside.obstacle.size_m = Eigen::Vector3d::Constant(100.0);
  aside.obstacle.center_m = Eigen::Vector3d(-4000, 4000, 2500);
  aside.valid_from_utc_ns = now_ns_;
  ASSERT_FALSE(first.engine->updateObstacle(aside).has_value());
  now_ns_ += 20'000'000'000;  // 20 s into the flight
  crash(first);

  RecordingSink after;
  Life second = start(after);
  auto state = second.journal->load(now_ns_);
  ASSERT_TRUE(state.ok()) << state.error().describe();
  second.engine->recover(*state);
  // At once, before anything is planned: the same trajectory, revision and samples.
  ASSERT_EQ(after.trajectories.size(), 1u);
  EXPECT_EQ(after.trajectories[0].plan_id, published.plan_id);
  EXPECT_EQ(after.trajectories[0].revision, published.revision);
  EXPECT_TRUE(sameSamples(after.trajectories[0], published));
  EXPECT_EQ(second.world->obstacleCount(), 1u);
  EXPECT_TRUE(after.statuses.empty());  // the request was answered before the crash

  // The flight is rebuilt on a worker, answering nothing; until its first replan the trajectory
  // published before the crash stays the vehicle's current one.
  ASSERT_TRUE(second.engine->planNext());
  EXPECT_EQ(second.engine->activeMissions(), 1u);
  EXPECT_TRUE(after.statuses.empty());
  const std::vector<TrajectoryData> current = second.engine->currentTrajectories();
  ASSERT_EQ(current.size(), 1u);
  EXPECT_EQ(current[0].revision, published.revision);
  EXPECT_TRUE(sameSamples(current[0], published));
  EXPECT_EQ(second.engine->replanCycle(), 0u);  // nothing in the way

  // An obstacle on the route 30 s ahead: the next revision, of the same plan.
  const std::size_t ahead = static_cast<std::size_t>(50.0 / 0.05);
  ASSERT_LT(ahead, published.samples.size());
  ObstacleUpdateData blocking;
  blocking.obstacle.id = 4;
  blocking.obstacle.size_m = Eigen::Vector3d::Constant(250.0);
  blocking.obstacle.center_m = published.samples[ahead].position_enu_m;
  blocking.valid_from_utc_ns = now_ns_;
  ASSERT_FALSE(second.engine->updateObstacle(blocking).has_value());
  ASSERT_EQ(second.engine->replanCycle(), 1u);
  ASSERT_EQ(after.trajectories.size(), 2u);
  EXPECT_EQ(after.trajectories[1].plan_id, published.plan_id);
  EXPECT_EQ(after.trajectories[1].revision, published.revision + 1);

  // The journal holds the new revision and both obstacles.
  auto again = second.journal->load(now_ns_);
  ASSERT_TRUE(again.ok());
  ASSERT_EQ(again->trajectories.size(), 1u);
  EXPECT_EQ(again->trajectories[0].revision, published.revision + 1);
  EXPECT_EQ(again->obstacles.size(), 2u);

  // A new plan after the restart never reuses a plan id of before.
  ASSERT_FALSE(second.engine->submit(request("m2", "uav-2")).has_value());
  ASSERT_TRUE(second.engine->planNext());
  ASSERT_EQ(after.trajectories.size(), 3u);
  EXPECT_GT(planNumber(after.trajectories[2].plan_id), planNumber(published.plan_id));
}

// A replanned revision's curve is not in the journal (its samples are): the rebuilt flight differs
// from it, and goes out at once as the next revision of the same plan, so what is flown is what
// the replanning loop checks.
TEST_F(EngineRecoveryTest, RebuiltFlightOfAReplannedMissionGoesOutAsTheNextRevision) {
  RecordingSink before;
  Life first = start(before);
  ASSERT_FALSE(first.engine->submit(request("m1", "uav-1")).has_value());
  ASSERT_TRUE(first.engine->planNext());
  const TrajectoryData planned = before.trajectories.front();
  now_ns_ += 20'000'000'000;
  ObstacleUpdateData blocking;
  blocking.obstacle.id = 4;
  blocking.obstacle.size_m = Eigen::Vector3d::Constant(250.0);
  blocking.obstacle.center_m = planned.samples[static_cast<std::size_t>(50.0 / 0.05)].position_enu_m;
  blocking.valid_from_utc_ns = now_ns_;
  blocking.valid_until_utc_ns = now_ns_ + 5'000'000'000;  // gone again after the restart
  ASSERT_FALSE(first.engine->updateObstacle(blocking).has_value());
  ASSERT_EQ(first.engine->replanCycle(), 1u);
  const TrajectoryData replanned = before.trajectories.back();
  ASSERT_EQ(replanned.revision, 1u);
  now_ns_ += 10'000'000'000;
  crash(first);

  RecordingSink after;
  Life second = start(after);
  auto state = second.journal->load(now_ns_);
  ASSERT_TRUE(state.ok());
  EXPECT_TRUE(state->obstacles.empty());  // it ended before the restart
  second.engine->recover(*state);
  ASSERT_EQ(after.trajectories.size(), 1u);
  EXPECT_EQ(after.trajectories[0].revision, 1u);
  EXPECT_TRUE(sameSamples(after.trajectories[0], replanned));
  ASSERT_TRUE(second.engine->planNext());
  ASSERT_EQ(after.trajectories.size(), 2u);
  EXPECT_EQ(after.trajectories[1].plan_id, planned.plan_id);
  EXPECT_EQ(after.trajectories[1].revision, 2u);
  EXPECT_TRUE(sameSamples(after.trajectories[1], planned));  // the request planned again from its start
  const std::vector<TrajectoryData> current = second.engine->currentTrajectories();
  ASSERT_EQ(current.size(), 1u);
  EXPECT_EQ(current[0].revision, 2u);
}

TEST_F(EngineRecoveryTest, RequestAcceptedButNeverPlannedIsPlannedAfterTheRestart) {
  RecordingSink before;
  Life first = start(before);
  ASSERT_FALSE(first.engine->submit(request("queued", "uav-1")).has_value());
  ASSERT_EQ(before.statuses.size(), 1u);
  EXPECT_EQ(before.statuses[0].state, PlanState::kAccepted);
  crash(first);

  RecordingSink after;
  Life second = start(after);
  auto state = second.journal->load(now_ns_);
  ASSERT_TRUE(state.ok());
  ASSERT_EQ(state->missions.size(), 1u);
  second.engine->recover(*state);
  EXPECT_TRUE(after.trajectories.empty());
  ASSERT_TRUE(second.engine->planNext());
  ASSERT_EQ(after.trajectories.size(), 1u);
  EXPECT_EQ(after.trajectories[0].request_id, "queued");
  ASSERT_FALSE(after.statuses.empty());
  EXPECT_EQ(after.statuses.back().state, PlanState::kSucceeded);
  EXPECT_EQ(second.engine->activeMissions(), 1u);
}

TEST_F(EngineRecoveryTest, CancelledRecoveredFlightIsRetractedAndForgotten) {
  RecordingSink before;
  Life first = start(before);
  ASSERT_FALSE(first.engine->submit(request("m1", "uav-1")).has_value());
  ASSERT_TRUE(first.engine->planNext());
  crash(first);

  RecordingSink after;
  Life second = start(after);
  auto state = second.journal->load(now_ns_);
  ASSERT_TRUE(state.ok());
  second.engine->recover(*state);
  EXPECT_TRUE(second.engine->cancel(CancelRequestData{"m1", "uav-1"}));
  EXPECT_EQ(after.retracted, std::vector<std::string>{"uav-1"});
  ASSERT_FALSE(after.statuses.empty());
  EXPECT_EQ(after.statuses.back().state, PlanState::kCancelled);
  EXPECT_FALSE(second.engine->planNext());
  auto left = second.journal->load(now_ns_);
  ASSERT_TRUE(left.ok());
  EXPECT_TRUE(left->missions.empty());
  EXPECT_TRUE(left->trajectories.empty());
}

TEST_F(EngineRecoveryTest, TakingOverNumbersTheRevisionsOnFromTheWireOnlyWhenTheyDrifted) {
  RecordingSink published;
  Life life = start(published);
  ASSERT_FALSE(life.engine->submit(request("m1", "uav-1")).has_value());
  ASSERT_TRUE(life.engine->planNext());
  const TrajectoryData planned = published.trajectories.front();
  ASSERT_EQ(planned.revision, 0u);
  const auto current_revision = [&] { return life.engine->currentTrajectories().at(0).revision; };
  // In step (the same revision, or the primary one behind): nothing changes.
  EXPECT_FALSE(life.engine->followRevision("uav-1", planned.plan_id, 0));
  EXPECT_FALSE(life.engine->followRevision("uav-1", "uav-1-other", 5)) << "another plan on the wire";
  EXPECT_FALSE(life.engine->followRevision("uav-2", planned.plan_id, 5)) << "a vehicle it does not fly";
  // The primary made replans this engine did not: its current trajectory is the next one.
  EXPECT_EQ(life.engine->followRevision("uav-1", planned.plan_id, 5), std::optional<std::uint32_t>(6));
  EXPECT_EQ(current_revision(), 6u);
  EXPECT_TRUE(sameSamples(life.engine->currentTrajectories().at(0), planned)) << "renumbered, not replanned";
  // Its next replan counts on from there.
  now_ns_ += 20'000'000'000;
  ObstacleUpdateData blocking;
  blocking.obstacle.id = 4;
  blocking.obstacle.size_m = Eigen::Vector3d::Constant(250.0);
  blocking.obstacle.center_m = planned.samples[static_cast<std::size_t>(50.0 / 0.05)].position_enu_m;
  blocking.valid_from_utc_ns = now_ns_;
  ASSERT_FALSE(life.engine->updateObstacle(blocking).has_value());
  ASSERT_EQ(life.engine->replanCycle(), 1u);
  EXPECT_EQ(published.trajectories.back().revision, 7u);
  EXPECT_FALSE(life.engine->followRevision("uav-1", planned.plan_id, 6)) << "7 follows 6";
  // This engine made more replans than the primary: numbered back to the one after the primary's.
  EXPECT_EQ(life.engine->followRevision("uav-1", planned.plan_id, 2), std::optional<std::uint32_t>(3));
  EXPECT_EQ(current_revision(), 3u);
}

}  // namespace
}  // namespace skyroute
