// The audit every revision passes before it is published (service/trajectory_audit.hpp), on a
// flat synthetic DEM (100 m everywhere) with straight lines flown at constant speed, whose
// failing instant is known in closed form: a clear line passes; one made to pass under the
// ground, through a no-fly zone in force, over the speed limit, above the ceiling, into a moving
// obstacle's predicted position or too slowly for a fixed wing is refused, naming the check and the
// time; a zone out of force then and a moving obstacle met beyond the horizon refuse nothing.
// Then the audit as a flight uses it (service/flight_audit.hpp): counted, and a refused trajectory
// is never put in force.
#include <gtest/gtest.h>

#include <cmath>

#include "service/flight_audit.hpp"
#include "service/trajectory_audit.hpp"
#include "terrain/collision_world.hpp"
#include "terrain/dem.hpp"
#include "terrain/heightfield.hpp"
#include "tests/terrain_data.hpp"

namespace skyroute {
namespace {

constexpr double kGroundM = 100.0;
constexpr double kStartWorldS = 1'800'000'000.0;

std::shared_ptr<const Heightfield> flatTerrain() {
  const int n = 200;  // 6 km square of 30 m cells
  auto dem = Dem::fromArray(n, n, std::vector<float>(static_cast<std::size_t>(n) * n, static_cast<float>(kGroundM)),
                            {500000.0, 30.0, 0.0, 5200000.0, 0.0, -30.0}, testing::epsgWkt(32633), "flat");
  EXPECT_TRUE(dem.ok()) << dem.error().describe();
  auto hf = Heightfield::build(*dem);
  EXPECT_TRUE(hf.ok()) << hf.error().describe();
  return *hf;
}

// A straight line from a to b in duration_s at constant velocity (one segment, linear in tau).
Trajectory line(const Eigen::Vector3d& a, const Eigen::Vector3d& b, double duration_s) {
  Segment s;
  s.duration_s = duration_s;
  for (int axis = 0; axis < 3; ++axis) {
    Polynomial7::Coefficients c{};
    c[0] = a(axis);
    c[1] = b(axis) - a(axis);
    s.axes[static_cast<std::size_t>(axis)] = Polynomial7(c);
  }
  return Trajectory({s});
}

class Audit : public ::testing::Test {
 protected:
  void SetUp() override {
    world_.terrain = flatTerrain();
    ASSERT_TRUE(world_.terrain);
    world_.min_clearance_m = 30.0;
    world_.ceiling_m = 1000.0;
    world_.vehicle_radius_m = 5.0;
    world_.moving_until_world_s = kStartWorldS + 45.0;
    centre_ = world_.terrain->boundsEn().center();
  }
  // West to east through the DEM's centre at 300 m, 20 m/s for 40 s (800 m).
  Trajectory eastward(double up_m = 300.0, double speed_mps = 20.0) const {
    const double half_m = 20.0 * speed_mps;
    return line({centre_.x() - half_m, centre_.y(), up_m}, {centre_.x() + half_m, centre_.y(), up_m}, 40.0);
  }
  // A 100 m square zone centred `east_m` east of the DEM's centre, from the ground to 2000 m.
  NoFlyZone square(const std::string& name, double east_m) const {
    NoFlyZone z;
    z.name = name;
    const double x = centre_.x() + east_m;
    const double y = centre_.y();
    z.ring_m = {{x - 50, y - 50}, {x + 50, y - 50}, {x + 50, y + 50}, {x - 50, y + 50}};
    z.floor_m = -1000.0;
    z.ceiling_m = 2000.0;
    return z;
  }
  std::optional<AuditFinding> audit(const Trajectory& t) const {
    return auditTrajectory(t, kStartWorldS, world_, limits_, options_);
  }

