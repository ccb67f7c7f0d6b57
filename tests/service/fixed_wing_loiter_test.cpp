// A fixed wing cannot stop: when its way is blocked and no plan helps, its hold is a loiter. The
// new revision keeps the flown curve from now, enters a circle and flies it; an independent
// sampler of its positions (tests/fixed_wing_sampler.hpp) finds it never under the minimum
// airspeed, within the bank and path angles and above the terrain clearance everywhere; it stays
// clear of the obstacle, gets more turns before it ends, and once the way is free the next cycle
// plans on from a point on the circle, at the circle's velocity. With no clear circle the step
// says so (field "loiter") and the current trajectory stays in force.
#include <algorithm>
#include <cmath>
#include <cstdio>

#include <gtest/gtest.h>

#include "service/flight_replanner.hpp"
#include "service/moving_obstacle_scenario.hpp"
#include "terrain/terrain_world.hpp"
#include "tests/fixed_wing_sampler.hpp"
#include "tests/test_data.hpp"
#include "trajectory/feasibility.hpp"

namespace skyroute {
namespace {

struct StraightRoute {
  std::shared_ptr<CollisionWorld> collision;
  std::shared_ptr<const Heightfield> terrain;
  std::vector<Eigen::Vector3d> points;
};

// West to east across the embedded terrain, 300 m above the ground at both ends.
StraightRoute straightRoute(const CollisionWorldOptions& options) {
  auto world = loadTerrainWorld(testing::projectDataPath("default_terrain.tif"), options);
  EXPECT_TRUE(world.ok()) << world.error().describe();
  if (!world.ok()) return {};
  const Heightfield& terrain = *world->heightfield;
  const Eigen::AlignedBox2d box = terrain.boundsEn();
  auto above = [&](double e, double n) { return Eigen::Vector3d(e, n, terrain.heightAt(e, n) + 300.0); };
  const double w = box.sizes().x(), north = box.center().y();
  return {world->collision, world->heightfield, {above(box.min().x() + 0.1 * w, north), above(box.max().x() - 0.1 * w, north)}};
}

CollisionWorldOptions worldOptions() {
  CollisionWorldOptions options = seed003ScenarioWorldOptions();
  options.ceiling_m = 12000.0;
  return options;
}

ReplanOptions replanOptions() {
  ReplanOptions options;
  options.route.seed = 7;
  options.route.leg_budget_ms = 0.0;  // iteration budgets: the same result on any machine
  options.route.leg_max_iterations = 3000;
  options.route.corridor_margin_m = 4000.0;
  options.replan_budget_ms = 0.0;
  options.replan_leg_max_iterations = 200;
  options.max_attempts = 2;
  return options;
}

// The revision in force from world time from_s to to_s as published samples (equal steps).
TrajectoryData flown(const FlightReplanner& r, double from_s, double to_s, double dt_s = 0.05) {
  TrajectoryData data;
  for (std::size_t k = 0;; ++k) {
    const double t = from_s + dt_s * static_cast<double>(k);
    if (t > to_s) break;
    TrajectorySampleData s;
    s.t_rel_s = dt_s * static_cast<double>(k);
    const TrajectoryState state = r.stateAt(t);
    s.position_enu_m = state.position_m;
    s.velocity_enu_mps = state.velocity_mps;
    data.samples.push_back(s);
  }
  return data;
}

void expectContinuousToJerk(const Trajectory& t, const char* what) {
  const auto& segments = t.segments();
  for (std::size_t j = 0; j + 1 < segments.size(); ++j) {
    for (Derivative d : {Derivative::kPosition, Derivative::kVelocity, Derivative::kAcceleration, Derivative::kJerk}) {
      const Eigen::Vector3d left = segments[j].evaluate(segments[j].duration_s, d);
      const Eigen::Vector3d right = segments[j + 1].evaluate(0.0, d);
      ASSERT_LT((left - right).norm(), 1e-6 * std::max(1.0, left.norm())) << what << ": joint " << j;
    }
  }
}

void expectSameState(const TrajectoryState& a, const TrajectoryState& b, const std::string& where) {
  EXPECT_LT((a.position_m - b.position_m).norm(), 1e-6) << where;
  EXPECT_LT((a.velocity_mps - b.velocity_mps).norm(), 1e-6) << where;
  EXPECT_LT((a.acceleration_mps2 - b.acceleration_mps2).norm(), 1e-6) << where;
  EXPECT_LT((a.jerk_mps3 - b.jerk_mps3).norm(), 1e-5) << where;
}

class FixedWingLoiter : public ::testing::Test {
 protected:
  void SetUp() override {
    route_ = straightRoute(world_options_);
    ASSERT_TRUE(route_.collision);
    auto replanner = FlightReplanner::start(route_.collision, route_.points, limits_, options_, 0.0);
    ASSERT_TRUE(replanner.ok()) << replanner.error().describe();
    replanner_ = std::move(*replanner);
  }

