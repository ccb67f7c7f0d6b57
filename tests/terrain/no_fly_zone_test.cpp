// No-fly zone geometry against an independent reference (the distance to an axis-aligned box,
// computed in closed form), the zones' checks, and the collision world and terrain grid with zones.
#include <algorithm>
#include <cmath>
#include <limits>
#include <random>

#include <gtest/gtest.h>

#include "terrain/collision_world.hpp"
#include "terrain/grid_from_terrain.hpp"
#include "terrain/heightfield.hpp"
#include "terrain/no_fly_zone.hpp"
#include "tests/terrain_data.hpp"

namespace skyroute {
namespace {

NoFlyZone squareZone(double x0, double y0, double x1, double y1, double floor_m, double ceiling_m) {
  NoFlyZone z;
  z.name = "square";
  z.ring_m = {{x0, y0}, {x1, y0}, {x1, y1}, {x0, y1}};
  z.floor_m = floor_m;
  z.ceiling_m = ceiling_m;
  return z;
}

// Reference: the point is within `margin` of the box horizontally and of the slab vertically.
bool insideGrownBox(const Eigen::Vector3d& p, double x0, double y0, double x1, double y1, double lo, double hi,
                    double margin) {
  const double dx = std::max({x0 - p.x(), 0.0, p.x() - x1});
  const double dy = std::max({y0 - p.y(), 0.0, p.y() - y1});
  return std::hypot(dx, dy) <= margin && p.z() >= lo - margin && p.z() <= hi + margin;
}

TEST(NoFlyZoneGeometry, PointsMatchTheBoxReference) {
  const NoFlyZone z = squareZone(0, 0, 100, 50, 200, 400);
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> x(-60, 160), y(-60, 110), h(100, 500);
  int inside = 0;
  for (int i = 0; i < 20000; ++i) {
    const Eigen::Vector3d p(x(rng), y(rng), h(rng));
    const bool expected = insideGrownBox(p, 0, 0, 100, 50, 200, 400, 10.0);
    ASSERT_EQ(z.touchesPoint(p, 10.0), expected) << p.transpose();
    inside += expected;
  }
  EXPECT_GT(inside, 1000);  // both answers were exercised
  EXPECT_FALSE(z.touchesPoint({50, 25, 199}));
  EXPECT_TRUE(z.touchesPoint({50, 25, 200}));
  EXPECT_TRUE(z.touchesPoint({50, 25, 400}));
  EXPECT_FALSE(z.touchesPoint({50, 25, 401}));
}

TEST(NoFlyZoneGeometry, SegmentsAgreeWithDenseSamplesOfTheReference) {
  const NoFlyZone z = squareZone(0, 0, 100, 50, 200, 400);
  const double margin = 5.0;
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> x(-200, 300), y(-200, 250), h(0, 600);
  int touching = 0;
  for (int i = 0; i < 3000; ++i) {
    const Eigen::Vector3d a(x(rng), y(rng), h(rng)), b(x(rng), y(rng), h(rng));
    bool sampled = false;
    bool near_boundary = false;
    const int steps = 4000;
    for (int k = 0; k <= steps; ++k) {
      const Eigen::Vector3d p = a + (b - a) * (static_cast<double>(k) / steps);
      sampled = sampled || insideGrownBox(p, 0, 0, 100, 50, 200, 400, margin);
      near_boundary = near_boundary || insideGrownBox(p, 0, 0, 100, 50, 200, 400, margin + 0.5);
    }
    const bool touches = z.touchesSegment(a, b, margin);
    // The rims of the swept shape are rounded horizontally and flat vertically in both, so they
    // agree except where the samples skip a sliver narrower than their spacing.
    if (sampled) {
      ASSERT_TRUE(touches) << a.transpose() << " -> " << b.transpose();
    }
    if (touches) {
      ASSERT_TRUE(near_boundary) << a.transpose() << " -> " << b.transpose();
    }
    touching += touches;
  }
  EXPECT_GT(touching, 300);
  EXPECT_LT(touching, 2700);
}

TEST(NoFlyZoneGeometry, ConcavePolygonLeavesItsNotchFree) {
  NoFlyZone u;
  u.name = "u";
  u.ring_m = {{0, 0}, {300, 0}, {300, 300}, {200, 300}, {200, 100}, {100, 100}, {100, 300}, {0, 300}};
  u.floor_m = 0;
  u.ceiling_m = 1000;
  EXPECT_FALSE(checkNoFlyZone(u).has_value());
  EXPECT_FALSE(u.touchesPoint({150, 200, 500}, 10.0));  // in the notch
  EXPECT_TRUE(u.touchesPoint({50, 200, 500}, 10.0));
  EXPECT_FALSE(u.touchesSegment({150, 350, 500}, {150, 150, 500}, 10.0));  // down into the notch
  EXPECT_TRUE(u.touchesSegment({150, 350, 500}, {150, 50, 500}, 10.0));   // through its bottom
  EXPECT_TRUE(u.touchesSquare({150, 200}, 90.0, 10.0));                   // 45 + 10 reaches x = 95 .. 205
  EXPECT_FALSE(u.touchesSquare({150, 200}, 70.0, 10.0));
  EXPECT_TRUE(u.touchesSquare({150, 150}, 1000.0));                       // a square holding the zone
}

TEST(NoFlyZoneGeometry, TimeWindowIsHalfOpen) {
  NoFlyZone z = squareZone(0, 0, 10, 10, 0, 10);
  z.valid_from_s = 100.0;
  z.valid_until_s = 200.0;
  EXPECT_FALSE(z.activeAt(99.9));
  EXPECT_TRUE(z.activeAt(100.0));
  EXPECT_FALSE(z.activeAt(200.0));
  EXPECT_TRUE(z.activeDuring(50.0, 100.0));
  EXPECT_FALSE(z.activeDuring(200.0, 300.0));
  const std::vector<NoFlyZone> zones{z};
  EXPECT_NE(zoneTouchingPoint(zones, {5, 5, 5}, 0.0), nullptr);  // no time: every zone counts
  EXPECT_EQ(zoneTouchingPoint(zones, {5, 5, 5}, 0.0, 50.0), nullptr);
  EXPECT_NE(zoneTouchingPoint(zones, {5, 5, 5}, 0.0, 50.0, 60.0), nullptr);  // in force within the window
}

TEST(NoFlyZoneCheck, NamesTheZoneAndTheFault) {
  NoFlyZone z = squareZone(0, 0, 10, 10, 0, 10);
  z.name = "features[3] 'tower'";
  EXPECT_FALSE(checkNoFlyZone(z).has_value());

  NoFlyZone two = z;
  two.ring_m.resize(2);
  auto e = checkNoFlyZone(two);
  ASSERT_TRUE(e);
  EXPECT_EQ(e->field, "features[3] 'tower'");
  EXPECT_NE(e->message.find("at least 3"), std::string::npos) << e->message;

  NoFlyZone bow = z;  // a bow tie: edges 0 and 2 cross
  bow.ring_m = {{0, 0}, {10, 10}, {10, 0}, {0, 10}};
  e = checkNoFlyZone(bow);
  ASSERT_TRUE(e);
  EXPECT_NE(e->message.find("self-intersection"), std::string::npos) << e->message;

  NoFlyZone flat = z;  // three collinear vertices fold back on themselves
  flat.ring_m = {{0, 0}, {5, 0}, {10, 0}};
  e = checkNoFlyZone(flat);
  ASSERT_TRUE(e);
  EXPECT_NE(e->message.find("self-intersection"), std::string::npos) << e->message;

  NoFlyZone nan = z;
  nan.ring_m[1].x() = std::numeric_limits<double>::quiet_NaN();
  e = checkNoFlyZone(nan);
  ASSERT_TRUE(e);
  EXPECT_NE(e->message.find("NaN"), std::string::npos) << e->message;

  NoFlyZone upside = z;
  upside.floor_m = 20.0;
  e = checkNoFlyZone(upside);
  ASSERT_TRUE(e);
  EXPECT_NE(e->message.find("floor_m 20 is above ceiling_m 10"), std::string::npos) << e->message;
}

// A ring of n vertices on a circle: simple, and its area close to the circle's.
NoFlyZone circleZone(std::size_t n, double radius_m) {
  NoFlyZone z = squareZone(0, 0, 1, 1, 0, 10);
  z.name = "circle";
  z.ring_m.clear();
  for (std::size_t i = 0; i < n; ++i) {
    const double a = 2.0 * M_PI * static_cast<double>(i) / static_cast<double>(n);
    z.ring_m.emplace_back(radius_m * std::cos(a), radius_m * std::sin(a));
  }
  return z;
}

TEST(NoFlyZoneCheck, BoundsTheVerticesBeforeAnythingElse) {
  EXPECT_FALSE(checkNoFlyZone(circleZone(kMaxNoFlyZoneVertices, 2000.0)).has_value());
  NoFlyZone big = circleZone(kMaxNoFlyZoneVertices + 1, 2000.0);
  big.ring_m[3].x() = std::numeric_limits<double>::quiet_NaN();  // not looked at: the count comes first
  big.floor_m = 50.0;                                             // above the ceiling: not looked at either
  const auto e = checkNoFlyZone(big);
  ASSERT_TRUE(e);
  EXPECT_EQ(e->field, "circle");
  EXPECT_EQ(e->message, "ring has 10001 vertices, more than the 10000 a zone may have");
  const auto ring = checkNoFlyRing(big.ring_m);
  ASSERT_TRUE(ring);
  EXPECT_EQ(ring->field, "ring");
}

TEST(NoFlyZoneCheck, RefusesZonesOfNearlyZeroArea) {
  NoFlyZone z = squareZone(0, 0, 1, 1, 0, 10);  // 1 m², 0.5 m mean width: the least a zone may be
  EXPECT_FALSE(checkNoFlyZone(z).has_value());
  // Three vertices 2 km along a line, the middle one 5 cm off it: 50 m² but a sliver.
  z.ring_m = {{0, 0}, {1000, 0.05}, {2000, 0}};
  auto e = checkNoFlyZone(z);
  ASSERT_TRUE(e);
  EXPECT_NE(e->message.find("has (nearly) zero area: its vertices lie (nearly) on one line (area 50 m², mean width"),
            std::string::npos)
      << e->message;
  z.ring_m = {{0, 0}, {0.5, 0}, {0.5, 0.5}, {0, 0.5}};  // 0.25 m²
  e = checkNoFlyZone(z);
  ASSERT_TRUE(e);
  EXPECT_NE(e->message.find("zero area"), std::string::npos) << e->message;
  z.ring_m = {{0, 0}, {2000, 0}, {2000, 1}, {0, 1}};  // a 1 m wide corridor is a zone
  EXPECT_FALSE(checkNoFlyZone(z).has_value());
}

TEST(NoFlyZoneGeometry, RectanglesMatchTheBoxReference) {
  const NoFlyZone z = squareZone(0, 0, 100, 50, 0, 10);
  EXPECT_TRUE(z.touchesRectangle(Eigen::AlignedBox2d(Eigen::Vector2d(-10, -10), Eigen::Vector2d(200, 200))));  // holds it
  EXPECT_TRUE(z.touchesRectangle(Eigen::AlignedBox2d(Eigen::Vector2d(40, 20), Eigen::Vector2d(41, 21))));      // inside
  EXPECT_TRUE(z.touchesRectangle(Eigen::AlignedBox2d(Eigen::Vector2d(100, -5), Eigen::Vector2d(120, 5))));     // corner
  EXPECT_FALSE(z.touchesRectangle(Eigen::AlignedBox2d(Eigen::Vector2d(101, 0), Eigen::Vector2d(120, 5))));
  EXPECT_TRUE(z.touchesRectangle(Eigen::AlignedBox2d(Eigen::Vector2d(101, 0), Eigen::Vector2d(120, 5)), 1.0));
}

class ZonesInTheWorld : public ::testing::Test {
 protected:
  void SetUp() override {
    terrain_ = testing::defaultTerrainHeightfield();
    if (!terrain_) GTEST_SKIP() << "default terrain did not load";
    CollisionWorldOptions o;
    o.vehicle_radius_m = 5.0;
    o.min_clearance_m = 30.0;
    o.build_octree = false;
    world_ = CollisionWorld::create(terrain_, o).value();
    const Eigen::Vector2d c = terrain_->boundsEn().center();
    zone_ = squareZone(c.x() - 500, c.y() - 500, c.x() + 500, c.y() + 500, -1000, 5000);
    high_ = terrain_->maxHeightM() + 100.0;
    center_ = c;
  }
  std::shared_ptr<const Heightfield> terrain_;
  std::shared_ptr<CollisionWorld> world_;
  NoFlyZone zone_;
  double high_ = 0.0;
  Eigen::Vector2d center_;
};

TEST_F(ZonesInTheWorld, EveryValidityCheckKeepsOut) {
  const Eigen::Vector3d inside(center_.x(), center_.y(), high_);
  const Eigen::Vector3d west(center_.x() - 2000, center_.y(), high_), east(center_.x() + 2000, center_.y(), high_);
  ASSERT_TRUE(world_->isPointValid(inside));
  ASSERT_TRUE(world_->isSegmentValid(west, east));
  const std::uint64_t version = world_->obstacleVersion();
  world_->setNoFlyZones({zone_});
  EXPECT_GT(world_->obstacleVersion(), version);
  EXPECT_FALSE(world_->isPointValid(inside));
  EXPECT_FALSE(world_->isSegmentValid(west, east));
  EXPECT_FALSE(world_->isStaticSegmentValid(west, east));
  EXPECT_FALSE(world_->isSegmentValidDuring(west, 0.0, east, 100.0));
  EXPECT_EQ(world_->noFlyZoneAt(inside).value_or(""), "square");
  // 4 m beside the zone is inside the 5 m vehicle sphere; 6 m is not.
  EXPECT_FALSE(world_->isPointValid({center_.x() + 504, center_.y(), high_}));
  EXPECT_TRUE(world_->isPointValid({center_.x() + 506, center_.y(), high_}));
}

TEST_F(ZonesInTheWorld, AWindowedZoneBlocksOnlyWhileInForce) {
  zone_.valid_from_s = 1000.0;
  zone_.valid_until_s = 2000.0;
  world_->setNoFlyZones({zone_});
  const Eigen::Vector3d west(center_.x() - 2000, center_.y(), high_), east(center_.x() + 2000, center_.y(), high_);
  EXPECT_FALSE(world_->isSegmentValid(west, east));  // timeless: it may be in force
  EXPECT_TRUE(world_->isSegmentValid(west, east, 500.0));
  EXPECT_FALSE(world_->isSegmentValid(west, east, 1500.0));
  EXPECT_TRUE(world_->isSegmentValidDuring(west, 0.0, east, 999.0));
  EXPECT_FALSE(world_->isSegmentValidDuring(west, 900.0, east, 1100.0));
  EXPECT_TRUE(world_->isSegmentValidDuring(west, 2000.0, east, 2100.0));
}

TEST_F(ZonesInTheWorld, TerrainGridBlocksTheZonesCellsInTheBand) {
  TerrainGridOptions o;
  o.cell_size_m = 200.0;
  o.flight_ceiling_m = 5000.0;
  o.min_clearance_m = 30.0;
  const GridLayer plain = buildTerrainGrid(*terrain_, o).value();
  o.no_fly_zones = {zone_};
  o.zone_margin_m = 5.0;
  const GridLayer zoned = buildTerrainGrid(*terrain_, o).value();
  int added = 0;
  for (int y = 0; y < zoned.height(); ++y) {
    for (int x = 0; x < zoned.width(); ++x) {
      const GridCell c{x, y};
      const Eigen::Vector2d m = zoned.cellCenter(c);
      // Reference: the cell square within 5 m of the 1000 m square round the centre.
      const double dx = std::max(0.0, std::abs(m.x() - center_.x()) - 500.0 - 100.0);
      const double dy = std::max(0.0, std::abs(m.y() - center_.y()) - 500.0 - 100.0);
      const bool covered = std::hypot(dx, dy) <= 5.0;
      if (covered) {
        ASSERT_TRUE(zoned.blocked(c)) << x << "," << y;
      } else {
        ASSERT_EQ(zoned.blocked(c), plain.blocked(c)) << x << "," << y;
      }
      added += covered && !plain.blocked(c);
    }
  }
  EXPECT_GE(added, 25);
  // A zone above the band, or a kept-free point, leaves the cells to the terrain.
  o.no_fly_zones = {squareZone(center_.x() - 500, center_.y() - 500, center_.x() + 500, center_.y() + 500, 6000, 7000)};
  EXPECT_EQ(buildTerrainGrid(*terrain_, o)->blockedCount(), plain.blockedCount());
  o.no_fly_zones = {zone_};
  o.keep_free_m = {center_};
  const GridLayer kept = buildTerrainGrid(*terrain_, o).value();
  const GridCell mid = *kept.cellAt(center_);
  EXPECT_EQ(kept.blocked(mid), plain.blocked(mid));
  EXPECT_EQ(kept.blockedCount() + 1, zoned.blockedCount() + (plain.blocked(mid) ? 1 : 0));
}

}  // namespace
}  // namespace skyroute
