// Live re-ordering on the embedded terrain's order grid: an obstacle that walls off the approach
// to the next point makes another order shorter, and the incremental repair gives exactly what a
// from-scratch MMD*L solve of the same grid, vehicle and points left gives (cost matrix and order);
// a reached point is never ordered again; an obstacle far from every point changes no order and
// costs few expansions; while a point is cut off the order stays and the repair waits (then sees
// every cell that flipped); a moving obstacle covers the cells it crosses within the sweep only.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

#include "planning/mission/mission_planner.hpp"
#include "service/mission_order.hpp"
#include "service/mission_reorder.hpp"
#include "terrain/heightfield.hpp"
#include "tests/terrain_data.hpp"

namespace skyroute {
namespace {

constexpr double kClearanceM = 30.0;
constexpr double kCeilingM = 5000.0;
constexpr double kVehicleRadiusM = 5.0;

class MissionReorderTest : public ::testing::Test {
 protected:
  static void SetUpTestSuite() { terrain_ = testing::defaultTerrainHeightfield(); }
  void SetUp() override {
    ASSERT_TRUE(terrain_) << "data/default_terrain.tif did not load";
    // Two points near begin that are about as good either way round, then two on the way to end.
    points_ = {above(-4500, -4500), above(-2500, -4000), above(-4000, -2300), above(1000, 1000),
               above(2500, 3500),   above(4500, 4500)};
    auto order = orderMissionPoints(*terrain_, points_, kClearanceM, kCeilingM, false);
    ASSERT_TRUE(order.ok()) << order.error().describe();
    ASSERT_EQ(order->method, "mmdstar") << order->fallback_reason;
    order_ = *order;
    reorder_ = MissionReorder::create(order_.search, MissionReorderOptions{}, kVehicleRadiusM);
    ASSERT_TRUE(reorder_);
  }

  Eigen::Vector3d above(double east_m, double north_m) const {
    return {east_m, north_m, terrain_->heightAt(east_m, north_m) + 200.0};
  }
  // A fixed vertical cylinder of radius_m at `at` (2 km tall round the ground there).
  Obstacle cylinder(std::uint64_t id, const Eigen::Vector2d& at, double radius_m) const {
    Obstacle o;
    o.id = id;
    o.shape = ObstacleShape::kCylinder;
    o.size_m = Eigen::Vector3d(radius_m, radius_m, 1000.0);
    o.center_m = Eigen::Vector3d(at.x(), at.y(), terrain_->heightAt(at.x(), at.y()));
    return o;
  }
  // The points after the vehicle's in an order.
  static std::vector<int> left(const std::vector<int>& order) { return {order.begin() + 1, order.end()}; }

  // MMD*L from scratch on a copy of the repaired grid: the vehicle's cell as begin, the points
  // left as missions; its order and costs in the mission's numbering.
  struct Scratch {
    std::vector<int> order;
    std::vector<std::vector<double>> cost;  // [from][to] in the mission's numbering, cell edges
    double total = 0.0;
    std::uint64_t expansions = 0;
  };
  Scratch fromScratch(GridCell vehicle, int vehicle_point, const std::vector<int>& missions) const {
    grid_copy_ = reorder_->grid();
    const std::vector<GridCell>& cells = reorder_->search().cells;
    std::vector<GridCell> mission_cells;
    for (int p : missions) mission_cells.push_back(cells[static_cast<std::size_t>(p)]);
    auto planner = MissionPlanner::create(grid_copy_, vehicle, mission_cells, cells.back());
    EXPECT_TRUE(planner.ok()) << planner.error().describe();
    auto plan = planner->preplan();
    EXPECT_TRUE(plan.ok()) << plan.error().describe();
    // Scratch numbering: 0 = vehicle, 1..m = missions, m+1 = end.
    std::vector<int> to_mission{vehicle_point};
    to_mission.insert(to_mission.end(), missions.begin(), missions.end());
    to_mission.push_back(static_cast<int>(cells.size()) - 1);
    Scratch out;
    for (int p : plan->order) out.order.push_back(to_mission[static_cast<std::size_t>(p)]);
    out.cost.assign(cells.size(), std::vector<double>(cells.size(), kInfiniteCost));
    for (std::size_t i = 0; i < to_mission.size(); ++i)
      for (std::size_t j = 0; j < to_mission.size(); ++j)
        out.cost[static_cast<std::size_t>(to_mission[i])][static_cast<std::size_t>(to_mission[j])] = plan->cost_matrix[i][j];
    out.total = plan->cost;
    out.expansions = plan->search.expansions;
    return out;
  }
  // Every pair the incremental searches plan now equals the from-scratch cost.
  void expectSameCosts(const Scratch& scratch) const {
    const MissionSearch& s = reorder_->planner().search();
    for (int from = 0; from < s.pointCount(); ++from) {
      for (int to = 0; to < s.pointCount(); ++to) {
        if (!s.planned(from, to)) continue;
        const double expected = scratch.cost[static_cast<std::size_t>(from)][static_cast<std::size_t>(to)];
        EXPECT_NEAR(s.cost(from, to), expected, 1e-9 * std::max(1.0, expected)) << from << " -> " << to;
      }
    }
  }

