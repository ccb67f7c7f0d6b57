// The fixed-wing vehicle model: its fields are validated by name, its derived turn radius and load
// factor follow from the bank angle, its trajectories never hover (cruise speed at both ends, no
// stop at a fixed waypoint) and stay within its airspeed, bank, load factor and path angles as
// measured from positions alone, and a trajectory that breaks them is reported by kind.
#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>

#include <gtest/gtest.h>

#include "tests/trajectory/finite_differences.hpp"
#include "tests/trajectory/fixed_wing_vehicle.hpp"
#include "trajectory/trajectory_builder.hpp"

namespace skyroute {
namespace {

constexpr double kG = 9.80665;
constexpr double kRadToDeg = 180.0 / std::numbers::pi;

VehicleLimits glider() { return testing::fixedWingVehicle(); }

// Corners of about 106 degrees on 500 m legs, climbing gently then descending.
std::vector<Eigen::Vector3d> zigZag() {
  return {{0, 0, 500}, {300, 400, 520}, {600, 0, 540}, {900, 400, 560}, {1200, 0, 560}, {1500, 400, 540}};
}

// What positions alone say about the flight (central differences every 0.01 s).
struct Flown {
  double min_speed_mps = std::numeric_limits<double>::infinity();
  double max_speed_mps = 0.0;
  double max_bank_deg = 0.0;
  double max_climb_deg = 0.0;
  double max_descent_deg = 0.0;
};

Flown measure(const Trajectory& t) {
  Flown f;
  testing::forEachFiniteDifference(t, [&](double, const Eigen::Vector3d& v, const Eigen::Vector3d& a) {
    f.min_speed_mps = std::min(f.min_speed_mps, v.norm());
    f.max_speed_mps = std::max(f.max_speed_mps, v.norm());
    const double horizontal = std::hypot(v.x(), v.y());
    // A coordinated turn banks so that lift's horizontal part gives the turn's acceleration.
    const double across = std::abs(v.x() * a.y() - v.y() * a.x()) / horizontal;
    f.max_bank_deg = std::max(f.max_bank_deg, std::atan2(across, kG) * kRadToDeg);
    const double gamma = std::atan2(v.z(), horizontal) * kRadToDeg;
    f.max_climb_deg = std::max(f.max_climb_deg, gamma);
    f.max_descent_deg = std::max(f.max_descent_deg, -gamma);
  });
  return f;
}

TEST(FixedWingLimits, EachBadFieldIsNamed) {
  const std::pair<const char*, void (*)(VehicleLimits&)> cases[] = {
      {"limits.stall_speed_mps", [](VehicleLimits& l) { l.stall_speed_mps = 0.0; }},
      {"limits.stall_speed_mps", [](VehicleLimits& l) { l.stall_speed_mps = std::nan(""); }},
      {"limits.stall_margin", [](VehicleLimits& l) { l.stall_margin = 0.9; }},
      {"limits.max_bank_deg", [](VehicleLimits& l) { l.max_bank_deg = 0.0; }},
      {"limits.max_bank_deg", [](VehicleLimits& l) { l.max_bank_deg = 85.0; }},
      {"limits.max_climb_angle_deg", [](VehicleLimits& l) { l.max_climb_angle_deg = -5.0; }},
      {"limits.max_descent_angle_deg", [](VehicleLimits& l) { l.max_descent_angle_deg = 75.0; }},
      {"limits.v_ref_mps", [](VehicleLimits& l) { l.v_ref_mps = 19.0; }},  // under 15 x 1.3
      {"limits.v_ref_mps", [](VehicleLimits& l) { l.max_speed_mps = 20.0; }},
  };
  ASSERT_TRUE(glider().validate().ok());
  for (const auto& [field, spoil] : cases) {
    VehicleLimits l = glider();
    spoil(l);
    Status s = l.validate();
    ASSERT_FALSE(s.ok()) << field;
    EXPECT_EQ(s.error().field, field);
  }
  // A multirotor ignores the fixed-wing fields.
  VehicleLimits multirotor = glider();
  multirotor.model = VehicleModel::kMultirotor;
  multirotor.stall_speed_mps = 0.0;
  multirotor.max_bank_deg = 0.0;
  EXPECT_TRUE(multirotor.validate().ok());
}

TEST(FixedWingLimits, TurnRadiusAndLoadFactorFollowFromTheBank) {
  const VehicleLimits l = glider();
  // Level coordinated turn: L cos(phi) = m g, L sin(phi) = m V^2 / R.
  const double phi = 35.0 / kRadToDeg;
  EXPECT_NEAR(l.turnRadiusAtM(25.0), 625.0 / (kG * std::tan(phi)), 1e-9);
  EXPECT_NEAR(l.turnRadiusAtM(25.0), 91.02, 0.01);
  EXPECT_NEAR(l.turnRadiusAtM(50.0), 4.0 * l.turnRadiusAtM(25.0), 1e-9);
  EXPECT_NEAR(l.maxLoadFactor(), 1.2208, 1e-4);
  EXPECT_NEAR(l.minAirspeedMps(), 19.5, 1e-12);
  EXPECT_NEAR(l.effectiveMinTurnRadiusM(), l.turnRadiusAtM(25.0), 1e-12);
  VehicleLimits wide = l;
  wide.min_turn_radius_m = 300.0;
  EXPECT_EQ(wide.effectiveMinTurnRadiusM(), 300.0);
  EXPECT_EQ(parseVehicleModel("fixed_wing"), VehicleModel::kFixedWing);
  EXPECT_EQ(parseVehicleModel("multirotor"), VehicleModel::kMultirotor);
  EXPECT_FALSE(parseVehicleModel("helicopter"));
}

TEST(FixedWingTrajectory, NeverHoversAndStaysWithinItsLimits) {
  const VehicleLimits l = glider();
  const auto w = zigZag();
  TrajectoryOptions options;
  options.fixed_waypoints = {2, 4};  // mission points: passed, never stopped at
  options.fixed_waypoint_mode = FixedWaypointMode::kStop;  // a fixed wing passes anyway
  auto built = buildTrajectory(w, l, options);
  ASSERT_TRUE(built.ok()) << built.error().describe();
  const TrajectoryBuildReport& report = built->report;
  ASSERT_NE(report.status, TrajectoryStatus::kInfeasible) << report.failure_reason;
  EXPECT_TRUE(report.stops.empty());
  EXPECT_GE(report.corners_rounded, 4u);
  const Trajectory& t = built->trajectory;
  // Cruise speed along the first and last legs at the ends.
  const TrajectoryState start = t.stateAt(0.0);
  const TrajectoryState end = t.stateAt(t.duration_s());
  EXPECT_NEAR(start.velocity_mps.norm(), l.v_ref_mps, 1e-6);
  EXPECT_NEAR(end.velocity_mps.norm(), l.v_ref_mps, 1e-6);
  EXPECT_GT(start.velocity_mps.dot((w[1] - w[0]).normalized()), l.v_ref_mps * (1 - 1e-9));
  EXPECT_GT(end.velocity_mps.dot((w[5] - w[4]).normalized()), l.v_ref_mps * (1 - 1e-9));
  // Every fixed waypoint is flown through at speed.
  for (std::size_t index : options.fixed_waypoints) {
    double nearest = std::numeric_limits<double>::infinity();
    double speed = 0.0;
    for (double time = 0.0; time <= t.duration_s(); time += 0.01) {
      const TrajectoryState s = t.stateAt(time);
      if ((s.position_m - w[index]).norm() < nearest) {
        nearest = (s.position_m - w[index]).norm();
        speed = s.velocity_mps.norm();
      }
    }
    EXPECT_LT(nearest, 0.13) << "waypoint " << index;  // samples 0.25 m apart
    EXPECT_GE(speed, l.minAirspeedMps()) << "waypoint " << index;
  }
  const Flown f = measure(t);
  const double tolerance = 1e-3;
  EXPECT_GE(f.min_speed_mps, l.minAirspeedMps() * (1 - tolerance));
  EXPECT_LE(f.max_speed_mps, l.max_speed_mps * (1 + tolerance));
  EXPECT_LE(f.max_bank_deg, l.max_bank_deg * (1 + tolerance));
  EXPECT_LE(f.max_climb_deg, l.max_climb_angle_deg);
  EXPECT_LE(f.max_descent_deg, l.max_descent_angle_deg);
  // The same path for a multirotor still rests at both ends.
  VehicleLimits multirotor = l;
  multirotor.model = VehicleModel::kMultirotor;
  auto hovering = buildTrajectory(w, multirotor, options);
  ASSERT_TRUE(hovering.ok());
  EXPECT_EQ(hovering->trajectory.stateAt(0.0).velocity_mps.norm(), 0.0);
  EXPECT_FALSE(hovering->report.stops.empty());
}

TEST(FixedWingTrajectory, ReportNamesEachViolationKind) {
  const VehicleLimits l = glider();
  // A multirotor's rest-to-rest curve flown by the fixed wing: it starts under its minimum
  // airspeed and turns its 106 degree corners far too tightly for 35 degrees of bank.
  VehicleLimits multirotor = l;
  multirotor.model = VehicleModel::kMultirotor;
  TrajectoryOptions no_repair;
  no_repair.repair = false;
  auto hover = buildTrajectory(zigZag(), multirotor, no_repair);
  ASSERT_TRUE(hover.ok());
  const FeasibilityReport report = checkFeasibility(hover->trajectory, l);
  EXPECT_TRUE(report.has(ViolationKind::kBelowMinAirspeed));
  EXPECT_TRUE(report.has(ViolationKind::kBankAngle));
  EXPECT_TRUE(report.has(ViolationKind::kTurnRadius));
  EXPECT_GT(report.max_bank_deg, l.max_bank_deg);
  EXPECT_FALSE(checkFeasibility(hover->trajectory, multirotor).has(ViolationKind::kBankAngle));

  // Too steep a climb for the path angle: named, and no repair pretends to fix it.
  const std::vector<Eigen::Vector3d> steep{{0, 0, 500}, {1000, 0, 520}, {1500, 0, 900}, {2500, 0, 900}};
  auto climbing = buildTrajectory(steep, l);
  ASSERT_TRUE(climbing.ok());
  EXPECT_EQ(climbing->report.status, TrajectoryStatus::kInfeasible);
  ASSERT_TRUE(climbing->report.failure_violation);
  EXPECT_EQ(climbing->report.failure_violation->kind, ViolationKind::kClimbAngle);
  EXPECT_NE(climbing->report.failure_reason.find("climb_angle"), std::string::npos) << climbing->report.failure_reason;

  // Without corner rounding the fixed wing cannot turn the corners, and never stops to do so.
  TrajectoryOptions square;
  square.round_corners = false;
  auto sharp = buildTrajectory(zigZag(), l, square);
  ASSERT_TRUE(sharp.ok());
  EXPECT_EQ(sharp->report.status, TrajectoryStatus::kInfeasible);
  EXPECT_TRUE(sharp->report.stops.empty());
  ASSERT_TRUE(sharp->report.failure_violation);
  const ViolationKind kind = sharp->report.failure_violation->kind;
  EXPECT_TRUE(kind == ViolationKind::kBankAngle || kind == ViolationKind::kTurnRadius) << to_string(kind);
  EXPECT_EQ(to_string(ViolationKind::kBankAngle), "bank_angle");
  EXPECT_EQ(to_string(ViolationKind::kLoadFactor), "load_factor");
  EXPECT_EQ(to_string(ViolationKind::kBelowMinAirspeed), "below_min_airspeed");
  EXPECT_EQ(to_string(ViolationKind::kDescentAngle), "descent_angle");
}

}  // namespace
}  // namespace skyroute
