// Octree, collision world and terrain grid against independent references: the build rule,
// dense sampling, analytic obstacle shapes, and brute force.
#include <atomic>
#include <cmath>
#include <random>
#include <thread>
#include <tuple>

#include <gtest/gtest.h>
#include <cpl_conv.h>
#include <ogr_srs_api.h>

#include "terrain/collision_world.hpp"
#include "terrain/grid_from_terrain.hpp"
#include "terrain/terrain_octree.hpp"
#include "terrain/terrain_world.hpp"
#include "tests/terrain_data.hpp"
#include "tests/test_data.hpp"

namespace skyroute {
namespace {

Obstacle makeObstacle(std::uint64_t id, ObstacleShape shape, const Eigen::Vector3d& size_m,
                      const Eigen::Vector3d& center_m) {
  Obstacle o;
  o.id = id;
  o.shape = shape;
  o.size_m = size_m;
  o.center_m = center_m;
  return o;
}

CollisionWorldOptions worldOptions(double radius, double clearance, double ceiling, bool octree = true) {
  CollisionWorldOptions o;
  o.vehicle_radius_m = radius;
  o.min_clearance_m = clearance;
  o.ceiling_m = ceiling;
  o.octree_resolution_m = 30.0;
  o.build_octree = octree;
  return o;
}

std::shared_ptr<const Heightfield> defaultTerrain() {
  static std::shared_ptr<const Heightfield> hf = [] {
    auto dem = Dem::load(testing::projectDataPath("default_terrain.tif"));
    EXPECT_TRUE(dem.ok());
    return Heightfield::build(*dem).value();
  }();
  return hf;
}

std::string utmWkt() { return testing::epsgWkt(32633); }

// A flat 100 m plain with a one-cell-wide ridge 400 m high along a column: the kind of feature a
// sampler with a coarse step misses.
std::shared_ptr<const Heightfield> thinRidgeTerrain(int ridge_col) {
  const int n = 64;
  std::vector<float> h(n * n, 100.f);
  for (int r = 0; r < n; ++r) h[r * n + ridge_col] = 500.f;
  const std::array<double, 6> gt = {500000.0, 30.0, 0.0, 5200000.0, 0.0, -30.0};
  auto dem = Dem::fromArray(n, n, h, gt, utmWkt(), "thin_ridge");
  EXPECT_TRUE(dem.ok());
  return Heightfield::build(*dem).value();
}

// Reference: smallest height above ground along the segment by dense sampling.
double denseMinAgl(const Heightfield& hf, const Eigen::Vector3d& a, const Eigen::Vector3d& b, double step_m) {
  const int n = std::max(1, static_cast<int>(std::ceil((b - a).norm() / step_m)));
  double lowest = std::numeric_limits<double>::infinity();
  for (int i = 0; i <= n; ++i) {
    const Eigen::Vector3d p = a + (b - a) * (static_cast<double>(i) / n);
    lowest = std::min(lowest, p.z() - hf.heightAt(p.x(), p.y()));
  }
  return lowest;
}

TEST(Heightfield, SweptSegmentMatchesDenseSampling) {
  auto hf = defaultTerrain();
  std::mt19937 rng(3);
  const auto& box = hf->boundsEn();
  std::uniform_real_distribution<double> ue(box.min().x(), box.max().x());
  std::uniform_real_distribution<double> un(box.min().y(), box.max().y());
  std::uniform_real_distribution<double> ua(100.0, 1000.0);
  std::uniform_real_distribution<double> ulen(50.0, 1500.0);
  std::uniform_real_distribution<double> uang(0.0, 2 * M_PI);
  int checked = 0;
  for (int i = 0; i < 300; ++i) {
    const Eigen::Vector3d a(ue(rng), un(rng), ua(rng));
    const double len = ulen(rng);
    const double ang = uang(rng);
    const Eigen::Vector3d b(a.x() + len * std::cos(ang), a.y() + len * std::sin(ang), ua(rng));
    if (!box.contains(b.head<2>())) continue;
    const double exact = hf->minHeightAboveGround(a, b);
    const double dense = denseMinAgl(*hf, a, b, 0.25);
    // The exact minimum is never above what any sample sees, and sampling at 0.25 m comes within
    // a few centimetres of it on slopes under 100%.
    EXPECT_LE(exact, dense + 1e-6);
    EXPECT_NEAR(exact, dense, 0.1);
    ++checked;
  }
  EXPECT_GT(checked, 100);
}

TEST(Heightfield, ExactCheckCatchesThinRidgeThatCoarseSamplingMisses) {
  auto hf = thinRidgeTerrain(31);
  const Eigen::Vector2d ridge = hf->pixelToEn(31, 32);
  // Fly east across the ridge at 450 m: ground 100 m either side, 500 m on the ridge cell.
  const Eigen::Vector3d a(ridge.x() - 475.0, ridge.y(), 450.0);
  const Eigen::Vector3d b(ridge.x() + 525.0, ridge.y(), 450.0);
  EXPECT_GT(denseMinAgl(*hf, a, b, 100.0), 0.0) << "a 100 m sampler should miss the ridge here";
  EXPECT_LT(hf->minHeightAboveGround(a, b), 0.0);
  EXPECT_NEAR(hf->minHeightAboveGround(a, b), 450.0 - 500.0, 1e-6);
  auto world = CollisionWorld::create(hf, worldOptions(2.0, 10.0, 1e9, false));
  ASSERT_TRUE(world.ok());
  EXPECT_FALSE((*world)->isSegmentValid(a, b));
  EXPECT_TRUE((*world)->isSegmentValid(a + Eigen::Vector3d(0, 0, 100), b + Eigen::Vector3d(0, 0, 100)));
}

class OctreeAgreement : public ::testing::TestWithParam<std::string> {};

TEST_P(OctreeAgreement, OctreeMatchesHeightfieldAboveAndBelowGround) {
  std::shared_ptr<const Heightfield> hf;
  double res = 30.0;
  if (GetParam() == "default") {
    hf = defaultTerrain();
  } else {
    SKYROUTE_REQUIRE_SHARED(path, "dem/" + GetParam());
    hf = Heightfield::build(Dem::load(path).value()).value();
    res = 90.0;
  }
  auto octree = TerrainOctree::build(hf, TerrainOctreeOptions{res, 0.0});
  std::mt19937 rng(11);
  const auto& box = hf->boundsEn();
  std::uniform_real_distribution<double> ue(box.min().x() + res, box.max().x() - res);
  std::uniform_real_distribution<double> un(box.min().y() + res, box.max().y() - res);
  std::uniform_real_distribution<double> udz(-600.0, 600.0);
  int under = 0;
  int over = 0;
  for (int i = 0; i < 5000; ++i) {
    const double e = ue(rng);
    const double n = un(rng);
    const double ground = hf->heightAt(e, n);
    const Eigen::Vector3d p(e, n, ground + udz(rng));
    if (p.z() < hf->minHeightM() - res) continue;  // below the solid floor
    // Exact: the octree holds what its build rule says about the voxel containing p.
    const octomap::point3d c = octree->tree()->keyToCoord(octree->tree()->coordToKey(p.x(), p.y(), p.z()));
    ASSERT_EQ(octree->occupied(p), octree->terrainOccupiesVoxel(Eigen::Vector3d(c.x(), c.y(), c.z())));
    // Physical: far enough from the surface, occupied exactly when under the ground. "Far enough"
    // is a voxel plus the ground's rise across the voxel.
    double lo = ground;
    double hi = ground;
    for (double dx : {-res, 0.0, res})
      for (double dy : {-res, 0.0, res}) {
        const double h = hf->heightAt(e + dx, n + dy);
        lo = std::min(lo, h);
        hi = std::max(hi, h);
      }
    if (p.z() > hi + res) {
      EXPECT_FALSE(octree->occupied(p));
      ++over;
    } else if (p.z() < lo - res) {
      EXPECT_TRUE(octree->occupied(p));
      ++under;
    }
  }
  EXPECT_GT(under, 1000);
  EXPECT_GT(over, 1000);
}

INSTANTIATE_TEST_SUITE_P(Dems, OctreeAgreement, ::testing::Values("default", "N44W072.hgt", "davosdorf.tif"));

TEST(TerrainOctree, ObstaclesAreAddedAndRemoved) {
  auto hf = defaultTerrain();
  auto octree = TerrainOctree::build(hf, TerrainOctreeOptions{30.0, 0.0});
  const Eigen::Vector3d c(0.0, 0.0, hf->heightAt(0.0, 0.0) + 400.0);
  const Obstacle a = makeObstacle(1, ObstacleShape::kSphere, Eigen::Vector3d(100, 100, 100), c);
  const Obstacle b = makeObstacle(2, ObstacleShape::kBox, Eigen::Vector3d(60, 60, 60), c + Eigen::Vector3d(90, 0, 0));
  EXPECT_FALSE(octree->occupied(c));
  octree->addObstacle(a);
  octree->addObstacle(b);
  EXPECT_TRUE(octree->occupied(c));
  EXPECT_TRUE(octree->occupied(c + Eigen::Vector3d(90, 0, 0)));  // inside both
  EXPECT_TRUE(octree->removeObstacle(1));
  EXPECT_FALSE(octree->occupied(c));
  EXPECT_TRUE(octree->occupied(c + Eigen::Vector3d(90, 0, 0)));  // still inside b
  EXPECT_TRUE(octree->removeObstacle(2));
  EXPECT_FALSE(octree->occupied(c + Eigen::Vector3d(90, 0, 0)));
  EXPECT_FALSE(octree->removeObstacle(2));
  // Terrain voxels survive an obstacle that overlapped them.
  const Eigen::Vector3d underground(500.0, 500.0, hf->heightAt(500.0, 500.0) - 100.0);
  octree->addObstacle(makeObstacle(3, ObstacleShape::kSphere, Eigen::Vector3d(300, 300, 300), underground));
  octree->removeObstacle(3);
  EXPECT_TRUE(octree->occupied(underground));
}

std::shared_ptr<CollisionWorld> makeWorld(double radius = 5.0, double clearance = 30.0, double ceiling = 1500.0) {
  auto world = CollisionWorld::create(defaultTerrain(), worldOptions(radius, clearance, ceiling));
  EXPECT_TRUE(world.ok());
  return world.value();
}

TEST(CollisionWorld, PointValidityFollowsClearanceCeilingAndBounds) {
  auto world = makeWorld(5.0, 30.0, 1500.0);
  const double g = world->terrain().heightAt(100.0, 100.0);
  EXPECT_TRUE(world->isPointValid(Eigen::Vector3d(100, 100, g + 31)));
  EXPECT_FALSE(world->isPointValid(Eigen::Vector3d(100, 100, g + 29)));
  EXPECT_FALSE(world->isPointValid(Eigen::Vector3d(100, 100, g - 10)));
  EXPECT_FALSE(world->isPointValid(Eigen::Vector3d(100, 100, 1501)));
  EXPECT_FALSE(world->isPointValid(Eigen::Vector3d(1e6, 100, 800)));
  const auto bounds = world->flyableBounds();
  EXPECT_LE(bounds.max().z(), 1500.0);
  EXPECT_TRUE(bounds.contains(Eigen::Vector3d(100, 100, g + 31)));
}

TEST(CollisionWorld, ObstacleShapesMatchAnalyticReference) {
  auto world = makeWorld(5.0, 30.0, 5000.0);
  const double z = 1500.0;  // far above the ground: only the obstacles matter
  world->upsertObstacle(makeObstacle(1, ObstacleShape::kSphere, Eigen::Vector3d(200, 0, 0), Eigen::Vector3d(-2000, 0, z)));
  world->upsertObstacle(makeObstacle(2, ObstacleShape::kBox, Eigen::Vector3d(300, 100, 150), Eigen::Vector3d(0, 0, z)));
  world->upsertObstacle(makeObstacle(3, ObstacleShape::kCylinder, Eigen::Vector3d(250, 0, 300), Eigen::Vector3d(2000, 0, z)));
  world->upsertObstacle(makeObstacle(4, ObstacleShape::kEllipsoid, Eigen::Vector3d(400, 200, 150), Eigen::Vector3d(0, 2000, z)));
  const auto obstacles = world->obstacles();
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> u(-700.0, 700.0);
  int inside = 0;
  for (int i = 0; i < 20000; ++i) {
    const Obstacle& o = obstacles[i % obstacles.size()];
    const Eigen::Vector3d p = o.center_m + Eigen::Vector3d(u(rng), u(rng), 0.5 * u(rng));
    const bool hit = o.contains(p, 0.0, 5.0);
    if (o.shape == ObstacleShape::kEllipsoid) {
      // The grown-axes ellipsoid is only a bound of the true offset: compare away from its edge.
      const bool clearly_in = o.contains(p, 0.0, 0.0);
      const bool clearly_out = !o.contains(p, 0.0, 10.0);
      if (!clearly_in && !clearly_out) continue;
      ASSERT_EQ(world->isPointValid(p), clearly_out) << p.transpose();
    } else {
      ASSERT_EQ(world->isPointValid(p), !hit) << to_string(o.shape) << " " << p.transpose();
    }
    inside += hit ? 1 : 0;
  }
  EXPECT_GT(inside, 500);
  // Segments: the swept sphere against dense sampling of points along it.
  std::uniform_real_distribution<double> ux(-2600.0, 2600.0);
  for (int i = 0; i < 500; ++i) {
    const Eigen::Vector3d a(ux(rng), ux(rng), z + u(rng) * 0.3);
    const Eigen::Vector3d b(ux(rng), ux(rng), z + u(rng) * 0.3);
    bool dense_valid = true;
    const int n = static_cast<int>((b - a).norm() / 0.5) + 1;
    for (int k = 0; k <= n && dense_valid; ++k) dense_valid = world->isPointValid(a + (b - a) * (double(k) / n));
    if (world->isSegmentValid(a, b)) {
      EXPECT_TRUE(dense_valid) << "segment passed but a point on it is invalid";
    } else if (dense_valid) {
      // Only allowed when the segment grazes a shape between samples: then a point at most
      // half a sample step away along the segment must be within 1 m of invalid.
      bool near_invalid = false;
      for (int k = 0; k <= 4 * n && !near_invalid; ++k) {
        const Eigen::Vector3d p = a + (b - a) * (double(k) / (4 * n));
        for (const auto& o : obstacles) near_invalid = near_invalid || o.contains(p, 0.0, 6.0);
      }
      EXPECT_TRUE(near_invalid) << a.transpose() << " -> " << b.transpose();
    }
  }
}

// A 100 m sphere going back and forth at 60 m/s along the x axis between -half_span_m and
// half_span_m, at height z, starting west at t = 0.
Obstacle sphereAlongX(std::uint64_t id, double half_span_m, double z) {
  Obstacle o = makeObstacle(id, ObstacleShape::kSphere, Eigen::Vector3d(100, 0, 0), Eigen::Vector3d::Zero());
  o.motion = BackAndForth{{-half_span_m, 0, z}, {half_span_m, 0, z}, 60.0, 0.0};
  return o;
}

TEST(CollisionWorld, MovingObstacleAtKnownTimes) {
  auto world = makeWorld(5.0, 30.0, 5000.0);
  const double z = 1500.0;
  // Table 1 style: back and forth between two points at 60 m/s; 1200 m apart, so 20 s per leg.
  const Obstacle o = sphereAlongX(7, 600.0, z);
  world->upsertObstacle(o);
  EXPECT_TRUE(o.centerAt(0.0).isApprox(Eigen::Vector3d(-600, 0, z)));
  EXPECT_TRUE(o.centerAt(20.0).isApprox(Eigen::Vector3d(600, 0, z)));
  EXPECT_TRUE(o.centerAt(30.0).isApprox(Eigen::Vector3d(0, 0, z)));
  EXPECT_TRUE(o.centerAt(40.0).isApprox(Eigen::Vector3d(-600, 0, z)));
  EXPECT_TRUE(o.centerAt(60.0).isApprox(Eigen::Vector3d(600, 0, z)));

  const Eigen::Vector3d origin(0, 0, z);
  EXPECT_FALSE(world->isPointValid(origin, 10.0));  // it passes the origin at t = 10 s
  EXPECT_TRUE(world->isPointValid(origin, 0.0));    // at t = 0 it is 600 m away
  EXPECT_FALSE(world->isPointValid(origin));        // without a time its whole sweep is blocked

  // A vehicle crossing the obstacle's track north to south at 50 m/s, passing the origin at t.
  auto crossing = [&](double t_cross) {
    return world->isSegmentValidDuring(Eigen::Vector3d(0, 500, z), t_cross - 10.0, Eigen::Vector3d(0, -500, z),
                                       t_cross + 10.0);
  };
  EXPECT_FALSE(crossing(10.0));   // meets it at the origin
  EXPECT_TRUE(crossing(20.0));    // the obstacle is at the far end then
  // Against a dense time-sampled reference.
  for (double t_cross = 0.0; t_cross < 60.0; t_cross += 0.7) {
    bool dense = true;
    for (double t = t_cross - 10.0; t <= t_cross + 10.0 && dense; t += 0.002) {
      const Eigen::Vector3d p(0, 500 - 50.0 * (t - (t_cross - 10.0)), z);
      dense = (p - o.centerAt(t)).norm() > 105.0 + 0.2;
    }
    if (dense) {
      EXPECT_TRUE(crossing(t_cross)) << t_cross;
    }
    bool dense_hit = false;
    for (double t = t_cross - 10.0; t <= t_cross + 10.0 && !dense_hit; t += 0.002) {
      const Eigen::Vector3d p(0, 500 - 50.0 * (t - (t_cross - 10.0)), z);
      dense_hit = (p - o.centerAt(t)).norm() < 105.0 - 0.2;
    }
    if (dense_hit) {
      EXPECT_FALSE(crossing(t_cross)) << t_cross;
    }
  }
  EXPECT_NEAR(world->obstacleDistance(Eigen::Vector3d(0, 300, z), 10.0), 300.0 - 105.0, 0.5);
  // Snapshots for replanning: the obstacle frozen where it is at a time, optionally with a margin.
  const Eigen::Vector3d north(0, 500, z);
  const Eigen::Vector3d south(0, -500, z);
  EXPECT_FALSE(world->isSegmentValid(north, south));                 // timeless: the sweep blocks
  EXPECT_FALSE(world->isSegmentValid(north, south, 10.0));           // at the origin at t = 10 s
  EXPECT_TRUE(world->isSegmentValid(north, south, 0.0));             // 600 m west at t = 0
  EXPECT_FALSE(world->isSegmentValid(north, south, 0.0, 500.0));     // ... unless 500 m more room is kept
  EXPECT_TRUE(world->isPointValid(Eigen::Vector3d(-400, 0, z), 0.0, 90.0));
  EXPECT_FALSE(world->isPointValid(Eigen::Vector3d(-400, 0, z), 0.0, 100.0));
  EXPECT_TRUE(world->removeObstacle(7));
  EXPECT_TRUE(world->isPointValid(origin, 10.0));
}

TEST(Obstacle, TrackDuringCoversTheWholeTrackWhenThePhaseIsLost) {
  Obstacle o;
  o.motion = BackAndForth{{0, 0, 0}, {1, 0, 0}, 1.0e10, 0.0};  // 1 m track, 1e10 m/s
  // 1.7e19 m travelled: far past what a double resolves in 1 m steps (this used to loop forever).
  auto [from, to] = o.trackDuring(1.7e9, 1.7e9 + 60.0);
  EXPECT_EQ(from, o.motion->from_m);
  EXPECT_EQ(to, o.motion->to_m);
  // Two lengths or more in the interval also give the whole track; less gives the stretch covered.
  o.motion->speed_mps = 1.0;
  std::tie(from, to) = o.trackDuring(0.25, 2.5);
  EXPECT_EQ(from, o.motion->from_m);
  EXPECT_EQ(to, o.motion->to_m);
  std::tie(from, to) = o.trackDuring(0.25, 0.5);
  EXPECT_TRUE(from.isApprox(Eigen::Vector3d(0.25, 0, 0)));
  EXPECT_TRUE(to.isApprox(Eigen::Vector3d(0.5, 0, 0)));
  std::tie(from, to) = o.trackDuring(0.75, 1.5);  // turns at 1 m: covers [0.5, 1]
  EXPECT_TRUE(from.isApprox(Eigen::Vector3d(0.5, 0, 0)));
  EXPECT_TRUE(to.isApprox(Eigen::Vector3d(1, 0, 0)));
}

TEST(CollisionWorld, SnapshotTimeBandBlocksOnlyWhileTheVehicleCanBeThere) {
  auto world = makeWorld(5.0, 30.0, 5000.0);
  const double z = 1500.0;
  // A 100 m sphere reaching the origin at t = 20 s (from 1200 m west, at 60 m/s).
  const Obstacle o = sphereAlongX(8, 1200.0, z);
  world->upsertObstacle(o);
  ObstacleSnapshot snapshot;
  snapshot.time_s = 0.0;
  snapshot.window_s = 30.0;
  snapshot.focus_m = Eigen::Vector3d(0, 0, z);  // the vehicle is at the origin now
  const Eigen::Vector3d origin(0, 0, z);
  EXPECT_FALSE(world->isPointValid(origin, snapshot));  // the whole window: it passes here at 20 s
  snapshot.band_fast_mps = 60.0;
  snapshot.band_slow_mps = 20.0;
  snapshot.band_slack_s = 3.0;
  EXPECT_TRUE(world->isPointValid(origin, snapshot));  // the vehicle is gone by 3 s
  // 400 m east: reached between 6.7 s and 20 s (+-3 s); the obstacle is there at 26.7 s: free.
  EXPECT_TRUE(world->isPointValid(Eigen::Vector3d(400, 0, z), snapshot));
  // 400 m west: the obstacle is there at 13.3 s, inside that band: blocked.
  EXPECT_FALSE(world->isPointValid(Eigen::Vector3d(-400, 0, z), snapshot));
  // A segment west from the origin to 600 m: blocked where the band meets the obstacle.
  EXPECT_FALSE(world->isSegmentValid(origin, Eigen::Vector3d(-600, 0, z), snapshot));
  EXPECT_TRUE(world->isSegmentValid(origin, Eigen::Vector3d(300, 0, z), snapshot));
  // Never looser than the window itself: a point the obstacle never nears in the window is free
  // either way, and without a window nothing changes.
  snapshot.window_s = 5.0;  // it only gets from -1200 to -900 m
  EXPECT_TRUE(world->isPointValid(Eigen::Vector3d(-400, 0, z), snapshot));
}

TEST(CollisionWorld, TerrainDistanceFromOctree) {
  auto world = makeWorld(5.0, 30.0, 5000.0);
  const double g = world->terrain().heightAt(0.0, 0.0);
  const double d = world->terrainDistance(Eigen::Vector3d(0, 0, g + 300.0), 1000.0);
  // The nearest terrain voxel is at most the vertical gap away (plus a voxel) and not much nearer
  // than the gap shrunk by the local slope.
  EXPECT_LE(d, 300.0 + 30.0);
  EXPECT_GT(d, 100.0);
}

TEST(CollisionWorld, ConcurrentReadersWhileObstaclesChange) {
  auto world = makeWorld(5.0, 30.0, 5000.0);
  std::atomic<bool> stop{false};
  std::atomic<long> checks{0};
  std::vector<std::thread> readers;
  for (int r = 0; r < 3; ++r) {
    readers.emplace_back([&, r] {
      std::mt19937 rng(r);
      std::uniform_real_distribution<double> u(-3000.0, 3000.0);
      while (!stop) {
        const Eigen::Vector3d p(u(rng), u(rng), 1500.0);
        // Far from every obstacle the answer must not depend on the writer.
        if (std::abs(p.x()) > 1000.0) {
          EXPECT_TRUE(world->isPointValid(p));
        }
        world->isSegmentValid(p, p + Eigen::Vector3d(100, 100, 0));
        ++checks;
      }
    });
  }
  // Keep writing until the readers have run a while (they may start late on a busy machine).
  for (int i = 0; (i < 300 || checks.load() < 300) && i < 10000000; ++i) {
    world->upsertObstacle(makeObstacle(static_cast<std::uint64_t>(i % 5), ObstacleShape::kSphere,
                                       Eigen::Vector3d(200, 0, 0), Eigen::Vector3d(0.0, (i % 7) * 100.0, 1500.0)));
    if (i % 3 == 0) world->removeObstacle(i % 5);
  }
  stop = true;
  for (auto& t : readers) t.join();
  EXPECT_GT(checks.load(), 100);
}

TEST(CollisionWorld, RejectsBadOptions) {
  auto hf = defaultTerrain();
  EXPECT_EQ(CollisionWorld::create(hf, worldOptions(-1, 30, 1e9)).error().field, "vehicle_radius_m");
  EXPECT_EQ(CollisionWorld::create(hf, worldOptions(5, 1, 1e9)).error().field, "min_clearance_m");
  EXPECT_EQ(CollisionWorld::create(hf, worldOptions(5, 30, 10.0)).error().field, "ceiling_m");
}

TEST(TerrainGrid, BlockedCellsMatchBruteForce) {
  auto hf = defaultTerrain();
  TerrainGridOptions options;
  options.cell_size_m = 200.0;
  options.flight_ceiling_m = 600.0;
  options.min_clearance_m = 50.0;
  auto grid = buildTerrainGrid(*hf, options);
  ASSERT_TRUE(grid.ok()) << grid.error().describe();
  EXPECT_GT(grid->blockedCount(), 10u);                  // the ridge blocks the band
  EXPECT_LT(grid->blockedCount(), grid->cellCount() / 2);  // the valleys stay open
  for (int y = 0; y < grid->height(); ++y) {
    for (int x = 0; x < grid->width(); ++x) {
      const Eigen::Vector2d c = grid->cellCenter({x, y});
      double highest = -1e9;
      for (double dx = -100.0; dx <= 100.0; dx += 5.0)
        for (double dy = -100.0; dy <= 100.0; dy += 5.0) highest = std::max(highest, hf->heightAt(c.x() + dx, c.y() + dy));
      const bool expect_blocked = highest + 50.0 > 600.0;
      // The grid samples every half DEM cell (20 m), a 5 m brute force may see a few metres more.
      if (std::abs(highest + 50.0 - 600.0) > 5.0) {
        EXPECT_EQ(grid->blocked({x, y}), expect_blocked) << x << "," << y;
      }
    }
  }
  options.cell_size_m = 0.0;
  EXPECT_EQ(buildTerrainGrid(*hf, options).error().field, "cell_size_m");
  options.cell_size_m = 0.5;  // a 25000-cell-wide grid
  EXPECT_EQ(buildTerrainGrid(*hf, options).error().field, "cell_size_m");
  // A cancelled build stops with kCancelled (the engine cancels in-flight plans this way).
  const std::atomic<bool> cancelled{true};
  options.cell_size_m = 200.0;
  options.cancel = &cancelled;
  EXPECT_EQ(buildTerrainGrid(*hf, options).error().code, ErrorCode::kCancelled);
}

}  // namespace
}  // namespace skyroute