  static inline std::shared_ptr<const Heightfield> terrain_;
  std::vector<Eigen::Vector3d> points_;
  MissionOrder order_;
  std::unique_ptr<MissionReorder> reorder_;
  mutable GridLayer grid_copy_;
};

TEST_F(MissionReorderTest, BlockingTheApproachToTheNextPointReordersAsAFromScratchSolveDoes) {
  const std::vector<int> first = order_.order;
  const int next = first[1];
  // A wall of cylinders 1.5 km wide across the way from begin to the next point, halfway.
  const Eigen::Vector2d from = points_[0].head<2>();
  const Eigen::Vector2d to = points_[static_cast<std::size_t>(next)].head<2>();
  const Eigen::Vector2d across = Eigen::Vector2d(-(to - from).y(), (to - from).x()).normalized();
  std::vector<Obstacle> wall;
  for (int k = -3; k <= 3; ++k) wall.push_back(cylinder(100 + static_cast<std::uint64_t>(k + 3), 0.5 * (from + to) + k * 250.0 * across, 200.0));
  const ReorderCheck check = reorder_->check(wall, 0.0, {}, points_[0], left(first));
  ASSERT_FALSE(check.failure) << check.failure->describe();
  ASSERT_TRUE(check.repaired);
  EXPECT_GT(check.changed_cells, 0u);
  EXPECT_EQ(check.old_order, first);
  ASSERT_TRUE(check.reordered()) << orderText(check.old_order) << " stays: " << check.old_cost_m << " m vs "
                                 << check.new_cost_m << " m; first " << order_.cost_m << " m, changed " << check.changed_cells << " covered " << check.covered_cells;
  EXPECT_NE(check.new_order[1], next);
  EXPECT_LT(check.new_cost_m, check.old_cost_m);
  // The same as planning the whole mission afresh on the changed grid.
  const std::vector<int> missions{1, 2, 3, 4};
  const Scratch scratch = fromScratch(reorder_->search().cells.front(), 0, missions);
  EXPECT_EQ(check.new_order, scratch.order);
  EXPECT_NEAR(check.new_cost_m, scratch.total * order_.cell_size_m, 1e-6);
  expectSameCosts(scratch);
  // Fewer expansions than the from-scratch solve: the searches were repaired, not rebuilt.
  EXPECT_LT(check.search.expansions, scratch.expansions);
}

TEST_F(MissionReorderTest, AReachedPointIsNeverOrderedAgainAndTheRepairMatchesAFreshSolveFromTheVehicle) {
  const std::vector<int> first = order_.order;
  const int reached = first[1];
  // The vehicle passed the first point and is a third of the way to the second.
  const Eigen::Vector3d vehicle = points_[static_cast<std::size_t>(reached)] +
                                  (points_[static_cast<std::size_t>(first[2])] - points_[static_cast<std::size_t>(reached)]) / 3.0;
  const std::vector<int> flown(first.begin() + 2, first.end());
  // An obstacle on the way to the next point.
  const Eigen::Vector2d on_the_way = (0.5 * (vehicle + points_[static_cast<std::size_t>(first[2])])).head<2>();
  const std::vector<Obstacle> obstacles{cylinder(7, on_the_way, 600.0)};
  const std::vector<int> reached_points{reached};
  const ReorderCheck check = reorder_->check(obstacles, 0.0, reached_points, vehicle, flown);
  ASSERT_FALSE(check.failure) << check.failure->describe();
  ASSERT_TRUE(check.repaired);
  EXPECT_EQ(check.old_order.front(), reached);
  EXPECT_EQ(check.new_order.front(), reached);
  EXPECT_EQ(std::count(check.new_order.begin(), check.new_order.end(), reached), 1);
  EXPECT_TRUE(reorder_->planner().search().visited(reached));
  // From scratch: the vehicle's cell as begin, the points not reached as missions.
  std::vector<int> missions;
  for (int p = 1; p <= 4; ++p)
    if (p != reached) missions.push_back(p);
  const GridCell vehicle_cell = *reorder_->grid().cellAt(vehicle.head<2>());
  ASSERT_TRUE(reorder_->grid().passable(vehicle_cell));
  const Scratch scratch = fromScratch(vehicle_cell, reached, missions);
  expectSameCosts(scratch);
  EXPECT_NEAR(check.new_cost_m, scratch.total * order_.cell_size_m, 1e-6);
  EXPECT_EQ(check.reordered() ? check.new_order : check.old_order, scratch.order);
}

TEST_F(MissionReorderTest, AnUpdateFarFromTheRouteChangesNothingAndCostsFewExpansions) {
  const std::vector<int> first = order_.order;
  // In the north-west corner, 3 km and more from every point.
  const std::vector<Obstacle> far{cylinder(1, Eigen::Vector2d(-5800, 5800), 300.0)};
  for (const Eigen::Vector3d& p : points_) ASSERT_GT((p.head<2>() - Eigen::Vector2d(-5800, 5800)).norm(), 3000.0);
  const ReorderCheck check = reorder_->check(far, 0.0, {}, points_[0], left(first));
  ASSERT_FALSE(check.failure) << check.failure->describe();
  ASSERT_TRUE(check.repaired);
  EXPECT_GT(check.changed_cells, 0u);
  EXPECT_FALSE(check.reordered());
  EXPECT_EQ(check.new_order, first);
  // Few: under a hundredth of what planning the mission cost.
  EXPECT_LT(check.search.expansions, order_.expansions / 100) << "of " << order_.expansions;
  // The same obstacle again: nothing flips, nothing is repaired.
  const ReorderCheck again = reorder_->check(far, 0.0, {}, points_[0], left(first));
  EXPECT_FALSE(again.repaired);
  EXPECT_EQ(again.changed_cells, 0u);
}

TEST_F(MissionReorderTest, WhileAPointIsCutOffTheOrderStaysAndTheRepairWaitsForIt) {
  const std::vector<int> first = order_.order;
  // A closed ring round points[2] (mission point 3), then the same ring with a gap.
  const Eigen::Vector2d at = points_[3].head<2>();
  auto ring = [&](int gap) {
    std::vector<Obstacle> out;
    for (int k = 0; k < 16; ++k) {
      if (k < gap) continue;
      const double angle = 2.0 * M_PI * k / 16.0;
      out.push_back(cylinder(200 + static_cast<std::uint64_t>(k), at + 800.0 * Eigen::Vector2d(std::cos(angle), std::sin(angle)), 200.0));
    }
    return out;
  };
  const ReorderCheck closed = reorder_->check(ring(0), 0.0, {}, points_[0], left(first));
  ASSERT_TRUE(closed.failure);
  EXPECT_EQ(closed.failure->field, "points[2]") << closed.failure->describe();
  EXPECT_FALSE(closed.repaired);
  EXPECT_GT(closed.changed_cells, 0u);
  EXPECT_FALSE(closed.reordered());
  // Open again: the searches now see the ring's cells too (kept while they waited), exactly as a
  // from-scratch solve of the grid does.
  const ReorderCheck open = reorder_->check(ring(3), 0.0, {}, points_[0], left(first));
  ASSERT_FALSE(open.failure) << open.failure->describe();
  ASSERT_TRUE(open.repaired);
  const Scratch scratch = fromScratch(reorder_->search().cells.front(), 0, {1, 2, 3, 4});
  expectSameCosts(scratch);
  EXPECT_NEAR(open.new_cost_m, scratch.total * order_.cell_size_m, 1e-6);
}

TEST_F(MissionReorderTest, ANoFlyZoneAcrossTheApproachReordersAsAnObstacleDoesAndLiftingItRestoresTheCosts) {
  const std::vector<int> first = order_.order;
  const int next = first[1];
  // A zone 1.9 km long and 400 m deep across the way from begin to the next point, halfway: the
  // footprint of the cylinder wall of the first test.
  const Eigen::Vector2d from = points_[0].head<2>();
  const Eigen::Vector2d to = points_[static_cast<std::size_t>(next)].head<2>();
  const Eigen::Vector2d along = (to - from).normalized();
  const Eigen::Vector2d across(-along.y(), along.x());
  const Eigen::Vector2d mid = 0.5 * (from + to);
  NoFlyZone zone;
  zone.name = "tfr-1";
  zone.ring_m = {mid - 950.0 * across - 200.0 * along, mid + 950.0 * across - 200.0 * along,
                 mid + 950.0 * across + 200.0 * along, mid - 950.0 * across + 200.0 * along};
  zone.floor_m = 0.0;
  zone.ceiling_m = 9000.0;
  const std::vector<NoFlyZone> zones{zone};
  const ReorderCheck check = reorder_->check({}, zones, 0.0, {}, points_[0], left(first));
  ASSERT_FALSE(check.failure) << check.failure->describe();
  ASSERT_TRUE(check.repaired);
  EXPECT_GT(check.covered_cells, 0u);
  ASSERT_TRUE(check.reordered()) << orderText(check.old_order) << " stays: " << check.old_cost_m << " m vs "
                                 << check.new_cost_m << " m";
  EXPECT_NE(check.new_order[1], next);
  const Scratch scratch = fromScratch(reorder_->search().cells.front(), 0, {1, 2, 3, 4});
  EXPECT_EQ(check.new_order, scratch.order);
  expectSameCosts(scratch);
  // A zone whose window starts after the sweep covers nothing yet.
  NoFlyZone later = zone;
  later.name = "tfr-2";
  later.valid_from_s = 3600.0;
  EXPECT_TRUE(MissionReorder::zoneCover(reorder_->search(), std::vector<NoFlyZone>{later}, 0.0, 15.0).empty());
  // Lifted: its cells are free again, and the costs are the first plan's.
  const ReorderCheck lifted = reorder_->check({}, std::vector<NoFlyZone>{}, 0.0, {}, points_[0], left(check.new_order.empty() ? first : check.new_order));
  ASSERT_TRUE(lifted.repaired);
  EXPECT_EQ(lifted.changed_cells, check.changed_cells);
  EXPECT_TRUE(reorder_->covered().empty());
  EXPECT_NEAR(lifted.new_cost_m, order_.cost_m, 1e-6);
}

TEST_F(MissionReorderTest, AZoneTheGridWasBuiltWithIsNotCoveredAgain) {
  NoFlyZone zone;
  zone.name = "built-in";
  zone.ring_m = {{-5900, 5000}, {-5000, 5000}, {-5000, 5900}, {-5900, 5900}};
  zone.floor_m = 0.0;
  zone.ceiling_m = 9000.0;
  auto order = orderMissionPoints(*terrain_, points_, kClearanceM, kCeilingM, false, MissionOrderOptions{}, {},
                                  std::vector<NoFlyZone>{zone}, kVehicleRadiusM);
  ASSERT_TRUE(order.ok()) << order.error().describe();
  ASSERT_EQ(order->method, "mmdstar");
  EXPECT_TRUE(MissionReorder::zoneCover(*order->search, std::vector<NoFlyZone>{zone}, 0.0, 15.0).empty());
  // The same name with another shape is a new zone.
  NoFlyZone moved = zone;
  for (Eigen::Vector2d& v : moved.ring_m) v.x() += 1500.0;
  EXPECT_FALSE(MissionReorder::zoneCover(*order->search, std::vector<NoFlyZone>{moved}, 0.0, 15.0).empty());
}

TEST_F(MissionReorderTest, AMovingObstacleCoversTheCellsItCrossesWithinTheSweepOnly) {
  const GridLayer& grid = reorder_->grid();
  Obstacle moving = cylinder(3, Eigen::Vector2d(-2000, 0), 100.0);
  moving.motion = BackAndForth{moving.center_m, moving.center_m + Eigen::Vector3d(4000, 0, 0), 100.0};
  const std::vector<Obstacle> obstacles{moving};
  const std::vector<std::uint32_t> cover =
      MissionReorder::coverOf(grid, obstacles, 0.0, 15.0, kVehicleRadiusM, kCeilingM, {});
  auto covered = [&](double east_m) {
    const GridCell c = *grid.cellAt(Eigen::Vector2d(east_m, 0.0));
    return std::binary_search(cover.begin(), cover.end(), static_cast<std::uint32_t>(grid.index(c)));
  };
  EXPECT_TRUE(covered(-2000));  // now
  EXPECT_TRUE(covered(-1250));  // halfway through the sweep
  EXPECT_TRUE(covered(-500));   // 15 s on at 100 m/s
  EXPECT_FALSE(covered(0));     // 20 s on: past the sweep
  EXPECT_FALSE(covered(-2500));
  // Above the band it covers nothing.
  Obstacle high = cylinder(4, Eigen::Vector2d(0, 0), 300.0);
  high.center_m.z() = kCeilingM + 2000.0;
  const std::vector<Obstacle> above{high};
  EXPECT_TRUE(MissionReorder::coverOf(grid, above, 0.0, 15.0, kVehicleRadiusM, kCeilingM, {}).empty());
}

}  // namespace
}  // namespace skyroute