  AuditWorld world_;
  VehicleLimits limits_;
  AuditOptions options_;
  Eigen::Vector2d centre_;
};

TEST_F(Audit, ClearLinePasses) {
  NoFlyZone beside = square("beside", 0.0);
  for (Eigen::Vector2d& v : beside.ring_m) v.y() += 70.0;  // its south side 20 m north of the line
  world_.zones = {beside};
  EXPECT_FALSE(audit(eastward()).has_value());
}

TEST_F(Audit, UnderTheGroundIsRefused) {
  // Down from 300 m to 50 m (50 m under the ground) over 40 s: under the 30 m clearance once
  // 300 - 6.25 t < 130 - 0.1, at t = 27.2 s.
  const Trajectory diving = line({centre_.x() - 400, centre_.y(), 300.0}, {centre_.x() + 400, centre_.y(), 50.0}, 40.0);
  const auto finding = audit(diving);
  ASSERT_TRUE(finding.has_value());
  EXPECT_EQ(finding->check, AuditCheck::kGroundClearance) << finding->reason;
  EXPECT_NEAR(finding->t_s, (300.0 - 129.9) / 6.25, options_.step_s);
  EXPECT_NE(finding->reason.find("under the minimum clearance 30.0 m"), std::string::npos) << finding->reason;
}

TEST_F(Audit, ThroughAZoneInForceIsRefusedNamingIt) {
  world_.zones = {square("stadium", 100.0)};
  // The sphere touches the zone's west side (x = centre + 50) when the centre is 4.9 m short of
  // it (the radius less the tolerance): 445.1 m into the line, at t = 22.255 s.
  const auto finding = audit(eastward());
  ASSERT_TRUE(finding.has_value());
  EXPECT_EQ(finding->check, AuditCheck::kNoFlyZone) << finding->reason;
  EXPECT_NEAR(finding->t_s, 22.255, options_.step_s);
  EXPECT_NE(finding->reason.find("no-fly zone 'stadium'"), std::string::npos) << finding->reason;
}

TEST_F(Audit, ZoneOutOfForceAtThePassRefusesNothing) {
  NoFlyZone later = square("later", 100.0);
  later.valid_from_s = kStartWorldS + 30.0;  // the vehicle has left it by then (t = 27.745 s)
  NoFlyZone earlier = square("earlier", 100.0);
  earlier.valid_until_s = kStartWorldS + 22.0;  // lifted before the vehicle comes (t = 22.255 s)
  world_.zones = {later, earlier};
  EXPECT_FALSE(audit(eastward()).has_value());
  world_.zones.front().valid_from_s = kStartWorldS + 25.0;  // in force while it is inside
  const auto finding = audit(eastward());
  ASSERT_TRUE(finding.has_value());
  EXPECT_EQ(finding->check, AuditCheck::kNoFlyZone);
  EXPECT_NEAR(finding->t_s, 25.0, 1e-9);
  EXPECT_NE(finding->reason.find("'later'"), std::string::npos) << finding->reason;
}

TEST_F(Audit, OverTheSpeedLimitIsRefused) {
  limits_.max_speed_mps = 60.0;
  const auto finding = audit(eastward(300.0, 62.0));  // 3 % over: beyond the 2 % tolerance
  ASSERT_TRUE(finding.has_value());
  EXPECT_EQ(finding->check, AuditCheck::kSpeed) << finding->reason;
  EXPECT_EQ(finding->t_s, 0.0);
  EXPECT_NE(finding->reason.find("62.00 m/s over the limit 60.00 m/s"), std::string::npos) << finding->reason;
  EXPECT_FALSE(audit(eastward(300.0, 61.0)).has_value());  // within the tolerance
}

TEST_F(Audit, AboveTheCeilingIsRefused) {
  world_.ceiling_m = 250.0;
  const auto finding = audit(eastward());
  ASSERT_TRUE(finding.has_value());
  EXPECT_EQ(finding->check, AuditCheck::kCeiling) << finding->reason;
}

TEST_F(Audit, MovingObstacleIsCheckedWherePredictedOverTheHorizon) {
  // A sphere of 20 m crossing the line from the south at 30 m/s, at the line at t = 20 s where
  // the vehicle is too (the centre of the line).
  Obstacle o;
  o.id = 7;
  o.shape = ObstacleShape::kSphere;
  o.size_m = Eigen::Vector3d::Constant(20.0);
  BackAndForth m;
  m.from_m = {centre_.x(), centre_.y() - 600.0, 300.0};
  m.to_m = {centre_.x(), centre_.y() + 600.0, 300.0};
  m.speed_mps = 30.0;
  m.start_time_s = kStartWorldS;
  o.motion = m;
  world_.obstacles = {o};
  const auto finding = audit(eastward());
  ASSERT_TRUE(finding.has_value());
  EXPECT_EQ(finding->check, AuditCheck::kObstacle) << finding->reason;
  EXPECT_NEAR(finding->t_s, 20.0, 1.0);
  EXPECT_NE(finding->reason.find("moving obstacle 7"), std::string::npos) << finding->reason;
  // Met 20 s into the trajectory, beyond a horizon that ends 15 s in: not this revision's business.
  world_.moving_until_world_s = kStartWorldS + 15.0;
  EXPECT_FALSE(audit(eastward()).has_value());
}

TEST_F(Audit, EllipsoidDistanceIsExactOffItsAxes) {
  // An ellipsoid 300 x 100 x 100 m centred 120 m north of the line's middle, at the line's height:
  // the line passes 20 m from its southern tip, clear of the 5 m sphere; 103 m north, 3 m, not.
  Obstacle o;
  o.id = 3;
  o.shape = ObstacleShape::kEllipsoid;
  o.size_m = {300.0, 100.0, 100.0};
  o.center_m = {centre_.x(), centre_.y() + 120.0, 300.0};
  world_.obstacles = {o};
  EXPECT_FALSE(audit(eastward()).has_value());
  world_.obstacles.front().center_m.y() = centre_.y() + 103.0;
  const auto finding = audit(eastward());
  ASSERT_TRUE(finding.has_value());
  EXPECT_EQ(finding->check, AuditCheck::kObstacle) << finding->reason;
  EXPECT_NE(finding->reason.find("fixed obstacle 3"), std::string::npos) << finding->reason;
  // Off the axes: a point 10 m outside along the surface normal at the ellipse point (150 cos 45,
  // 100 sin 45) is 10 m away (the line from the point to its centre is not the way to measure it).
  const double c = std::cos(M_PI / 4.0), s = std::sin(M_PI / 4.0);
  const Eigen::Vector2d surface(300.0 * c, 100.0 * s);
  const Eigen::Vector2d normal = Eigen::Vector2d(c / 300.0, s / 100.0).normalized();  // the gradient's direction
  const Eigen::Vector2d offset = surface + 10.0 * normal;
  world_.obstacles.front().center_m = {centre_.x() - offset.x(), centre_.y() - offset.y(), 300.0};
  const Eigen::Vector3d hover(centre_.x(), centre_.y(), 300.0);  // at rest there for a second
  world_.vehicle_radius_m = 9.0;
  EXPECT_FALSE(audit(line(hover, hover, 1.0)).has_value());
  world_.vehicle_radius_m = 11.0;
  EXPECT_TRUE(audit(line(hover, hover, 1.0)).has_value());
}

TEST_F(Audit, FixedWingUnderItsMinimumAirspeedIsRefused) {
  limits_.model = VehicleModel::kFixedWing;
  limits_.stall_speed_mps = 18.0;  // minimum airspeed 23.4 m/s
  limits_.v_ref_mps = 30.0;
  const auto finding = audit(eastward(300.0, 20.0));
  ASSERT_TRUE(finding.has_value());
  EXPECT_EQ(finding->check, AuditCheck::kMinAirspeed) << finding->reason;
  EXPECT_FALSE(audit(eastward(300.0, 25.0)).has_value());
}

TEST(AuditOptionsCheck, UnusableOptionsNameTheKey) {
  AuditOptions o;
  o.step_s = 0.0;
  ASSERT_TRUE(validateAuditOptions(o).has_value());
  EXPECT_EQ(validateAuditOptions(o)->field, "audit.step_s");
  o = AuditOptions{};
  o.limit_tolerance = -0.1;
  ASSERT_TRUE(validateAuditOptions(o).has_value());
  EXPECT_EQ(validateAuditOptions(o)->field, "audit.limit_tolerance");
  EXPECT_FALSE(validateAuditOptions(AuditOptions{}).has_value());
}

TEST(FlightAuditHook, CountsEveryAuditAndRefusesWithFieldAudit) {
  auto terrain = flatTerrain();
  ASSERT_TRUE(terrain);
  CollisionWorldOptions options;
  options.min_clearance_m = 30.0;
  options.build_octree = false;
  auto world = CollisionWorld::create(terrain, options);
  ASSERT_TRUE(world.ok()) << world.error().describe();
  const Eigen::Vector2d c = terrain->boundsEn().center();
  auto counters = std::make_shared<AuditCounters>();
  auto label = std::make_shared<FlightAuditLabel>();
  label->vehicle_id = "uav-audit";
  label->revision_base = 4;
  const auto hook = flightAudit(*world, VehicleLimits{}, AuditOptions{}, 45.0, counters, label);
  const Trajectory high = line({c.x() - 400, c.y(), 300.0}, {c.x() + 400, c.y(), 300.0}, 40.0);
  const Trajectory low = line({c.x() - 400, c.y(), 300.0}, {c.x() + 400, c.y(), 110.0}, 40.0);
  EXPECT_FALSE(hook(high, kStartWorldS, kStartWorldS, 1).has_value());
  const auto refused = hook(low, kStartWorldS, kStartWorldS, 2);
  ASSERT_TRUE(refused.has_value());
  EXPECT_EQ(refused->field, "audit");
  EXPECT_NE(refused->message.find("revision 6"), std::string::npos) << refused->message;
  EXPECT_NE(refused->message.find("ground_clearance"), std::string::npos) << refused->message;
  EXPECT_EQ(counters->audits.load(), 2u);
  EXPECT_EQ(counters->failures.load(), 1u);
  // A zone published on the world later is in the next audit (the world's data at that moment).
  NoFlyZone zone;
  zone.name = "new";
  zone.ring_m = {{c.x() - 50, c.y() - 50}, {c.x() + 50, c.y() - 50}, {c.x() + 50, c.y() + 50},
                 {c.x() - 50, c.y() + 50}};
  zone.floor_m = -1000.0;
  zone.ceiling_m = 2000.0;
  (*world)->setNoFlyZones({zone});
  const auto zoned = hook(high, kStartWorldS, kStartWorldS, 3);
  ASSERT_TRUE(zoned.has_value());
  EXPECT_NE(zoned->message.find("no-fly zone 'new'"), std::string::npos) << zoned->message;
}

}  // namespace
}  // namespace skyroute
