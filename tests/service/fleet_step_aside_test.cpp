// The places a fleet vehicle below its flight band steps to (fleet_step_aside.hpp), judged by
// sampling the obstacle's own motion: the climb from each place to the band stays clear of it, and
// the hold lasts until the vehicle's first place is clear again.
#include <gtest/gtest.h>

#include <cmath>

#include "service/fleet_step_aside.hpp"

namespace skyroute {
namespace {

constexpr double kBandM = 1154.0;
constexpr double kRoomM = 100.0;

// A column (radius 120 m, every altitude from 0 to 2500 m) from `from` northwards at 10 m/s from t = 0.
Obstacle columnNorth(const Eigen::Vector2d& from) {
  Obstacle o;
  o.shape = ObstacleShape::kCylinder;
  o.size_m = Eigen::Vector3d(120.0, 120.0, 1250.0);
  o.center_m = Eigen::Vector3d(from.x(), from.y(), 1250.0);
  o.motion = BackAndForth{o.center_m, o.center_m + Eigen::Vector3d(0.0, 36000.0, 0.0), 10.0, 0.0};
  return o;
}

// Whether the vertical line at xy, from z0 to the band, comes within room_m of o at t.
bool lineMet(const Obstacle& o, const Eigen::Vector2d& xy, double z0_m, double t, double room_m) {
  for (double z = z0_m; z <= kBandM; z += 10.0) {
    if (o.contains(Eigen::Vector3d(xy.x(), xy.y(), z), t, room_m)) return true;
  }
  return false;
}

TEST(FleetStepAside, ACrossingColumnGivesPlacesOffItsTrackOnBothSides) {
  const Obstacle column = columnNorth(Eigen::Vector2d(0.0, -1000.0));
  const Eigen::Vector3d p(30.0, 0.0, 500.0);
  ASSERT_TRUE(lineMet(column, p.head<2>(), p.z(), 100.0, 0.0)) << "the column must come over the climb";
  const std::vector<StepAside> asides = stepAsidesFrom({column}, p, kBandM, kRoomM, 0.0);
  ASSERT_EQ(asides.size(), 4u);
  EXPECT_GT(asides.front().xy.x(), 0.0) << "the side the vehicle is on first";
  EXPECT_LT(asides.back().xy.x(), 0.0);
  for (const StepAside& a : asides) {
    EXPECT_LT((a.xy - p.head<2>()).norm(), 120.0 + kRoomM + 31.0) << "no farther than it needs";
    for (double t = 0.0; t <= 3600.0; t += 0.5) {
      ASSERT_FALSE(lineMet(column, a.xy, p.z(), t, kRoomM - 1.0)) << "its climb meets the column at t=" << t;
    }
    if (a.hold_until_s == 0.0) continue;
    // Held until the vehicle's first place is clear again, and not much longer.
    for (double t = a.hold_until_s; t <= a.hold_until_s + 600.0; t += 0.5) {
      ASSERT_FALSE(lineMet(column, p.head<2>(), p.z(), t, kRoomM - 1.0)) << "the column is still there at t=" << t;
    }
    EXPECT_TRUE(lineMet(column, p.head<2>(), p.z(), a.hold_until_s - 2.0, kRoomM - 1.0));
  }
}

TEST(FleetStepAside, ColumnsThatMissTheClimbGiveNone) {
  const Eigen::Vector3d p(30.0, 0.0, 500.0);
  // Its track passes 500 m east.
  EXPECT_TRUE(stepAsidesFrom({columnNorth(Eigen::Vector2d(500.0, -1000.0))}, p, kBandM, kRoomM, 0.0).empty());
  // Gone by already: 1,000 m north of the vehicle and going on north.
  EXPECT_TRUE(stepAsidesFrom({columnNorth(Eigen::Vector2d(0.0, -1000.0))}, p, kBandM, kRoomM, 200.0).empty());
  // A sphere far above the band, crossing over the vehicle.
  Obstacle high = columnNorth(Eigen::Vector2d(0.0, -1000.0));
  high.shape = ObstacleShape::kSphere;
  high.size_m = Eigen::Vector3d::Constant(100.0);
  high.motion->from_m.z() = high.motion->to_m.z() = 3000.0;
  EXPECT_TRUE(stepAsidesFrom({high}, p, kBandM, kRoomM, 0.0).empty());
}

TEST(FleetStepAside, AFixedColumnOverTheClimbGivesThePlaceStraightAway) {
  Obstacle fixed;
  fixed.shape = ObstacleShape::kCylinder;
  fixed.size_m = Eigen::Vector3d(120.0, 120.0, 1250.0);
  fixed.center_m = Eigen::Vector3d(0.0, 0.0, 1250.0);
  const Eigen::Vector3d p(0.0, 50.0, 500.0);
  const std::vector<StepAside> asides = stepAsidesFrom({fixed}, p, kBandM, kRoomM, 0.0);
  ASSERT_EQ(asides.size(), 1u);
  EXPECT_GT(asides[0].xy.y(), 50.0);
  EXPECT_FALSE(lineMet(fixed, asides[0].xy, p.z(), 0.0, kRoomM - 1.0));
  EXPECT_TRUE(lineMet(fixed, asides[0].xy, p.z(), 0.0, kRoomM + 1.0)) << "no farther than it needs";
}

}  // namespace
}  // namespace skyroute
