// A flying fleet replanned by the engine around obstacles (fleet_replanner.hpp), judged only from
// what the engine published: the revision in force at each instant (a revision holds from its
// first sample until the next revision of that vehicle), sampled in continuous time by the test
// itself against the obstacles' actual motion, the other vehicles, the tasks and the grid checker.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <set>
#include <utility>

#include "planning/fleet/fleet_conflict_checker.hpp"
#include "service/engine.hpp"
#include "service/fleet_replanner.hpp"
#include "service/mission_pipeline.hpp"
#include "tests/service/default_world_fixture.hpp"
#include "tests/service/fleet_flown.hpp"
#include "tests/service/recording_sink.hpp"

namespace skyroute {
namespace {

constexpr std::int64_t kStartNs = 1'800'000'000'000'000'000LL;
constexpr double kSeparationM = 150.0;  // above the grid cell's diagonal: one vehicle per cell
using testing::RecordingSink;

using testing::endS;
using testing::FleetFlown;
using testing::sampledAt;
using testing::startS;

std::int64_t seconds(double s) { return static_cast<std::int64_t>(std::llround(s * 1e9)); }

class FleetReplanTest : public testing::DefaultWorldTest {
 protected:
  void SetUp() override {
    DefaultWorldTest::SetUp();
    EngineOptions options;
    options.pipeline.fleet.min_separation_m = kSeparationM;
    auto engine = Engine::create(world_, options, sink_, [this] { return now_ns_; });
    ASSERT_TRUE(engine.ok()) << engine.error().describe();
    engine_ = std::move(*engine);
  }

  // Five vehicles round the map, fifteen tasks spread over it.
  FleetRequestData fiveByFifteen() const {
    FleetRequestData r;
    r.request_id = "fleet-replan";
    r.vehicle_ids = {"uav-a", "uav-b", "uav-c", "uav-d", "uav-e"};
    r.begins = {enu(-4000, -4000, 100), enu(4000, -4000, 100), enu(-4000, 4000, 100), enu(4000, 4000, 100),
                enu(0, -4500, 100)};
    r.ends = r.begins;
    const double spots[15][2] = {{-2500, -1500}, {-1000, -3000}, {1500, -2500}, {3000, -1000}, {2500, 1500},
                                 {-3000, 1000},  {-1500, 3000},  {0, 0},        {1500, 3500},  {-3500, -2500},
                                 {2000, -500},   {-500, 1800},   {3500, 2800},  {-2000, 500},  {500, -1500}};
    for (const auto& s : spots) r.tasks.push_back(enu(s[0], s[1], 150));
    return r;
  }

  // A vertical column (reaching every altitude of the band) moving at constant velocity from now.
  ObstacleUpdateData column(std::uint64_t id, double e, double n, double ve, double vn, double radius_m) const {
    ObstacleUpdateData u;
    u.obstacle.id = id;
    u.obstacle.shape = ObstacleShape::kCylinder;
    u.obstacle.size_m = Eigen::Vector3d(radius_m, radius_m, 2500.0);
    u.obstacle.center_m = Eigen::Vector3d(e, n, 1000.0);
    if (ve != 0.0 || vn != 0.0) u.constant_velocity_enu_mps = Eigen::Vector3d(ve, vn, 0.0);
    u.valid_from_utc_ns = now_ns_;
    return u;
  }

  void planFleet(const FleetRequestData& r) {
    ASSERT_FALSE(engine_->submitFleet(r).has_value());
    ASSERT_TRUE(engine_->planNext());
    ASSERT_EQ(sink_.fleet.back().state, PlanState::kSucceeded) << sink_.fleet.back().message;
    ASSERT_EQ(sink_.trajectories.size(), r.vehicle_ids.size());
  }
  // A column (radius 120 m) sent now that passes `meet` at meet_s moving at `velocity`, two
  // replanning cycles, a clean replanned status; returns the column and `vehicle`'s new revisions.
  std::pair<ObstacleUpdateData, std::vector<TrajectoryData>> columnThrough(std::uint64_t id, const Eigen::Vector3d& meet,
                                                                          double meet_s, const Eigen::Vector2d& velocity,
                                                                          const std::string& vehicle) {
    const double now_s = static_cast<double>(now_ns_) * 1e-9;
    const Eigen::Vector2d from = meet.head<2>() - velocity * (meet_s - now_s);
    const ObstacleUpdateData update = column(id, from.x(), from.y(), velocity.x(), velocity.y(), 120.0);
    EXPECT_FALSE(engine_->updateObstacle(update).has_value());
    const std::size_t published_before = sink_.trajectories.size();
    cycle();
    now_ns_ += seconds(0.1);
    cycle();
    const FleetStatusData& status = sink_.fleet.back();
    EXPECT_EQ(status.state, PlanState::kReplanned);
    EXPECT_TRUE(status.field.empty()) << status.message;
    std::vector<TrajectoryData> revised;
    for (std::size_t k = published_before; k < sink_.trajectories.size(); ++k)
      if (sink_.trajectories[k].vehicle_id == vehicle) revised.push_back(sink_.trajectories[k]);
    return {update, revised};
  }

