// The DDS-free engine driven directly: a mission on the embedded terrain comes back as a
// trajectory through every point (begin first, end last) that keeps its clearance; bad requests
// get a failed status naming the field and do not stop the next request; an obstacle put on the
// route makes the next replanning cycle publish a revision that avoids it and continues the flown
// curve; cancels and stop() end work promptly.
#include <gtest/gtest.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <condition_variable>
#include <limits>
#include <mutex>
#include <set>
#include <thread>

#include <spdlog/sinks/ringbuffer_sink.h>
#include <spdlog/spdlog.h>

#include "service/engine.hpp"
#include "terrain/terrain_world.hpp"
#include "tests/service/default_world_fixture.hpp"
#include "tests/spoiled_request.hpp"

namespace skyroute {
namespace {

class CapturingSink : public EngineSink {
 public:
  void publishStatus(const PlanStatusData& status) override {
    std::lock_guard lock(mutex_);
    statuses.push_back(status);
    cv_.notify_all();
  }
  void publishTrajectory(const TrajectoryData& trajectory) override {
    std::lock_guard lock(mutex_);
    trajectories.push_back(trajectory);
    cv_.notify_all();
  }
  void retractTrajectory(const std::string& vehicle_id) override {
    std::lock_guard lock(mutex_);
    retracted.push_back(vehicle_id);
  }
  // The last status of a request (nullopt if none yet).
  std::optional<PlanStatusData> last(const std::string& request_id) {
    std::lock_guard lock(mutex_);
    for (auto it = statuses.rbegin(); it != statuses.rend(); ++it)
      if (it->request_id == request_id) return *it;
    return std::nullopt;
  }
  // Waits until every listed request has a terminal status.
  bool waitTerminal(const std::vector<std::string>& ids, double timeout_s) {
    std::unique_lock lock(mutex_);
    return cv_.wait_for(lock, std::chrono::duration<double>(timeout_s), [&] {
      return std::all_of(ids.begin(), ids.end(), [&](const std::string& id) {
        return std::any_of(statuses.begin(), statuses.end(),
                           [&](const PlanStatusData& s) { return s.request_id == id && isTerminal(s.state); });
      });
    });
  }

  std::vector<PlanStatusData> statuses;
  std::vector<TrajectoryData> trajectories;
  std::vector<std::string> retracted;

 private:
  std::mutex mutex_;
  std::condition_variable cv_;
};

struct ManualClock {
  std::int64_t now_ns = 1'800'000'000'000'000'000LL;  // a fixed UTC instant (2027)
  void advance(double seconds) { now_ns += static_cast<std::int64_t>(std::llround(seconds * 1e9)); }
  double seconds() const { return static_cast<double>(now_ns) * 1e-9; }
};

class EngineTest : public testing::DefaultWorldTest {
 protected:
  void SetUp() override {
    DefaultWorldTest::SetUp();
    if (HasFatalFailure()) return;
    EngineOptions options;
    options.pipeline.sample_dt_s = 0.05;  // dense enough for the clearance check between samples
    // Replans on iteration budgets: whether a cycle finds a plan or holds must not depend on how
    // loaded the machine is (a wall-clock deadline missed makes a hold).
    options.pipeline.replan.replan_budget_ms = 0.0;
    auto engine = Engine::create(world_, options, sink_, [this] { return clock_.now_ns; });
    ASSERT_TRUE(engine.ok()) << engine.error().describe();
    engine_ = std::move(*engine);
  }

  MissionRequestData request(const std::string& id, const std::string& vehicle = "uav-1") const {
    MissionRequestData r;
    r.request_id = id;
    r.vehicle_id = vehicle;
    r.begin = geo(-4500, -4500, 150);
    r.points = {enu(3500, 3000, 200), geo(-3000, 2500, 200), enu(3000, -3500, 200)};
    r.end = geo(4500, 4500, 150);
    return r;
  }
  // Corner to corner through the centre, 200 m up.
  MissionRequestData diagonalRequest(const std::string& id) const {
    MissionRequestData r = request(id);
    r.points = {enu(0, 0, 200)};
    r.begin = enu(-4500, -4500, 200);
    r.end = enu(4500, 4500, 200);
    return r;
  }
  Eigen::Vector3d toEnu(const MissionPointData& p) const {
    return p.frame == MissionPointData::Frame::kEnu ? p.enu_m : heightfield_->frame().toEnu(p.geo);
  }