  // The goal inside a sphere: no plan can reach it.
  Obstacle overGoal() const {
    Obstacle o;
    o.id = 9;
    o.shape = ObstacleShape::kSphere;
    o.size_m = Eigen::Vector3d::Constant(400.0);
    o.center_m = route_.points.back();
    return o;
  }

  testing::FixedWingFlight sampled(const TrajectoryData& data) const {
    testing::FixedWingEnvelope envelope = testing::envelopeOf(limits_data_);
    envelope.min_clearance_m = world_options_.min_clearance_m;
    return testing::sampleFixedWing(data, envelope, [&](double e, double n) { return route_.terrain->heightAt(e, n); });
  }

  const CollisionWorldOptions world_options_ = worldOptions();
  const ReplanOptions options_ = replanOptions();
  const VehicleLimitsData limits_data_ = testing::fixedWingTestLimits();
  const VehicleLimits limits_ = toVehicleLimits(limits_data_);
  StraightRoute route_;
  std::unique_ptr<FlightReplanner> replanner_;
};

TEST_F(FixedWingLoiter, ABlockedWayMakesALoiterWithinTheLimitsThenPlansOnFromIt) {
  FlightReplanner& r = *replanner_;
  const Trajectory before = r.route().built.trajectory;
  const double now_s = before.duration_s() - 35.0;
  const Obstacle blocking = overGoal();
  route_.collision->upsertObstacle(blocking);

  const ReplanStep step = r.step(now_s);
  ASSERT_TRUE(step.holding) << (step.failure ? step.failure->describe() : std::string("no failure"))
                            << (step.hold_failure ? " / " + step.hold_failure->describe() : std::string());
  // Independently, from the positions alone: never under the minimum airspeed, within the bank
  // and path angles, above the clearance; and outside the obstacle grown by the vehicle radius.
  const TrajectoryData data = flown(r, now_s, r.arrivalWorldS());
  const testing::FixedWingFlight f = sampled(data);
  EXPECT_TRUE(f.violations.empty()) << testing::joined(f.violations);
  EXPECT_GE(f.checked, data.samples.size() - 2);
  EXPECT_GE(f.min_speed_mps, limits_.minAirspeedMps());
  EXPECT_GT(f.max_bank_deg, 15.0);  // it does circle
  std::printf("hold: sampled speed %.2f..%.2f m/s, bank <= %.1f deg, clearance >= %.0f m\n", f.min_speed_mps,
              f.max_speed_mps, f.max_bank_deg, f.min_clearance_m);
  for (const TrajectorySampleData& s : data.samples)
    ASSERT_FALSE(blocking.contains(s.position_enu_m, 0.0, world_options_.vehicle_radius_m)) << s.t_rel_s;
  EXPECT_TRUE(step.loiter);
  ASSERT_TRUE(step.failure.has_value());
  EXPECT_TRUE(r.holding());
  ASSERT_TRUE(r.loiterCircle().has_value());
  const LoiterCircle circle = *r.loiterCircle();
  std::printf("loiter: radius %.0f m at %.1f m/s\n", circle.radius_m, circle.speed_mps);
  EXPECT_GE(circle.radius_m, limits_.turnRadiusAtM(circle.speed_mps) * options_.loiter_radius_margin * (1.0 - 1e-9));
  EXPECT_GE(circle.speed_mps, limits_.minAirspeedMps());
  const Trajectory& hold = r.route().built.trajectory;
  EXPECT_LE(r.trajectoryStartWorldS(), now_s + 1e-9);
  expectSameState(before.stateAt(now_s), r.stateAt(now_s), "now");
  expectContinuousToJerk(hold, "loiter");
  const FeasibilityReport check = checkFeasibility(hold, limits_);
  EXPECT_TRUE(check.ok()) << check.violations.size() << " violation(s), first "
                          << (check.violations.empty() ? "" : std::string(to_string(check.violations.front().kind)));
  // Flown for at least the horizon, so the next cycles plan on from a point on it.
  EXPECT_GE(r.arrivalWorldS() - now_s, options_.horizon_s);
  EXPECT_FALSE(r.finished(r.arrivalWorldS() + 10.0)) << "a loiter does not finish the mission";
  EXPECT_TRUE(r.clearAhead(now_s, options_.horizon_s));
  // Still blocked: the cycles keep the loiter, and before it ends it gets more turns of the same
  // circle (a new revision, the same curve from then on).
  const double late_s = r.arrivalWorldS() - options_.horizon_s + 0.5;
  const Trajectory loiter = r.route().built.trajectory;
  const double loiter_start_s = r.trajectoryStartWorldS();
  const std::uint32_t revision = r.revision();
  const ReplanStep extended = r.step(late_s);
  EXPECT_TRUE(extended.holding);
  EXPECT_EQ(r.revision(), revision + 1);
  EXPECT_GE(r.arrivalWorldS() - late_s, 1.5 * options_.horizon_s);
  expectSameState(loiter.stateAt(late_s + 1.0 - loiter_start_s), r.stateAt(late_s + 1.0), "extended");
  expectContinuousToJerk(r.route().built.trajectory, "extended loiter");
  EXPECT_TRUE(sampled(flown(r, late_s, r.arrivalWorldS())).violations.empty());

  // The way is free: the next cycle plans on from a point on the circle, at its velocity.
  route_.collision->removeObstacle(blocking.id);
  const double free_s = late_s + 5.0;
  const ReplanStep next = r.step(free_s);
  ASSERT_TRUE(next.replanned) << (next.failure ? next.failure->describe() : std::string("no failure"));
  EXPECT_FALSE(r.holding());
  EXPECT_FALSE(r.loiterCircle().has_value());
  const TrajectoryState takeover = r.stateAt(next.takeover_s);
  const Eigen::Vector3d off = takeover.position_m - circle.center_m;
  EXPECT_NEAR(std::hypot(off.x(), off.y()), circle.radius_m, 0.01);
  EXPECT_NEAR(takeover.velocity_mps.norm(), circle.speed_mps, 0.01 * circle.speed_mps);
  EXPECT_LT((r.stateAt(r.arrivalWorldS()).position_m - route_.points.back()).norm(), 1e-3);
  const testing::FixedWingFlight onward = sampled(flown(r, free_s, r.arrivalWorldS()));
  EXPECT_TRUE(onward.violations.empty()) << testing::joined(onward.violations);
}

TEST_F(FixedWingLoiter, NoClearCircleIsNamedAndTheCurrentTrajectoryStays) {
  // Circles far wider than the map: none is clear.
  ReplanOptions options = options_;
  options.loiter_radius_margin = 40.0;
  auto replanner = FlightReplanner::start(route_.collision, route_.points, limits_, options, 0.0);
  ASSERT_TRUE(replanner.ok()) << replanner.error().describe();
  FlightReplanner& r = **replanner;
  const Trajectory before = r.route().built.trajectory;
  const double now_s = before.duration_s() - 35.0;
  route_.collision->upsertObstacle(overGoal());
  const ReplanStep step = r.step(now_s);
  EXPECT_FALSE(step.holding);
  EXPECT_FALSE(step.replanned);
  ASSERT_TRUE(step.failure.has_value());
  ASSERT_TRUE(step.hold_failure.has_value());
  EXPECT_EQ(step.hold_failure->code, ErrorCode::kUnreachable);
  EXPECT_EQ(step.hold_failure->field, "loiter");
  EXPECT_NE(step.hold_failure->message.find("no loiter circle is clear"), std::string::npos) << step.hold_failure->message;
  EXPECT_EQ(r.revision(), 0u);
  EXPECT_FALSE(r.holding());
  expectSameState(before.stateAt(now_s + 10.0), r.stateAt(now_s + 10.0), "kept");
}

TEST(FixedWingLoiterOptions, ALoiterRadiusMarginUnderOneIsRefusedByName) {
  ReplanOptions options = replanOptions();
  options.loiter_radius_margin = 0.8;
  auto r = FlightReplanner::start(nullptr, {Eigen::Vector3d::Zero(), Eigen::Vector3d::UnitX()}, VehicleLimits{}, options, 0.0);
  ASSERT_FALSE(r.ok());
  EXPECT_EQ(r.error().field, "loiter_radius_margin");
}

}  // namespace
}  // namespace skyroute
