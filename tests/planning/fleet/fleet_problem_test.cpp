// Bad input to the fleet planner gets an error naming the item, never a crash or a plan.
#include <gtest/gtest.h>

#include <utility>

#include "planning/fleet/fleet_planner.hpp"
#include "planning/fleet/fleet_problem.hpp"

namespace skyroute {
namespace {

// Rows top to bottom are y = 0, 1, ...; '#' is blocked.
// Rows are y = 0 (top) down, as in a .map file.
GridLayer gridFrom(const std::vector<std::string>& rows) { return GridLayer::fromRows(rows); }

const std::vector<std::string> kRoom = {
    ".....#...",
    ".....#...",
    ".....#.#.",
    ".....#.#.",
    ".....#...",
};

FleetProblem twoVehicles() {
  FleetProblem p;
  p.vehicles = {{"alpha", {0, 0}, 0}, {"bravo", {4, 4}, 0}};
  p.tasks = {{"t1", {2, 2}}, {"t2", {3, 0}}};
  return p;
}

// twoVehicles() with one task more.
FleetProblem twoVehiclesAnd(FleetTask task) {
  FleetProblem p = twoVehicles();
  p.tasks.push_back(std::move(task));
  return p;
}

void expectError(const GridLayer& g, const FleetProblem& p, ErrorCode code, const std::string& must_name) {
  const Status s = validateFleetProblem(g, p);
  ASSERT_FALSE(s.ok()) << "accepted a bad problem; expected " << to_string(code);
  EXPECT_EQ(s.error().code, code) << s.error().describe();
  EXPECT_NE(s.error().describe().find(must_name), std::string::npos) << s.error().describe();
  // The planner refuses it the same way.
  const auto plan = planFleet(g, p);
  ASSERT_FALSE(plan.ok());
  EXPECT_EQ(plan.error().code, code);
}

TEST(FleetProblem, AcceptsAGoodProblem) {
  const GridLayer g = gridFrom(kRoom);
  EXPECT_TRUE(validateFleetProblem(g, twoVehicles()).ok());
}

TEST(FleetProblem, TaskInAnObstacleIsNamed) {
  const GridLayer g = gridFrom(kRoom);
  expectError(g, twoVehiclesAnd({"in-wall", {5, 2}}), ErrorCode::kOccupied, "in-wall");
}

TEST(FleetProblem, UnreachableTaskIsNamed) {
  const GridLayer g = gridFrom(kRoom);
  FleetProblem p = twoVehicles();
  p.tasks.push_back({"walled-in", {6, 2}});  // beyond the wall at x = 5
  expectError(g, p, ErrorCode::kUnreachable, "walled-in");
}

TEST(FleetProblem, MoreTasksThanCapacityIsRefused) {
  const GridLayer g = gridFrom(kRoom);
  FleetProblem p = twoVehicles();
  p.vehicles[0].max_tasks = 1;
  p.vehicles[1].max_tasks = 1;
  p.tasks.push_back({"t3", {1, 3}});
  expectError(g, p, ErrorCode::kInvalidArgument, "capacity");
}

TEST(FleetProblem, DuplicateIdsAreNamed) {
  const GridLayer g = gridFrom(kRoom);
  expectError(g, twoVehiclesAnd({"t1", {1, 3}}), ErrorCode::kInvalidArgument, "t1");
  FleetProblem q = twoVehicles();
  q.vehicles.push_back({"alpha", {2, 4}, 0});
  expectError(g, q, ErrorCode::kInvalidArgument, "alpha");
}

TEST(FleetProblem, OtherBadItemsAreNamed) {
  const GridLayer g = gridFrom(kRoom);
  expectError(g, twoVehiclesAnd({"far", {40, 1}}), ErrorCode::kOutsideMap, "far");
  FleetProblem depot_wall = twoVehicles();
  depot_wall.vehicles[1].depot = {5, 0};
  expectError(g, depot_wall, ErrorCode::kOccupied, "bravo");
  FleetProblem shared_depot = twoVehicles();
  shared_depot.vehicles[1].depot = {0, 0};
  expectError(g, shared_depot, ErrorCode::kInvalidArgument, "bravo");
  expectError(g, twoVehiclesAnd({"home", {4, 4}}), ErrorCode::kOccupied, "home");
  FleetProblem none;
  expectError(g, none, ErrorCode::kInvalidArgument, "vehicles");
  FleetProblem jumpy = twoVehicles();
  jumpy.moving_obstacles.push_back({"hopper", 0, {{1, 1}, {3, 1}}});
  expectError(g, jumpy, ErrorCode::kInvalidArgument, "hopper");
}

TEST(FleetProblem, CapacityTooTightForReachabilityIsAnAllocationError) {
  // Every task is reachable by someone and the total capacity suffices, but the only vehicle that
  // reaches the far-side tasks may take one of them.
  const GridLayer g = gridFrom({
      "..#..",
      "..#..",
  });
  FleetProblem p;
  p.vehicles = {{"left", {0, 0}, 0}, {"right", {4, 0}, 1}};
  p.tasks = {{"r1", {3, 1}}, {"r2", {4, 1}}};
  ASSERT_TRUE(validateFleetProblem(g, p).ok());
  for (FleetAllocator a : {FleetAllocator::kGreedy, FleetAllocator::kGenetic, FleetAllocator::kExact}) {
    FleetPlannerOptions o;
    o.allocator = a;
    o.ga.generations = 20;
    const auto plan = planFleet(g, p, o);
    ASSERT_FALSE(plan.ok()) << to_string(a);
    EXPECT_EQ(plan.error().code, ErrorCode::kUnreachable) << to_string(a) << ": " << plan.error().describe();
  }
}

}  // namespace
}  // namespace skyroute