  CapturingSink sink_;
  ManualClock clock_;
  std::unique_ptr<Engine> engine_;
};

TEST_F(EngineTest, MissionBecomesATrajectoryThroughEveryPointClearOfTheGround) {
  const MissionRequestData r = request("m1");
  ASSERT_FALSE(engine_->submit(r).has_value());
  ASSERT_TRUE(engine_->planNext());
  ASSERT_FALSE(engine_->planNext());  // nothing else queued

  std::vector<PlanState> states;
  for (const auto& s : sink_.statuses) states.push_back(s.state);
  ASSERT_EQ(states, (std::vector<PlanState>{PlanState::kAccepted, PlanState::kPlanning, PlanState::kSucceeded}))
      << sink_.statuses.back().message;
  ASSERT_EQ(sink_.trajectories.size(), 1u);
  const TrajectoryData& t = sink_.trajectories.front();
  EXPECT_EQ(t.vehicle_id, "uav-1");
  EXPECT_EQ(t.request_id, "m1");
  EXPECT_EQ(t.revision, 0u);

  // The order visits every point once, B first and E last; the legs follow it.
  const std::size_t count = r.points.size() + 2;
  ASSERT_EQ(t.visiting_order.size(), count);
  EXPECT_EQ(t.visiting_order.front(), 0u);
  EXPECT_EQ(t.visiting_order.back(), count - 1);
  EXPECT_EQ(std::set<std::uint32_t>(t.visiting_order.begin(), t.visiting_order.end()).size(), count);
  ASSERT_EQ(t.legs.size(), count - 1);
  for (std::size_t k = 0; k < t.legs.size(); ++k) {
    EXPECT_EQ(t.legs[k].from_point, t.visiting_order[k]);
    EXPECT_EQ(t.legs[k].to_point, t.visiting_order[k + 1]);
    EXPECT_LT(t.legs[k].start_s, t.legs[k].end_s);
  }

  // Samples: time from 0 at the plan's clock, every point passed, clearance kept everywhere.
  std::vector<Eigen::Vector3d> all{toEnu(r.begin)};
  for (const auto& p : r.points) all.push_back(toEnu(p));
  all.push_back(toEnu(r.end));
  ASSERT_GT(t.samples.size(), 100u);
  EXPECT_EQ(t.samples.front().utc_ns, clock_.now_ns);
  EXPECT_LT((t.samples.front().position_enu_m - all.front()).norm(), 0.01);
  EXPECT_LT((t.samples.back().position_enu_m - all.back()).norm(), 0.01);
  const double max_step_m = VehicleLimitsData{}.max_speed_mps * 0.05;
  for (std::size_t k = 0; k < t.legs.size(); ++k) {
    const Eigen::Vector3d& point = all[t.legs[k].to_point];
    double nearest = std::numeric_limits<double>::infinity();
    for (const auto& s : t.samples) nearest = std::min(nearest, (s.position_enu_m - point).norm());
    EXPECT_LT(nearest, max_step_m) << "point " << t.legs[k].to_point << " is not on the trajectory";
  }
  const double clearance = VehicleLimitsData{}.min_clearance_agl_m;
  for (std::size_t i = 0; i < t.samples.size(); ++i) {
    const auto& s = t.samples[i];
    const double ground = heightfield_->heightAt(s.position_enu_m.x(), s.position_enu_m.y());
    ASSERT_GE(s.position_enu_m.z() - ground, clearance - 0.5) << "sample " << i << " at t=" << s.t_rel_s;
    if (i > 0) {
      if (i + 1 < t.samples.size()) {
        EXPECT_NEAR(s.t_rel_s - t.samples[i - 1].t_rel_s, 0.05, 1e-9);
      }
      EXPECT_LE((s.position_enu_m - t.samples[i - 1].position_enu_m).norm(), max_step_m + 1e-6);
    }
    const Eigen::Vector3d back = heightfield_->frame().toEnu(s.geo);
    ASSERT_LT((back - s.position_enu_m).norm(), 0.01);
  }
}

TEST_F(EngineTest, HabPpPlannersGoThroughTheSameTrajectoryStage) {
  // A leg that must cross the embedded terrain's main ridge low: the straight line is blocked, so
  // HAB-PP plans on the flight band. The middle point sits 150 m above the valley floor: at 60 m
  // the lift dives from the band into it and climbs straight out again, a pass-through corner the
  // trajectory stage often cannot round for a 30 m turn radius (bench/grid_route_bench: 17 of 24
  // failures on random missions), which would make this test depend on the exact path.
  // Both settings of the output stage's windowed re-planning (off, and the default).
  for (const int windows : {0, HabPpParameters{}.output_window_segments}) {
    EngineOptions options;
    options.pipeline.sample_dt_s = 0.05;
    options.pipeline.grid_legs.output_window_segments = windows;
    auto engine = Engine::create(world_, options, sink_, [this] { return clock_.now_ns; });
    ASSERT_TRUE(engine.ok()) << engine.error().describe();
    for (const std::string planner : {"hab-pp", "hab-pp-rrt"}) {
      const std::string name = planner + "-windows-" + std::to_string(windows);
      SCOPED_TRACE(name);
      MissionRequestData r = request("grid-" + name, "uav-" + name);
      r.planner = planner;
      r.begin = enu(-5000, -2000, 60);
      r.points = {enu(0, -5500, 150)};
      r.end = enu(5000, 2000, 60);
      r.fixed_order = true;
      r.limits.min_turn_radius_m = 30.0;  // the corners of the grid path are rounded
      auto world = world_->worldFor(r.limits.min_clearance_agl_m, r.limits.ceiling_amsl_m);
      ASSERT_TRUE(world.ok());
      ASSERT_FALSE((*world)->isSegmentValid(r.begin.enu_m, r.points[0].enu_m) &&
                   (*world)->isSegmentValid(r.points[0].enu_m, r.end.enu_m))
          << "the test needs a leg whose straight line is blocked";
      ASSERT_FALSE((*engine)->submit(r).has_value());
      ASSERT_TRUE((*engine)->planNext());
      const auto status = sink_.last(r.request_id);
      ASSERT_EQ(status->state, PlanState::kSucceeded) << status->field << " " << status->message;
      const TrajectoryData& t = sink_.trajectories.back();
      ASSERT_EQ(t.request_id, r.request_id);
      ASSERT_EQ(t.legs.size(), 2u);
      EXPECT_LT((t.samples.front().position_enu_m - r.begin.enu_m).norm(), 0.01);
      EXPECT_LT((t.samples.back().position_enu_m - r.end.enu_m).norm(), 0.01);
      const double clearance = r.limits.min_clearance_agl_m;
      for (const auto& s : t.samples) {
        const double ground = heightfield_->heightAt(s.position_enu_m.x(), s.position_enu_m.y());
        ASSERT_GE(s.position_enu_m.z() - ground, clearance - 0.5) << "at t=" << s.t_rel_s;
      }
    }
  }
}

TEST_F(EngineTest, PlainBeginToEndMissionIsServed) {
  MissionRequestData r = request("a-to-b");
  r.points.clear();
  ASSERT_FALSE(engine_->submit(r).has_value());
  ASSERT_TRUE(engine_->planNext());
  const auto status = sink_.last(r.request_id);
  ASSERT_EQ(status->state, PlanState::kSucceeded) << status->field << " " << status->message;
  const TrajectoryData& t = sink_.trajectories.back();
  EXPECT_EQ(t.visiting_order, (std::vector<std::uint32_t>{0, 1}));
  ASSERT_EQ(t.legs.size(), 1u);
  EXPECT_LT((t.samples.front().position_enu_m - toEnu(r.begin)).norm(), 0.01);
  EXPECT_LT((t.samples.back().position_enu_m - toEnu(r.end)).norm(), 0.01);
}

TEST_F(EngineTest, AFiredWallClockCapIsReportedInTheStatus) {
  // A leg whose straight line is blocked (RRT* must search) with more iterations than the cap
  // lets it run: the plan is still made, and its status says the cap fired on that leg.
  EngineOptions options;
  options.pipeline.budget.leg_max_iterations = 5'000'000;  // fits the memory budget, far beyond the cap
  options.pipeline.budget.leg_time_cap_s = 0.2;
  auto engine = Engine::create(world_, options, sink_, [this] { return clock_.now_ns; });
  ASSERT_TRUE(engine.ok()) << engine.error().describe();
  MissionRequestData r = request("capped", "uav-capped");
  r.begin = enu(-5000, -2000, 60);
  r.points.clear();
  r.end = enu(0, -5500, 150);
  auto world = world_->worldFor(r.limits.min_clearance_agl_m, r.limits.ceiling_amsl_m);
  ASSERT_TRUE(world.ok());
  ASSERT_FALSE((*world)->isSegmentValid(r.begin.enu_m, r.end.enu_m)) << "the test needs a blocked straight leg";
  ASSERT_FALSE((*engine)->submit(r).has_value());
  ASSERT_TRUE((*engine)->planNext());
  const auto status = sink_.last(r.request_id);
  ASSERT_EQ(status->state, PlanState::kSucceeded) << status->message;
  EXPECT_NE(status->message.find("legs[0]: the wall-clock cap of 0.2 s"), std::string::npos) << status->message;
  EXPECT_NE(status->message.find("not reproducible"), std::string::npos) << status->message;

  // Within its iteration budget the same leg says nothing of the kind.
  ASSERT_FALSE(engine_->submit(request("uncapped", "uav-uncapped")).has_value());
  ASSERT_TRUE(engine_->planNext());
  EXPECT_EQ(sink_.last("uncapped")->message, "");
}

TEST_F(EngineTest, SameSeedSameTrajectory) {
  ASSERT_FALSE(engine_->submit(request("a")).has_value());
  ASSERT_TRUE(engine_->planNext());
  ASSERT_FALSE(engine_->submit(request("b", "uav-2")).has_value());
  ASSERT_TRUE(engine_->planNext());
  ASSERT_EQ(sink_.trajectories.size(), 2u);
  const auto& a = sink_.trajectories[0].samples;
  const auto& b = sink_.trajectories[1].samples;
  ASSERT_EQ(a.size(), b.size());
  for (std::size_t i = 0; i < a.size(); ++i) ASSERT_EQ(a[i].position_enu_m, b[i].position_enu_m);
}

TEST_F(EngineTest, BadRequestsGetTheirErrorAndTheNextRequestIsServed) {
  using Case = testing::SpoiledRequest;
  const std::vector<Case> cases = {
      {"planner", [](MissionRequestData& r) { r.planner = "dijkstra-3d"; }, PlanErrorCode::kUnknownPlanner, "planner"},
      {"nan", [](MissionRequestData& r) { r.points[1].geo.lat_deg = std::nan(""); }, PlanErrorCode::kInvalidArgument,
       "points[1]"},
      {"oversize", [](MissionRequestData& r) { r.points.resize(65, r.points.front()); },
       PlanErrorCode::kMissionTooLarge, "points"},
      {"limits", [](MissionRequestData& r) { r.limits.max_accel_mps2 = -1.0; }, PlanErrorCode::kLimitsOutOfRange,
       "limits.max_accel_mps2"},
      {"vref", [](MissionRequestData& r) { r.limits.v_ref_mps = 99.0; }, PlanErrorCode::kLimitsOutOfRange,
       "limits.v_ref_mps"},
      {"outside", [](MissionRequestData& r) { r.points[2] = MissionPointData::enu({9000.0, 0.0, 1500.0}); },
       PlanErrorCode::kOutsideMap, "points[2]"},
      {"underground", [this](MissionRequestData& r) { r.end = enu(4500, 4500, -20); }, PlanErrorCode::kUnderGround,
       "end"},
      {"clearance", [](MissionRequestData& r) { r.limits.min_clearance_agl_m = 1.0; },
       PlanErrorCode::kLimitsOutOfRange, "limits.min_clearance_agl_m"},
      {"vehicle", [](MissionRequestData& r) { r.vehicle_id.clear(); }, PlanErrorCode::kInvalidArgument, "vehicle_id"},
  };
  for (const Case& c : cases) {
    MissionRequestData r = request("bad-" + c.name);
    c.spoil(r);
    engine_->submit(r);
    while (engine_->planNext()) {
    }
    const auto status = sink_.last(r.request_id);
    ASSERT_TRUE(status.has_value()) << c.name;
    EXPECT_EQ(status->state, PlanState::kFailed) << c.name;
    EXPECT_EQ(status->error_code, c.code) << c.name << ": " << status->message;
    EXPECT_EQ(status->field.rfind(c.field, 0), 0u) << c.name << ": field " << status->field;
    EXPECT_NE(status->message.find(status->field), std::string::npos) << c.name << ": " << status->message;
  }
  EXPECT_TRUE(sink_.trajectories.empty());
  ASSERT_FALSE(engine_->submit(request("good")).has_value());
  ASSERT_TRUE(engine_->planNext());
  EXPECT_EQ(sink_.last("good")->state, PlanState::kSucceeded);
  EXPECT_EQ(sink_.trajectories.size(), 1u);
}

TEST_F(EngineTest, ObstacleOnTheRouteGivesARevisionThatAvoidsItAndContinuesTheFlight) {
  const MissionRequestData r = diagonalRequest("replan");
  ASSERT_FALSE(engine_->submit(r).has_value());
  ASSERT_TRUE(engine_->planNext());
  ASSERT_EQ(sink_.trajectories.size(), 1u);
  const TrajectoryData first = sink_.trajectories.front();
  EXPECT_EQ(engine_->replanCycle(), 0u);  // nothing in the way

  // Fly 20 s, then a fixed sphere appears where the trajectory will be 30 s later (inside the
  // 45 s horizon).
  clock_.advance(20.0);
  const auto& s0 = first.samples;
  const std::size_t ahead = static_cast<std::size_t>(50.0 / 0.05);
  ASSERT_LT(ahead, s0.size());
  ObstacleUpdateData update;
  update.obstacle.id = 42;
  update.obstacle.shape = ObstacleShape::kSphere;
  update.obstacle.size_m = Eigen::Vector3d::Constant(250.0);
  update.obstacle.center_m = s0[ahead].position_enu_m;
  update.valid_from_utc_ns = clock_.now_ns;
  ASSERT_FALSE(engine_->updateObstacle(update).has_value());
  ASSERT_EQ(engine_->replanCycle(), 1u);
  ASSERT_EQ(sink_.trajectories.size(), 2u);
  const TrajectoryData& second = sink_.trajectories.back();
  EXPECT_EQ(second.revision, 1u);
  EXPECT_EQ(second.plan_id, first.plan_id);
  EXPECT_EQ(sink_.last("replan")->state, PlanState::kReplanned);

  // It takes over where the first one is at its start time, with the same velocity.
  const std::int64_t takeover_ns = second.samples.front().utc_ns;
  EXPECT_GT(takeover_ns, clock_.now_ns - 1);
  const double takeover_rel_s = static_cast<double>(takeover_ns - s0.front().utc_ns) * 1e-9;
  const std::size_t k = static_cast<std::size_t>(std::llround(takeover_rel_s / 0.05));
  ASSERT_NEAR(s0[k].t_rel_s, takeover_rel_s, 1e-6);
  EXPECT_LT((second.samples.front().position_enu_m - s0[k].position_enu_m).norm(), 1e-3);
  EXPECT_LT((second.samples.front().velocity_enu_mps - s0[k].velocity_enu_mps).norm(), 1e-3);
  // It avoids the sphere (with the vehicle's radius), and still ends at E and passes the point.
  for (const auto& s : second.samples)
    ASSERT_GT((s.position_enu_m - update.obstacle.center_m).norm(), 250.0 + WorldModelOptions{}.vehicle_radius_m);
  EXPECT_LT((second.samples.back().position_enu_m - toEnu(r.end)).norm(), 0.01);
  ASSERT_FALSE(second.legs.empty());
  EXPECT_EQ(second.legs.back().to_point, 2u);
  EXPECT_EQ(second.visiting_order, first.visiting_order);

  // Clear ahead now: the next cycles publish nothing; at the end the mission completes.
  clock_.advance(0.1);
  EXPECT_EQ(engine_->replanCycle(), 0u);
  EXPECT_EQ(engine_->activeMissions(), 1u);
  clock_.advance(second.samples.back().t_rel_s + 1.0);
  engine_->replanCycle();
  EXPECT_EQ(engine_->activeMissions(), 0u);
}

// A mission flown 20 s, and spheres of 250 m put on its trajectory `ahead_s` seconds later.
class EngineLoadTest : public EngineTest {
 protected:
  TrajectoryData flyFor20S() {
    EXPECT_FALSE(engine_->submit(diagonalRequest("load")).has_value());
    EXPECT_TRUE(engine_->planNext());
    EXPECT_EQ(sink_.trajectories.size(), 1u);
    clock_.advance(20.0);
    return sink_.trajectories.front();
  }
  ObstacleUpdateData sphereAhead(const TrajectoryData& t, std::uint64_t id, double ahead_s) const {
    ObstacleUpdateData u;
    u.obstacle.id = id;
    u.obstacle.shape = ObstacleShape::kSphere;
    u.obstacle.size_m = Eigen::Vector3d::Constant(250.0);
    u.obstacle.center_m = t.samples[static_cast<std::size_t>((20.0 + ahead_s) / 0.05)].position_enu_m;
    u.valid_from_utc_ns = clock_.now_ns;
    return u;
  }
};

TEST_F(EngineLoadTest, UpdatesForOneVehicleWithinOneCycleAreOneReplanAndTheLogCountsThem) {
  const TrajectoryData first = flyFor20S();
  auto log = std::make_shared<spdlog::sinks::ringbuffer_sink_mt>(64);
  log->set_pattern("%v");
  auto previous = spdlog::default_logger();
  spdlog::set_default_logger(std::make_shared<spdlog::logger>("engine_load_test", log));
  for (std::uint64_t id = 1; id <= 5; ++id) ASSERT_FALSE(engine_->updateObstacle(sphereAhead(first, id, 26.0 + id)));
  const std::size_t published = engine_->replanCycle();
  spdlog::set_default_logger(previous);
  EXPECT_EQ(published, 1u);
  EXPECT_EQ(engine_->replans(), 1u);
  ASSERT_EQ(sink_.trajectories.size(), 2u);
  EXPECT_EQ(sink_.trajectories.back().revision, 1u);
  const std::vector<std::string> lines = log->last_formatted();
  EXPECT_EQ(std::count_if(lines.begin(), lines.end(),
                          [](const std::string& l) { return l.find("event=replanned") != std::string::npos; }),
            1);
  EXPECT_TRUE(std::any_of(lines.begin(), lines.end(), [](const std::string& l) {
    return l.find("event=replanned") != std::string::npos && l.find("updates_coalesced=5") != std::string::npos;
  })) << (lines.empty() ? "" : lines.back());
}

// No plan can help (the goal inside an obstacle): the vehicle holds. The hold is a new revision
// with its own non-terminal status, published at once; it starts now on the flown curve, stops
// short of the obstacle and waits at rest. The mission goes on (replanning from the hold), and
// every later change is answered once with a holding status naming the revision in force.
TEST_F(EngineLoadTest, AReplanThatFindsNothingHoldsAndIsAnsweredOncePerChange) {
  const TrajectoryData first = flyFor20S();
  // The goal about 45 s ahead (room to stop short of the obstacle round it), at a time on the
  // first trajectory's sample grid.
  clock_.advance(std::round((first.samples.back().t_rel_s - 20.0 - 45.0) / 0.05) * 0.05);
  // The goal inside an obstacle: no replan can help.
  ObstacleUpdateData over_goal = sphereAhead(first, 9, 0.0);
  over_goal.valid_from_utc_ns = clock_.now_ns;
  over_goal.obstacle.center_m = first.samples.back().position_enu_m;
  over_goal.obstacle.size_m = Eigen::Vector3d::Constant(400.0);
  ASSERT_FALSE(engine_->updateObstacle(over_goal));
  const std::size_t statuses_before = sink_.statuses.size();
  const std::int64_t seen_ns = clock_.now_ns;
  EXPECT_EQ(engine_->replanCycle(), 1u);
  for (int cycle = 0; cycle < 3; ++cycle) {
    clock_.advance(0.1);
    EXPECT_EQ(engine_->replanCycle(), 0u);
  }
  ASSERT_EQ(sink_.statuses.size(), statuses_before + 1) << "one answer for one change, not one per cycle";
  const PlanStatusData& answer = sink_.statuses.back();
  EXPECT_EQ(answer.state, PlanState::kHolding);
  EXPECT_FALSE(isTerminal(answer.state));
  EXPECT_NE(answer.error_code, PlanErrorCode::kNone);
  EXPECT_EQ(answer.stage, PlanStage::kReplan);
  EXPECT_NE(answer.message.find("holding: revision 1"), std::string::npos) << answer.message;
  ASSERT_EQ(sink_.trajectories.size(), 2u);
  const TrajectoryData& hold = sink_.trajectories.back();
  EXPECT_EQ(hold.revision, 1u);
  EXPECT_EQ(hold.plan_id, first.plan_id);
  // It starts at the cycle's time, where the first trajectory is then, at its velocity.
  EXPECT_LT(std::abs(hold.samples.front().utc_ns - seen_ns), 1000);  // world seconds as a double: sub-us
  const std::size_t k = static_cast<std::size_t>(std::llround(static_cast<double>(seen_ns - first.samples.front().utc_ns) * 1e-9 / 0.05));
  ASSERT_LT(k, first.samples.size());
  EXPECT_LT((hold.samples.front().position_enu_m - first.samples[k].position_enu_m).norm(), 1e-3);
  EXPECT_LT((hold.samples.front().velocity_enu_mps - first.samples[k].velocity_enu_mps).norm(), 1e-3);
  // It ends at rest, clear of the obstacle.
  EXPECT_LT(hold.samples.back().velocity_enu_mps.norm(), 1e-6);
  for (const auto& s : hold.samples)
    ASSERT_GT((s.position_enu_m - over_goal.obstacle.center_m).norm(), 400.0 + WorldModelOptions{}.vehicle_radius_m);
  EXPECT_EQ(engine_->activeMissions(), 1u);
  // A new change is answered again, once, with the hold in force.
  over_goal.valid_from_utc_ns = clock_.now_ns;
  ASSERT_FALSE(engine_->updateObstacle(over_goal));
  engine_->replanCycle();
  ASSERT_EQ(sink_.statuses.size(), statuses_before + 2);
  EXPECT_EQ(sink_.statuses.back().state, PlanState::kHolding);
  EXPECT_NE(sink_.statuses.back().message.find("revision 1 (a hold) stays in force"), std::string::npos)
      << sink_.statuses.back().message;
  EXPECT_EQ(sink_.trajectories.size(), 2u);
}

TEST_F(EngineLoadTest, AnObstacleUpdateBackInTimeAndOneObstacleTooManyAreRefusedByField) {
  EngineOptions options = engine_->options();
  options.obstacles.max_obstacles = 2;
  ASSERT_TRUE(engine_->setOptions(options).ok());
  const TrajectoryData first = flyFor20S();
  ObstacleUpdateData a = sphereAhead(first, 1, 30.0);
  ASSERT_FALSE(engine_->updateObstacle(a));
  ObstacleUpdateData older = a;
  older.valid_from_utc_ns -= 1'000'000'000;
  const auto back = engine_->updateObstacle(older);
  ASSERT_TRUE(back.has_value());
  EXPECT_EQ(back->field, "valid_from_utc_ns");
  EXPECT_EQ(world_->validFromOf(1), a.valid_from_utc_ns) << "the update in force stays";
  ASSERT_FALSE(engine_->updateObstacle(sphereAhead(first, 2, 35.0)));
  const auto third = engine_->updateObstacle(sphereAhead(first, 3, 40.0));
  ASSERT_TRUE(third.has_value());
  EXPECT_EQ(third->field, "obstacle_id");
  EXPECT_EQ(third->code, PlanErrorCode::kLimitsOutOfRange);
  EXPECT_EQ(world_->obstacleCount(), 2u);
  // Known ids still move, and a removal makes room.
  a.valid_from_utc_ns += 1'000'000'000;
  EXPECT_FALSE(engine_->updateObstacle(a));
  ObstacleUpdateData gone;
  gone.obstacle.id = 2;
  gone.remove = true;
  EXPECT_FALSE(engine_->updateObstacle(gone));
  EXPECT_FALSE(engine_->updateObstacle(sphereAhead(first, 3, 40.0)));
}

TEST_F(EngineTest, ExpiredObstacleIsDropped) {
  ObstacleUpdateData update;
  update.obstacle.id = 7;
  update.obstacle.center_m = Eigen::Vector3d(0, 0, 2000);
  update.valid_from_utc_ns = clock_.now_ns;
  update.valid_until_utc_ns = clock_.now_ns + 2'000'000'000;
  ASSERT_FALSE(engine_->updateObstacle(update).has_value());
  EXPECT_EQ(world_->obstacleCount(), 1u);
  clock_.advance(1.0);
  engine_->replanCycle();
  EXPECT_EQ(world_->obstacleCount(), 1u);
  clock_.advance(1.5);
  engine_->replanCycle();
  EXPECT_EQ(world_->obstacleCount(), 0u);
  update.obstacle.size_m.x() = -1.0;
  const auto refused = engine_->updateObstacle(update);
  ASSERT_TRUE(refused.has_value());
  EXPECT_EQ(refused->field.rfind("size_m", 0), 0u);
  EXPECT_EQ(world_->obstacleCount(), 0u);
}

TEST_F(EngineTest, CancelQueuedAndActive) {
  ASSERT_FALSE(engine_->submit(request("q1")).has_value());
  EXPECT_TRUE(engine_->cancel(CancelRequestData{"q1", "uav-1"}));
  EXPECT_EQ(sink_.last("q1")->state, PlanState::kCancelled);
  EXPECT_FALSE(engine_->planNext());
  EXPECT_FALSE(engine_->cancel(CancelRequestData{"nothing", "uav-1"}));

  ASSERT_FALSE(engine_->submit(request("q2")).has_value());
  ASSERT_TRUE(engine_->planNext());
  EXPECT_EQ(engine_->activeMissions(), 1u);
  EXPECT_TRUE(engine_->cancel(CancelRequestData{"", "uav-1"}));
  EXPECT_EQ(sink_.last("q2")->state, PlanState::kCancelled);
  EXPECT_EQ(engine_->activeMissions(), 0u);
  EXPECT_EQ(sink_.retracted, std::vector<std::string>{"uav-1"});
}

TEST_F(EngineTest, ThreadsServeSeveralVehiclesAndStopPromptly) {
  engine_->start();
  std::vector<std::string> ids;
  for (int v = 0; v < 4; ++v) {
    MissionRequestData r = request("t" + std::to_string(v), "uav-" + std::to_string(v));
    r.begin = enu(-4500 + 300 * v, -4500, 150);
    ids.push_back(r.request_id);
    ASSERT_FALSE(engine_->submit(r).has_value());
  }
  ASSERT_TRUE(sink_.waitTerminal(ids, 120.0));
  for (const auto& id : ids) EXPECT_EQ(sink_.last(id)->state, PlanState::kSucceeded) << sink_.last(id)->message;
  EXPECT_EQ(engine_->activeMissions(), 4u);
  EXPECT_EQ(engine_->status("svc").vehicles, 4u);

  // A large mission in flight is cancelled by stop() well within a second.
  MissionRequestData big = request("big", "uav-big");
  for (int i = 0; i < 12; ++i) big.points.push_back(enu(-4000 + 700 * i, 600 * (i % 5) - 1500, 250));
  ASSERT_FALSE(engine_->submit(big).has_value());
  std::this_thread::sleep_for(std::chrono::milliseconds(100));
  const auto stop_started = std::chrono::steady_clock::now();
  engine_->stop();
  const double stop_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - stop_started).count();
  EXPECT_LT(stop_s, 1.0);
  ASSERT_TRUE(sink_.last("big").has_value());
  EXPECT_TRUE(sink_.last("big")->state == PlanState::kCancelled || sink_.last("big")->state == PlanState::kSucceeded);
  EXPECT_FALSE(engine_->running());
  const auto refused = engine_->submit(request("late"));
  ASSERT_TRUE(refused.has_value());
  EXPECT_EQ(refused->code, PlanErrorCode::kBusy);
}

}  // namespace
}  // namespace skyroute