  // A column (radius 120 m) sent now, moving at `velocity`, that is where `vehicle` of the plan
  // `first` is at_s after the start.
  ObstacleUpdateData columnAimedAt(const std::vector<TrajectoryData>& first, std::uint64_t id, const std::string& vehicle,
                                   double at_s, const Eigen::Vector2d& velocity) const {
    const TrajectoryData& t = *std::find_if(first.begin(), first.end(), [&](const TrajectoryData& f) {
      return f.vehicle_id == vehicle;
    });
    const double now_s = static_cast<double>(now_ns_) * 1e-9;
    const Eigen::Vector3d meet = sampledAt(t, kStartNs * 1e-9 + at_s);
    const Eigen::Vector2d from = meet.head<2>() - velocity * (kStartNs * 1e-9 + at_s - now_s);
    return column(id, from.x(), from.y(), velocity.x(), velocity.y(), 120.0);
  }

  // One replanning cycle and the fleet replan job it queues, at now_ns_.
  void cycle() {
    engine_->replanCycle();
    while (engine_->planNext()) {
    }
  }

  // The independent checks of everything published: every task served exactly once, no vehicle
  // inside an obstacle (its actual motion) while flying, the separation kept between every pair.
  void expectCleanFlight(const FleetRequestData& r, const std::vector<ObstacleUpdateData>& updates) const {
    const FleetFlown flown(sink_.trajectories, r.request_id);
    for (std::uint32_t j = 0; j < r.tasks.size(); ++j) {
      const auto served = flown.servings(j);
      ASSERT_EQ(served.size(), 1u) << "task " << j;
      const Eigen::Vector3d p = flown.positionAt(served[0].first, served[0].second);
      EXPECT_LT((p.head<2>() - r.tasks[j].enu_m.head<2>()).norm(), 3.0) << "task " << j;
    }
    const double radius_m = WorldModelOptions{}.vehicle_radius_m;
    std::vector<Obstacle> obstacles;
    for (const ObstacleUpdateData& u : updates) obstacles.push_back(worldObstacle(u, 3600.0));
    double closest_obstacle_m = std::numeric_limits<double>::infinity();
    for (const std::string& v : r.vehicle_ids) {
      for (double t = flown.beginOf(v); t <= flown.endOf(v); t += 0.05) {
        const Eigen::Vector3d p = flown.positionAt(v, t);
        for (std::size_t k = 0; k < obstacles.size(); ++k) {
          if (t < static_cast<double>(updates[k].valid_from_utc_ns) * 1e-9) continue;
          if (updates[k].valid_until_utc_ns != 0 && t >= static_cast<double>(updates[k].valid_until_utc_ns) * 1e-9) continue;
          ASSERT_FALSE(obstacles[k].contains(p, t, radius_m)) << v << " inside obstacle " << k << " at t=" << t;
          closest_obstacle_m = std::min(closest_obstacle_m, (p - obstacles[k].centerAt(t)).head<2>().norm());
        }
      }
    }
    double last_end = 0.0;
    for (const std::string& v : r.vehicle_ids) last_end = std::max(last_end, flown.endOf(v));
    double closest_m = std::numeric_limits<double>::infinity();
    for (double t = kStartNs * 1e-9; t <= last_end; t += 0.1) {
      std::vector<Eigen::Vector3d> at;
      for (const std::string& v : r.vehicle_ids) at.push_back(flown.positionAt(v, t));
      for (std::size_t a = 0; a < at.size(); ++a)
        for (std::size_t b = a + 1; b < at.size(); ++b) closest_m = std::min(closest_m, (at[a] - at[b]).norm());
    }
    EXPECT_GE(closest_m, kSeparationM - 0.5);
    std::printf("closest pair %.1f m, closest obstacle axis %.1f m\n", closest_m, closest_obstacle_m);
  }

