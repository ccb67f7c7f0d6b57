// A loiter (a fixed wing's hold): entered from a flown state, it is continuous to the jerk, its
// arcs lie on the circle and fly it at its speed, one turn later it is in the same state again,
// and the whole passes the fixed wing's limits with no violation, bank included.
#include <cmath>
#include <numbers>

#include <gtest/gtest.h>

#include "tests/trajectory/fixed_wing_vehicle.hpp"
#include "trajectory/feasibility.hpp"
#include "trajectory/loiter.hpp"

namespace skyroute {
namespace {

VehicleLimits fixedWing() { return testing::fixedWingVehicle(); }

// Flying north-east, climbing gently, already turning a little.
TrajectoryState entryState() {
  TrajectoryState s;
  s.position_m = {100.0, -50.0, 600.0};
  s.velocity_mps = {17.0, 17.0, 2.0};
  s.acceleration_mps2 = {-0.5, 0.5, 0.0};
  s.jerk_mps3 = {0.1, 0.0, 0.0};
  return s;
}

TEST(Loiter, EnteredFromAFlownStateItIsContinuousRepeatsAndKeepsTheFixedWingsLimits) {
  const VehicleLimits limits = fixedWing();
  for (bool left : {true, false}) {
    LoiterShape shape;
    shape.turning_left = left;
    shape.speed_mps = 25.0;
    shape.radius_m = 1.3 * limits.turnRadiusAtM(shape.speed_mps);
    shape.lead_m = 0.5 * shape.radius_m * shape.join_turn_rad;
    auto path = loiterFrom(entryState(), shape, 100.0);
    ASSERT_TRUE(path.ok()) << path.error().describe();
    const Trajectory t(path->segments);
    ASSERT_GE(t.duration_s(), 100.0);
    // The entry state exactly.
    const TrajectoryState start = t.stateAt(0.0);
    EXPECT_LT((start.position_m - entryState().position_m).norm(), 1e-9);
    EXPECT_LT((start.velocity_mps - entryState().velocity_mps).norm(), 1e-9);
    EXPECT_LT((start.acceleration_mps2 - entryState().acceleration_mps2).norm(), 1e-9);
    EXPECT_LT((start.jerk_mps3 - entryState().jerk_mps3).norm(), 1e-9);
    // Continuous to the jerk at every joint.
    const auto& segments = t.segments();
    for (std::size_t j = 0; j + 1 < segments.size(); ++j)
      for (Derivative d : {Derivative::kPosition, Derivative::kVelocity, Derivative::kAcceleration, Derivative::kJerk}) {
        const Eigen::Vector3d a = segments[j].evaluate(segments[j].duration_s, d);
        const Eigen::Vector3d b = segments[j + 1].evaluate(0.0, d);
        ASSERT_LT((a - b).norm(), 1e-6 * std::max(1.0, a.norm())) << "joint " << j;
      }
    // After the entry: on the circle, at its speed, level, turning to the chosen side.
    const LoiterCircle& c = path->circle;
    const double join_s = segments.front().duration_s;
    for (double s = join_s; s < t.duration_s(); s += 0.37) {
      const TrajectoryState state = t.stateAt(s);
      const Eigen::Vector3d off = state.position_m - c.center_m;
      EXPECT_NEAR(std::hypot(off.x(), off.y()), c.radius_m, 1e-3) << s;
      EXPECT_NEAR(off.z(), 0.0, 1e-6) << s;
      EXPECT_NEAR(state.velocity_mps.norm(), c.speed_mps, 1e-3 * c.speed_mps) << s;
      const double turn = off.x() * state.velocity_mps.y() - off.y() * state.velocity_mps.x();
      EXPECT_EQ(turn > 0.0, left) << s;
    }
    // One turn later the same state.
    const TrajectoryState a = t.stateAt(join_s + 1.0), b = t.stateAt(join_s + 1.0 + c.turnS());
    EXPECT_LT((a.position_m - b.position_m).norm(), 1e-6);
    EXPECT_LT((a.velocity_mps - b.velocity_mps).norm(), 1e-6);
    // The fixed wing's limits, bank and minimum airspeed included.
    const FeasibilityReport check = checkFeasibility(t, limits);
    EXPECT_TRUE(check.ok()) << (check.violations.empty() ? "" : std::string(to_string(check.violations.front().kind)));
    EXPECT_GE(check.min_speed_mps, limits.minAirspeedMps());
    EXPECT_LE(check.max_bank_deg, limits.max_bank_deg);
    EXPECT_GT(check.max_bank_deg, 20.0);  // it does turn, near the bank the radius asks for
    // More arcs continue the last one exactly.
    const std::vector<Segment> more = loiterArcs(c, path->end_angle_rad, 3);
    ASSERT_EQ(more.size(), 3u);
    const Segment& last = segments.back();
    for (Derivative d : {Derivative::kPosition, Derivative::kVelocity, Derivative::kAcceleration, Derivative::kJerk})
      EXPECT_LT((last.evaluate(last.duration_s, d) - more.front().evaluate(0.0, d)).norm(), 1e-6);
  }
}

TEST(Loiter, BadEntriesAndShapesAreRefusedByName) {
  LoiterShape shape;
  shape.radius_m = 120.0;
  shape.speed_mps = 25.0;
  TrajectoryState hovering;
  hovering.velocity_mps = {0.0, 0.0, 3.0};
  auto refused = loiterFrom(hovering, shape, 60.0);
  ASSERT_FALSE(refused.ok());
  EXPECT_EQ(refused.error().field, "loiter.entry");
  shape.radius_m = std::numeric_limits<double>::quiet_NaN();
  refused = loiterFrom(entryState(), shape, 60.0);
  ASSERT_FALSE(refused.ok());
  EXPECT_EQ(refused.error().field, "loiter.shape");
}

}  // namespace
}  // namespace skyroute