  // The grid checker on the cells the vehicles occupy in the flight band, one sample per grid step
  // (a cell of the plan's size, 99 m, flown at the cruise speed; the plan's own grid is checked
  // only through the separation).
  void expectNoGridConflicts(const FleetRequestData& r) const {
    const double cell_m = 99.0;
    const double step_s = cell_m / r.limits.v_ref_mps;
    const FleetFlown flown(sink_.trajectories, r.request_id);
    const GridLayer grid(static_cast<int>(std::ceil(heightfield_->boundsEn().sizes().x() / cell_m)) + 2,
                         static_cast<int>(std::ceil(heightfield_->boundsEn().sizes().y() / cell_m)) + 2, cell_m,
                         heightfield_->boundsEn().min() - Eigen::Vector2d(cell_m, cell_m));
    double last_end = 0.0;
    for (const std::string& v : r.vehicle_ids) last_end = std::max(last_end, flown.endOf(v));
    FleetProblem problem;
    std::vector<std::vector<GridCell>> paths(r.vehicle_ids.size());
    for (std::size_t i = 0; i < r.vehicle_ids.size(); ++i) {
      problem.vehicles.push_back({r.vehicle_ids[i], *grid.cellAt(r.begins[i].enu_m.head<2>()), 0});
      double cruise_m = 0.0;
      for (double t = kStartNs * 1e-9; t <= last_end; t += 1.0) cruise_m = std::max(cruise_m, flown.positionAt(r.vehicle_ids[i], t).z());
      for (double t = kStartNs * 1e-9; t <= last_end + step_s; t += step_s) {
        const Eigen::Vector3d p = flown.positionAt(r.vehicle_ids[i], t);
        // Below the band (climbing, landed) a vehicle is in no cell of it: its own off-grid cell.
        paths[i].push_back(p.z() > cruise_m - 50.0 ? *grid.cellAt(p.head<2>()) : GridCell{-1 - static_cast<int>(i), -1});
      }
    }
    const FleetCheckReport report = checkFleetPlan(grid, problem, paths, std::vector<std::vector<int>>(paths.size()));
    EXPECT_TRUE(report.conflicts.empty()) << report.summary();
  }

  RecordingSink sink_;
  std::int64_t now_ns_ = kStartNs;
  std::unique_ptr<Engine> engine_;
};

TEST_F(FleetReplanTest, ThreeCrossingObstaclesFiveVehiclesFifteenTasks) {
  const FleetRequestData r = fiveByFifteen();
  planFleet(r);
  const std::vector<TrajectoryData> first = sink_.trajectories;

  now_ns_ += seconds(60.0);
  // Three columns, each aimed at where one vehicle will be: uav-a at 300 s, uav-c at 450 s and
  // uav-d at 600 s after the start, crossing its path from the side.
  auto aimedAt = [&](std::uint64_t id, const std::string& vehicle, double at_s, const Eigen::Vector2d& velocity) {
    return columnAimedAt(first, id, vehicle, at_s, velocity);
  };
  const std::vector<ObstacleUpdateData> updates = {aimedAt(1, "uav-a", 300.0, Eigen::Vector2d(0.0, 12.0)),
                                                   aimedAt(2, "uav-c", 450.0, Eigen::Vector2d(10.0, -6.0)),
                                                   aimedAt(3, "uav-d", 600.0, Eigen::Vector2d(-8.0, 0.0))};
  // Which vehicles the obstacles meet, by the test's own sampling of the first plan (the
  // engine's margin of 30 m round the vehicle's sphere).
  std::set<std::string> meeting;
  for (const TrajectoryData& t : first) {
    for (double s = static_cast<double>(now_ns_) * 1e-9; s <= endS(t); s += 0.5) {
      for (const ObstacleUpdateData& u : updates) {
        if (worldObstacle(u, 3600.0).contains(sampledAt(t, s), s, 35.0)) meeting.insert(t.vehicle_id);
      }
    }
  }
  ASSERT_GE(meeting.size(), 2u) << "the scenario must cross several vehicles' paths";
  ASSERT_LT(meeting.size(), r.vehicle_ids.size()) << "and leave at least one alone";
  for (const ObstacleUpdateData& u : updates) ASSERT_FALSE(engine_->updateObstacle(u).has_value());
  const std::size_t published_before = sink_.trajectories.size();
  const std::size_t fleet_before = sink_.fleet.size();
  cycle();
  // The next cycle: it goes on with any vehicle the first step's budget did not reach.
  now_ns_ += seconds(0.1);
  cycle();

  std::set<std::string> revised;
  for (std::size_t k = published_before; k < sink_.trajectories.size(); ++k) {
    const TrajectoryData& t = sink_.trajectories[k];
    revised.insert(t.vehicle_id);
    EXPECT_EQ(t.revision, 1u);
    EXPECT_EQ(t.plan_id, r.request_id + "-" + t.vehicle_id);
    // Continuous with the revision before where it starts (the kept curve).
    const TrajectoryData& before = *std::find_if(first.begin(), first.end(), [&](const TrajectoryData& f) {
      return f.vehicle_id == t.vehicle_id;
    });
    EXPECT_LT((sampledAt(before, startS(t)) - t.samples.front().position_enu_m).norm(), 0.5);
  }
  // Only the vehicles whose paths the obstacles cross (and any that took over a task) changed.
  ASSERT_GT(sink_.fleet.size(), fleet_before);
  const FleetStatusData& status = sink_.fleet.back();
  EXPECT_EQ(status.state, PlanState::kReplanned);
  for (const std::string& v : revised) EXPECT_TRUE(meeting.count(v) > 0) << v << " changed without meeting an obstacle";
  for (const std::string& v : meeting) EXPECT_TRUE(revised.count(v) > 0) << v << " meets an obstacle and was not replanned";

  expectCleanFlight(r, updates);
  expectNoGridConflicts(r);
  std::printf("meeting %zu vehicles, revised %zu, latency %.3f s\n", meeting.size(), revised.size(),
              status.planning_time_s);
}

// A column crosses uav-a's climb over its begin: a hover in the climb stays on the column's track
// and the band search turns away only once up there, so the vehicle steps aside at the altitude it
// is at, climbs there and flies on; every task is still served and nobody meets the column.
TEST_F(FleetReplanTest, AColumnCrossingAClimbIsSteppedAround) {
  const FleetRequestData r = fiveByFifteen();
  planFleet(r);
  const std::vector<TrajectoryData> first = sink_.trajectories;
  const TrajectoryData& a = first.front();
  ASSERT_EQ(a.vehicle_id, "uav-a");
  double cruise_m = 0.0;
  for (const TrajectorySampleData& x : a.samples) cruise_m = std::max(cruise_m, x.position_enu_m.z());

  now_ns_ += seconds(20.0);
  // Where uav-a is 70 s after the start: still climbing over its begin, well below the band.
  const double meet_s = kStartNs * 1e-9 + 70.0;
  const Eigen::Vector3d meet = sampledAt(a, meet_s);
  ASSERT_LT(meet.z(), cruise_m - 200.0) << "the column must meet uav-a in its climb";
  ASSERT_LT((meet.head<2>() - r.begins[0].enu_m.head<2>()).norm(), 150.0);
  const auto [update, revised] = columnThrough(4, meet, meet_s, Eigen::Vector2d(0.0, 10.0), "uav-a");
  EXPECT_FALSE(revised.empty());
  for (const TrajectoryData& t : revised) {
    EXPECT_LT((sampledAt(a, startS(t)) - t.samples.front().position_enu_m).norm(), 0.5);
    // It leaves the climb's vertical line below the band: the step aside.
    bool aside_below_band = false;
    for (const TrajectorySampleData& x : t.samples) {
      aside_below_band = aside_below_band || (x.position_enu_m.z() < cruise_m - 100.0 &&
                                              (x.position_enu_m.head<2>() - meet.head<2>()).norm() > 100.0);
    }
    EXPECT_TRUE(aside_below_band);
  }
  expectCleanFlight(r, {update});
  expectNoGridConflicts(r);
}

// A column crosses uav-a's descent onto its end, when the vehicle is already descending: it
// steps aside at the altitude it is at, holds there until the column has gone by, then lands,
// without climbing back to the band. (Seen while still on the band, a hover there does.)
TEST_F(FleetReplanTest, AColumnCrossingADescentIsSteppedAround) {
  const FleetRequestData r = fiveByFifteen();
  planFleet(r);
  const std::vector<TrajectoryData> first = sink_.trajectories;
  const TrajectoryData& a = first.front();
  ASSERT_EQ(a.vehicle_id, "uav-a");
  double cruise_m = 0.0;
  for (const TrajectorySampleData& x : a.samples) cruise_m = std::max(cruise_m, x.position_enu_m.z());

  // Where uav-a is 40 s before its end: descending onto it, well below the band.
  const double meet_s = endS(a) - 40.0;
  const Eigen::Vector3d meet = sampledAt(a, meet_s);
  ASSERT_LT(meet.z(), cruise_m - 200.0) << "the column must meet uav-a in its descent";
  ASSERT_LT((meet.head<2>() - r.ends[0].enu_m.head<2>()).norm(), 150.0);
  now_ns_ = seconds(meet_s - 30.0);
  const auto [update, revised] = columnThrough(5, meet, meet_s, Eigen::Vector2d(-10.0, 0.0), "uav-a");
  EXPECT_FALSE(revised.empty());
  for (const TrajectoryData& t : revised) {
    EXPECT_LT((sampledAt(a, startS(t)) - t.samples.front().position_enu_m).norm(), 0.5);
    EXPECT_LT((t.samples.back().position_enu_m - r.ends[0].enu_m).norm(), 1.0);
    double highest_m = 0.0;
    for (const TrajectorySampleData& x : t.samples) highest_m = std::max(highest_m, x.position_enu_m.z());
    EXPECT_LT(highest_m, cruise_m - 100.0) << "it climbs back to the band";
  }
  expectCleanFlight(r, {update});
  expectNoGridConflicts(r);
}

// An obstacle far from every vehicle's path: nothing is replanned, nothing published.
TEST_F(FleetReplanTest, AFarObstacleChangesNothing) {
  const FleetRequestData r = fiveByFifteen();
  planFleet(r);
  const std::vector<TrajectoryData> first = sink_.trajectories;
  now_ns_ += seconds(60.0);
  // The grid point farthest from every sample of every trajectory.
  Eigen::Vector2d farthest = Eigen::Vector2d::Zero();
  double far_m = 0.0;
  const Eigen::AlignedBox2d box = heightfield_->boundsEn();
  for (double e = box.min().x() + 300; e < box.max().x() - 300; e += 200) {
    for (double n = box.min().y() + 300; n < box.max().y() - 300; n += 200) {
      double closest = std::numeric_limits<double>::infinity();
      for (const TrajectoryData& t : first)
        for (const TrajectorySampleData& x : t.samples) closest = std::min(closest, (x.position_enu_m.head<2>() - Eigen::Vector2d(e, n)).norm());
      if (closest > far_m) {
        far_m = closest;
        farthest = Eigen::Vector2d(e, n);
      }
    }
  }
  ASSERT_GT(far_m, 600.0);
  ASSERT_FALSE(engine_->updateObstacle(column(7, farthest.x(), farthest.y(), 0.0, 0.0, 100.0)).has_value());
  const std::size_t fleet_before = sink_.fleet.size();
  cycle();
  EXPECT_EQ(sink_.trajectories.size(), first.size());
  EXPECT_EQ(sink_.fleet.size(), fleet_before);
}

// A column parks over a task for 200 s, before its vehicle gets there: no vehicle can serve it
// meanwhile, so it is dropped from its vehicle's route and the fleet status names it; when the
// column is gone the task goes to a vehicle still flying, and is served once.
TEST_F(FleetReplanTest, ATaskAnObstacleCoversIsReallocatedAndServed) {
  const FleetRequestData r = fiveByFifteen();
  planFleet(r);
  const std::vector<TrajectoryData> first = sink_.trajectories;
  now_ns_ += seconds(60.0);
  // uav-a's last task: it is still ahead when the column parks on it.
  const TrajectoryData& a = first.front();
  ASSERT_EQ(a.vehicle_id, "uav-a");
  ASSERT_GE(a.visiting_order.size(), 3u);
  const std::uint32_t task = a.visiting_order[a.visiting_order.size() - 2] - 1;
  ObstacleUpdateData parked = column(9, r.tasks[task].enu_m.x(), r.tasks[task].enu_m.y(), 0.0, 0.0, 150.0);
  parked.valid_until_utc_ns = now_ns_ + seconds(200.0);
  ASSERT_FALSE(engine_->updateObstacle(parked).has_value());
  const std::size_t published_before = sink_.trajectories.size();
  cycle();
  ASSERT_GT(sink_.trajectories.size(), published_before);
  const FleetStatusData& blocked = sink_.fleet.back();
  EXPECT_EQ(blocked.state, PlanState::kReplanned);
  EXPECT_EQ(blocked.field, "tasks[" + std::to_string(task) + "]") << blocked.message;
  for (const FleetVehicleAllocationData& v : blocked.allocation) {
    EXPECT_EQ(std::count(v.tasks.begin(), v.tasks.end(), task), 0) << v.vehicle_id;
  }
  // The column goes away; the next cycle offers the task again.
  now_ns_ += seconds(201.0);
  cycle();
  const FleetStatusData& taken = sink_.fleet.back();
  EXPECT_EQ(taken.state, PlanState::kReplanned);
  EXPECT_TRUE(taken.field.empty()) << taken.message;
  int holders = 0;
  for (const FleetVehicleAllocationData& v : taken.allocation) holders += static_cast<int>(std::count(v.tasks.begin(), v.tasks.end(), task));
  EXPECT_EQ(holders, 1);
  expectCleanFlight(r, {parked});
  expectNoGridConflicts(r);
}

// Every trajectory a fleet puts in force passes the audit: each vehicle's first one before the
// fleet is published, and each replanned revision before it is adopted; the service counts them.
TEST_F(FleetReplanTest, EveryTrajectoryOfAFleetIsAuditedAndCounted) {
  const FleetRequestData r = fiveByFifteen();
  planFleet(r);
  const ServiceStatusData planned = engine_->status("svc");
  EXPECT_EQ(planned.audits, r.vehicle_ids.size());
  EXPECT_EQ(planned.audit_failures, 0u);
  const std::vector<TrajectoryData> first = sink_.trajectories;
  now_ns_ += seconds(60.0);
  ASSERT_FALSE(engine_->updateObstacle(columnAimedAt(first, 1, "uav-a", 300.0, Eigen::Vector2d(0.0, 12.0))).has_value());
  cycle();
  now_ns_ += seconds(0.1);
  cycle();
  const std::size_t revisions = sink_.trajectories.size() - first.size();
  ASSERT_GE(revisions, 1u) << "the column must make the fleet replan";
  const ServiceStatusData replanned = engine_->status("svc");
  EXPECT_GE(replanned.audits, planned.audits + revisions) << "a published revision was not audited";
  EXPECT_EQ(replanned.audit_failures, 0u);
}

// A revision the audit refuses is never adopted: with an audit that refuses everything of uav-a,
// the column crossing its path leaves it unresolved on the revision in force, and nothing new of
// it is published.
TEST_F(FleetReplanTest, ARevisionTheAuditRefusesIsNeverAdopted) {
  const FleetRequestData r = fiveByFifteen();
  planFleet(r);
  const std::vector<TrajectoryData> first = sink_.trajectories;
  EngineOptions options;
  options.pipeline.fleet.min_separation_m = kSeparationM;
  const MissionPipeline pipeline(world_, options.pipeline);
  const FleetPlanOutput plan = pipeline.planFleet(r, kStartNs);
  ASSERT_TRUE(plan.ok()) << plan.status.message;
  FleetReplanOptions replan = options.pipeline.fleet_replan;
  std::size_t refused = 0;
  std::size_t passed = 0;
  replan.audit = [&](std::size_t vehicle, const Trajectory&, double, double, std::uint32_t) -> std::optional<Error> {
    if (vehicle != 0) {
      ++passed;
      return std::nullopt;
    }
    ++refused;
    return make_error(ErrorCode::kInternal, "audit", "refused by the test");
  };
  auto replanner = FleetReplanner::create(r, plan, world_, fleetMissionOptions(options.pipeline), replan, kStartNs * 1e-9);
  ASSERT_TRUE(replanner.ok()) << replanner.error().describe();
  now_ns_ += seconds(60.0);
  ASSERT_FALSE(engine_->updateObstacle(columnAimedAt(first, 1, "uav-a", 300.0, Eigen::Vector2d(0.0, 12.0))).has_value());
  const FleetReplanStep step = (*replanner)->step(static_cast<double>(now_ns_) * 1e-9, TerminationCondition{});
  ASSERT_TRUE(std::find(step.affected.begin(), step.affected.end(), 0u) != step.affected.end())
      << "the column must meet uav-a";
  EXPECT_GE(refused, 1u) << "no candidate of uav-a reached the audit";
  EXPECT_TRUE(std::find(step.changed.begin(), step.changed.end(), 0u) == step.changed.end());
  EXPECT_TRUE(std::find(step.unresolved.begin(), step.unresolved.end(), 0u) != step.unresolved.end());
  EXPECT_EQ((*replanner)->vehicle(0).revision, 0u);
  std::printf("audit refused %zu candidates of uav-a, passed %zu of the others\n", refused, passed);
}

}  // namespace
}  // namespace skyroute
