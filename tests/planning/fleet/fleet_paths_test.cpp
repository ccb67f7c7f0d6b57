// Collision stage: the independent checker finds every planted conflict; space-time A* is as
// early as a plain space-time breadth-first search; the paper's 5 x 5 conflict is resolved by
// vehicle 2 waiting at (C,0) (Fig. 3); a moving obstacle is stepped around (Fig. 13); every plan
// returned on random instances is conflict-free with every task done once.
#include <algorithm>
#include <deque>
#include <map>
#include <random>
#include <set>
#include <tuple>

#include <gtest/gtest.h>

#include "planning/fleet/fleet_conflict_checker.hpp"
#include "planning/fleet/fleet_planner.hpp"
#include "planning/fleet/gmtpa.hpp"
#include "planning/grid/space_time_astar.hpp"
#include "terrain/movingai.hpp"
#include "tests/test_data.hpp"

namespace skyroute {
namespace {

// Rows are y = 0 (top) down, as in a .map file.
GridLayer gridFrom(const std::vector<std::string>& rows) { return GridLayer::fromRows(rows); }

using Key = std::tuple<int, int, int, int>;  // kind, a, b, step
std::set<Key> keysOf(const std::vector<FleetConflict>& conflicts) {
  std::set<Key> out;
  for (const auto& c : conflicts) out.insert({static_cast<int>(c.kind), c.a, c.b, c.step});
  return out;
}

// Reference conflict list from an occupancy table (cell, step) -> vehicles.
std::set<Key> referenceConflicts(const std::vector<std::vector<GridCell>>& paths) {
  int end = 0;
  for (const auto& p : paths) end = std::max(end, static_cast<int>(p.size()) - 1);
  auto at = [&](std::size_t v, int t) { return paths[v][std::min<std::size_t>(t, paths[v].size() - 1)]; };
  std::set<Key> out;
  for (int t = 0; t <= end; ++t) {
    std::map<std::pair<int, int>, std::vector<int>> occupancy;
    for (std::size_t v = 0; v < paths.size(); ++v) occupancy[{at(v, t).x, at(v, t).y}].push_back(static_cast<int>(v));
    for (const auto& [cell, who] : occupancy) {
      for (std::size_t i = 0; i < who.size(); ++i) {
        for (std::size_t k = i + 1; k < who.size(); ++k) out.insert({0, who[i], who[k], t});
      }
    }
    if (t == 0) continue;
    std::map<std::tuple<int, int, int, int>, int> moves;  // (from, to) -> vehicle
    for (std::size_t v = 0; v < paths.size(); ++v) {
      const GridCell a = at(v, t - 1);
      const GridCell b = at(v, t);
      if (a == b) continue;
      auto back = moves.find({b.x, b.y, a.x, a.y});
      if (back != moves.end()) out.insert({1, back->second, static_cast<int>(v), t});
      moves[{a.x, a.y, b.x, b.y}] = static_cast<int>(v);
    }
  }
  return out;
}

TEST(FleetChecker, FindsHandPlantedVertexAndSwapConflicts) {
  GridLayer g(6, 4);
  FleetProblem p;
  p.vehicles = {{"a", {0, 0}, 0}, {"b", {2, 2}, 0}, {"c", {5, 0}, 0}};
  // a runs right along y = 0 and back; b comes down to (2, 0) at step 2 (vertex with a);
  // c runs left and meets a head-on between steps 3 and 4 (a at (3,0) -> (4,0), c (4,0) -> (3,0)).
  const std::vector<std::vector<GridCell>> paths = {
      {{0, 0}, {1, 0}, {2, 0}, {3, 0}, {4, 0}, {3, 0}, {2, 0}, {1, 0}, {0, 0}},
      {{2, 2}, {2, 1}, {2, 0}, {2, 1}, {2, 2}},
      {{5, 0}, {5, 0}, {5, 0}, {4, 0}, {3, 0}, {4, 0}, {5, 0}},
  };
  const FleetCheckReport r = checkFleetPlan(g, p, paths, {{}, {}, {}});
  EXPECT_TRUE(r.violations.empty()) << r.summary();
  const std::set<Key> want = {{0, 0, 1, 2}, {1, 0, 2, 4}, {1, 0, 2, 5}};
  EXPECT_EQ(keysOf(r.conflicts), want) << r.summary();

  // Moving obstacles: one sitting where a passes at step 1, one swapping with b.
  p.moving_obstacles = {{"sit", 1, {{1, 0}}}, {"swap", 0, {{2, 1}, {2, 2}}}};
  const FleetCheckReport o = checkFleetPlan(g, p, paths, {{}, {}, {}});
  EXPECT_TRUE(keysOf(o.conflicts).count({0, 0, 3, 1}));
  EXPECT_TRUE(keysOf(o.conflicts).count({1, 1, 4, 1}));
}

TEST(FleetChecker, FindsEveryRandomlyPlantedConflict) {
  std::mt19937_64 rng(7);
  GridLayer g(8, 8);
  int planted_total = 0;
  for (int trial = 0; trial < 200; ++trial) {
    // Random walks that start and end at distinct depots (they walk out and retrace).
    const int nu = 2 + trial % 4;
    FleetProblem p;
    std::vector<std::vector<GridCell>> paths;
    std::set<std::pair<int, int>> used;
    for (int v = 0; v < nu; ++v) {
      GridCell d;
      do d = GridCell{static_cast<int>(rng() % 8), static_cast<int>(rng() % 8)};
      while (!used.insert({d.x, d.y}).second);
      p.vehicles.push_back({"v" + std::to_string(v), d, 0});
      std::vector<GridCell> out{d};
      const int steps = 2 + static_cast<int>(rng() % 6);
      for (int s = 0; s < steps; ++s) {
        GridCell c = out.back();
        const int m = static_cast<int>(rng() % 5);
        const GridCell moves[5] = {{1, 0}, {-1, 0}, {0, 1}, {0, -1}, {0, 0}};
        GridCell n{c.x + moves[m].x, c.y + moves[m].y};
        out.push_back(g.inside(n) ? n : c);
      }
      std::vector<GridCell> path = out;
      for (int k = static_cast<int>(out.size()) - 2; k >= 0; --k) path.push_back(out[static_cast<std::size_t>(k)]);
      paths.push_back(path);
    }
    const std::set<Key> want = referenceConflicts(paths);
    planted_total += static_cast<int>(want.size());
    const FleetCheckReport r = checkFleetPlan(g, p, paths, std::vector<std::vector<int>>(nu));
    EXPECT_TRUE(r.violations.empty()) << r.summary();
    EXPECT_EQ(keysOf(r.conflicts), want) << "trial " << trial;
  }
  EXPECT_GT(planted_total, 50);  // the random walks do collide, so the comparison means something
}

TEST(FleetChecker, ReportsBrokenPathsAndCoverage) {
  GridLayer g(5, 5);
  FleetProblem p;
  p.vehicles = {{"a", {0, 0}, 1}};
  p.tasks = {{"t", {2, 0}}, {"u", {0, 2}}};
  EXPECT_FALSE(checkFleetPlan(g, p, {{{0, 0}, {2, 0}, {1, 0}, {0, 0}}}, {{0}}).ok());     // jump
  EXPECT_FALSE(checkFleetPlan(g, p, {{{0, 0}, {1, 0}, {2, 0}, {1, 0}}}, {{0}}).ok());     // not home
  EXPECT_FALSE(checkFleetPlan(g, p, {{{0, 0}, {1, 0}, {0, 0}}}, {{0}}).ok());             // misses t
  EXPECT_FALSE(checkFleetPlan(g, p, {{{0, 0}, {1, 0}, {2, 0}, {1, 0}, {0, 0}}}, {{0}}).ok());  // u undone
}

// Earliest arrival by breadth-first search over (cell, step), with the rules written out again:
// no cell another agent holds at that step, no exchange of cells with one.
int referenceArrival(const GridLayer& g, const std::vector<std::vector<GridCell>>& others, GridCell start, GridCell goal,
                     int horizon) {
  auto held = [&](GridCell c, int t) {
    for (const auto& o : others) {
      if (o[std::min<std::size_t>(t, o.size() - 1)] == c) return true;
    }
    return false;
  };
  auto swaps = [&](GridCell a, GridCell b, int t) {
    for (const auto& o : others) {
      if (o[std::min<std::size_t>(t, o.size() - 1)] == b && o[std::min<std::size_t>(t + 1, o.size() - 1)] == a) return true;
    }
    return false;
  };
  std::set<std::pair<int, int>> layer{{start.x, start.y}};
  for (int t = 0; t <= horizon; ++t) {
    if (layer.count({goal.x, goal.y})) return t;
    std::set<std::pair<int, int>> next;
    for (const auto& [x, y] : layer) {
      const GridCell moves[5] = {{x + 1, y}, {x - 1, y}, {x, y + 1}, {x, y - 1}, {x, y}};
      for (const GridCell& n : moves) {
        if (g.blocked(n) || held(n, t + 1)) continue;
        if (!(n == GridCell{x, y}) && swaps({x, y}, n, t)) continue;
        next.insert({n.x, n.y});
      }
    }
    layer = std::move(next);
  }
  return -1;
}

// A width x height grid with `walls` cells blocked at random (a cell may be drawn twice).
GridLayer gridWithRandomWalls(int width, int height, int walls, std::mt19937_64& rng) {
  GridLayer g(width, height);
  std::vector<GridCell> blocked;
  for (int k = 0; k < walls; ++k) blocked.push_back({static_cast<int>(rng() % width), static_cast<int>(rng() % height)});
  g.setStaticBlocked(blocked, true);
  return g;
}

TEST(SpaceTimeAStar, ArrivesAsEarlyAsSpaceTimeBreadthFirstSearch) {
  std::mt19937_64 rng(11);
  int checked = 0;
  for (int trial = 0; trial < 120; ++trial) {
    GridLayer g = gridWithRandomWalls(9, 9, 14, rng);
    auto freeCell = [&] {
      GridCell c;
      do c = GridCell{static_cast<int>(rng() % 9), static_cast<int>(rng() % 9)};
      while (g.blocked(c));
      return c;
    };
    const GridCell start = freeCell();
    const GridCell goal = freeCell();
    // Other agents: random walks of 12 steps that end and vanish (not parked).
    std::vector<std::vector<GridCell>> others;
    CellTimeReservations res(g);
    for (int a = 0; a < 4; ++a) {
      std::vector<GridCell> w{freeCell()};
      while (w.front() == start) w.front() = freeCell();
      for (int s = 0; s < 12; ++s) {
        const GridCell c = w.back();
        const GridCell moves[5] = {{c.x + 1, c.y}, {c.x - 1, c.y}, {c.x, c.y + 1}, {c.x, c.y - 1}, c};
        const GridCell n = moves[rng() % 5];
        w.push_back(g.blocked(n) ? c : n);
      }
      for (std::size_t s = 0; s < w.size(); ++s) res.reserveCellAt(1 + a, w[s], static_cast<int>(s));
      // After their walk they are gone; the reference sees them beyond as a far-away cell.
      w.push_back({-100, -100});
      others.push_back(w);
    }
    SpaceTimeQuery q;
    q.self = 0;
    q.start = start;
    q.goal = goal;
    const SpaceTimePath path = planSpaceTime(g, res, q);
    const int want = referenceArrival(g, others, start, goal, 120);
    if (want < 0) {
      EXPECT_FALSE(path.found());
      continue;
    }
    ASSERT_TRUE(path.found()) << "trial " << trial << ": " << to_string(path.status);
    EXPECT_EQ(path.arrivalStep(), want) << "trial " << trial;
    // The path itself obeys the rules (checked against the plain walks).
    for (std::size_t t = 1; t < path.cells.size(); ++t) {
      const GridCell a = path.cells[t - 1];
      const GridCell b = path.cells[t];
      EXPECT_LE(std::abs(a.x - b.x) + std::abs(a.y - b.y), 1);
      for (const auto& o : others) {
        const GridCell ob = o[std::min<std::size_t>(t, o.size() - 1)];
        const GridCell oa = o[std::min<std::size_t>(t - 1, o.size() - 1)];
        EXPECT_FALSE(ob == b) << "trial " << trial << " step " << t;
        EXPECT_FALSE(oa == b && ob == a && !(a == b)) << "trial " << trial << " step " << t;
      }
    }
    ++checked;
  }
  EXPECT_GT(checked, 80);
}

TEST(SpaceTimeAStar, ParkingGoalWaitsUntilNobodyPassesAnyMore) {
  GridLayer g(5, 1);
  CellTimeReservations res(g);
  // Another agent passes over (2, 0) at step 6.
  res.reservePath(1, 0, {{4, 0}, {4, 0}, {4, 0}, {4, 0}, {3, 0}, {3, 0}, {2, 0}, {1, 0}, {0, 0}}, true);
  SpaceTimeQuery q;
  q.start = {2, 0};
  q.goal = {2, 0};
  q.park_at_goal = true;
  const SpaceTimePath path = planSpaceTime(g, res, q);
  // In a one-row corridor the only way to let it pass is impossible: no path.
  EXPECT_FALSE(path.found());
  GridLayer wide(5, 2);
  CellTimeReservations res2(wide);
  res2.reservePath(1, 0, {{4, 0}, {4, 0}, {4, 0}, {4, 0}, {3, 0}, {3, 0}, {2, 0}, {1, 0}, {0, 0}}, true);
  const SpaceTimePath aside = planSpaceTime(wide, res2, q);
  ASSERT_TRUE(aside.found());
  EXPECT_GE(aside.arrivalStep(), 7);  // back home only after the other went by
  EXPECT_TRUE(std::any_of(aside.cells.begin(), aside.cells.end(), [](GridCell c) { return c.y == 1; }));
}

// Seed 002, section 4.1, Fig. 3 (columns A-E are x = 0-4, rows 0-4 are y): vehicle 1 at (B,1)
// serves (E,1) and (E,3), vehicle 2 at (C,0) serves (C,3) and (C,4). On shortest paths both
// enter (C,1) at step 1; vehicle 2, which has slack, waits one step at (C,0).
TEST(FleetPaths, PapersFiveByFiveConflictIsResolvedByAWaitAtC0) {
  const GridLayer g = gridFrom({
      "##.##",
      ".....",
      "##.#.",
      "##.#.",
      "##.##",
  });
  FleetProblem p;
  p.vehicles = {{"1", {1, 1}, 0}, {"2", {2, 0}, 0}};
  p.tasks = {{"1", {4, 1}}, {"2", {4, 3}}, {"3", {2, 3}}, {"4", {2, 4}}};
  FleetPlannerOptions greedy_options;
  const auto greedy = planFleet(g, p, greedy_options);
  ASSERT_TRUE(greedy.ok()) << greedy.error().describe();
  FleetPlannerOptions exact_options;
  exact_options.allocator = FleetAllocator::kExact;
  const auto exact = planFleet(g, p, exact_options);
  ASSERT_TRUE(exact.ok()) << exact.error().describe();

  EXPECT_EQ(greedy->allocation.sequences, (std::vector<std::vector<int>>{{0, 1}, {2, 3}}));
  EXPECT_EQ(greedy->allocation.makespan_steps, exact->allocation.makespan_steps);
  EXPECT_EQ(greedy->makespan(), exact->makespan());
  EXPECT_EQ(greedy->makespan(), 10);  // the wait costs nothing: vehicle 2 had two steps of slack
  EXPECT_EQ(greedy->paths.conflicts_resolved, 1);

  const VehiclePlan& v2 = greedy->paths.vehicles[1];
  ASSERT_GE(v2.cells.size(), 3u);
  EXPECT_EQ(v2.cells[0], (GridCell{2, 0}));
  EXPECT_EQ(v2.cells[1], (GridCell{2, 0}));  // the wait at (C,0)
  EXPECT_EQ(v2.cells[2], (GridCell{2, 1}));
  const VehiclePlan& v1 = greedy->paths.vehicles[0];
  EXPECT_EQ(v1.cells[1], (GridCell{2, 1}));  // vehicle 1 keeps its shortest path
  EXPECT_EQ(v1.finish_step, 10);
  EXPECT_TRUE(checkFleetPlan(g, p, pathsOf(greedy->paths), sequencesOf(greedy->paths)).ok());
}

// Seed 002, Fig. 13: an obstacle moving up one cell per step. Here it comes head-on up the
// vehicle's column, so waiting is not enough: the vehicle steps aside, lets it pass and goes on.
TEST(FleetPaths, MovingObstacleIsSteppedAround) {
  const GridLayer g(5, 7);
  FleetProblem p;
  p.vehicles = {{"5", {2, 6}, 0}};
  p.tasks = {{"6", {2, 0}}};
  p.moving_obstacles = {MovingObstacle::straight("up", {2, 0}, 0, 1, 0, 6)};
  const auto plan = planFleet(g, p);
  ASSERT_TRUE(plan.ok()) << plan.error().describe();
  const VehiclePlan& v = plan->paths.vehicles[0];
  ASSERT_EQ(v.task_steps.size(), 1u);
  // Earliest possible arrival, by space-time breadth-first search with the obstacle as an agent.
  std::vector<GridCell> obstacle = p.moving_obstacles[0].cells;
  obstacle.push_back({-100, -100});
  EXPECT_EQ(v.task_steps[0], referenceArrival(g, {obstacle}, {2, 6}, {2, 0}, 50));
  EXPECT_EQ(v.task_steps[0], 8);  // two steps lost to the side step, none to waiting in vain
  EXPECT_TRUE(std::any_of(v.cells.begin(), v.cells.end(), [](GridCell c) { return c.x != 2; }));
  EXPECT_EQ(v.cells[static_cast<std::size_t>(v.task_steps[0])], (GridCell{2, 0}));
  EXPECT_GE(plan->paths.conflicts_resolved, 1);
  EXPECT_TRUE(checkFleetPlan(g, p, pathsOf(plan->paths), sequencesOf(plan->paths)).ok());
}

TEST(FleetPaths, ParkedVehicleMovesAsideForAnother) {
  // Vehicle "home" has no task and sits in the corridor; "far" must pass it twice, and the only
  // place to make room is the niche at (3, 1).
  const GridLayer g = gridFrom({
      "........",
      "###.####",
  });
  FleetProblem p;
  p.vehicles = {{"far", {0, 0}, 0}, {"home", {4, 0}, 0}};
  p.tasks = {{"t", {7, 0}}};
  const TravelTimeTable table = TravelTimeTable::build(g, p);
  FleetAllocation allocation;
  allocation.sequences = {{0}, {}};
  refreshAllocationCosts(table, allocation);
  const FleetPaths paths = buildFleetPaths(g, p, table, allocation);
  ASSERT_EQ(paths.status, PlannerStatus::kSolved) << paths.detail;
  const FleetCheckReport r = checkFleetPlan(g, p, pathsOf(paths), sequencesOf(paths));
  EXPECT_TRUE(r.ok()) << r.summary();
  const VehiclePlan& home = paths.vehicles[1];
  EXPECT_TRUE(std::any_of(home.cells.begin(), home.cells.end(), [](GridCell c) { return c.y == 1; }));
  EXPECT_EQ(home.cells.back(), (GridCell{4, 0}));
}

TEST(FleetPaths, EveryPlanOnRandomInstancesIsConflictFreeAndComplete) {
  std::mt19937_64 rng(2024);
  int planned = 0;
  int with_conflicts = 0;
  for (int trial = 0; trial < 60; ++trial) {
    GridLayer g = gridWithRandomWalls(12, 11, 20, rng);
    const int nu = 2 + trial % 5;
    FleetProblem p;
    std::set<std::pair<int, int>> used;
    auto place = [&] {
      GridCell c;
      do c = GridCell{static_cast<int>(rng() % 12), static_cast<int>(rng() % 11)};
      while (g.blocked(c) || !used.insert({c.x, c.y}).second);
      return c;
    };
    for (int i = 0; i < nu; ++i) p.vehicles.push_back({"v" + std::to_string(i), place(), 0});
    for (int j = 0; j < 3 * nu; ++j) p.tasks.push_back({"t" + std::to_string(j), place()});
    if (!validateFleetProblem(g, p).ok()) continue;  // a walled-in cell: covered by the problem tests
    for (FleetAllocator a : {FleetAllocator::kGreedy, FleetAllocator::kGenetic}) {
      FleetPlannerOptions o;
      o.allocator = a;
      o.ga.seed = static_cast<std::uint64_t>(trial);
      o.ga.generations = 40;
      const auto plan = planFleet(g, p, o);
      ASSERT_TRUE(plan.ok()) << "trial " << trial << " " << to_string(a) << ": " << plan.error().describe();
      const FleetCheckReport r = checkFleetPlan(g, p, pathsOf(plan->paths), sequencesOf(plan->paths));
      EXPECT_TRUE(r.ok()) << r.summary();
      EXPECT_TRUE(referenceConflicts(pathsOf(plan->paths)).empty());
      std::vector<int> done(p.tasks.size(), 0);
      for (const VehiclePlan& v : plan->paths.vehicles) {
        ASSERT_EQ(v.tasks.size(), v.task_steps.size());
        for (std::size_t k = 0; k < v.tasks.size(); ++k) {
          ++done[static_cast<std::size_t>(v.tasks[k])];
          EXPECT_EQ(v.cellAt(v.task_steps[k]), p.tasks[static_cast<std::size_t>(v.tasks[k])].cell);
        }
      }
      for (int d : done) EXPECT_EQ(d, 1);
      EXPECT_GE(plan->makespan(), plan->allocation.makespan_steps);
      with_conflicts += plan->paths.conflicts_resolved > 0 ? 1 : 0;
      ++planned;
    }
  }
  EXPECT_GT(planned, 80);
  EXPECT_GT(with_conflicts, 10);  // the instances are crowded enough to exercise the collision stage
}

TEST(FleetPaths, TwentyVehiclesOnAMovingAiMap) {
  SKYROUTE_REQUIRE_SHARED(map_path, "movingai/random-64-64-20.map");
  auto grid = loadMovingAiMap(map_path);
  ASSERT_TRUE(grid.ok()) << grid.error().describe();
  std::mt19937_64 rng(5);
  FleetProblem p;
  std::set<std::pair<int, int>> used;
  // Places in the component of the first vehicle, so every task is reachable.
  GridCell first;
  do first = GridCell{static_cast<int>(rng() % 64), static_cast<int>(rng() % 64)};
  while (grid->blocked(first));
  const std::vector<int> reach = bfsDistanceMap4(*grid, first);
  auto place = [&] {
    GridCell c;
    do c = GridCell{static_cast<int>(rng() % 64), static_cast<int>(rng() % 64)};
    while (grid->blocked(c) || reach[grid->index(c)] == kUnreachableSteps || !used.insert({c.x, c.y}).second);
    return c;
  };
  for (int i = 0; i < 20; ++i) p.vehicles.push_back({"v" + std::to_string(i), place(), 0});
  for (int j = 0; j < 60; ++j) p.tasks.push_back({"t" + std::to_string(j), place()});
  const auto plan = planFleet(*grid, p);
  ASSERT_TRUE(plan.ok()) << plan.error().describe();
  EXPECT_TRUE(referenceConflicts(pathsOf(plan->paths)).empty());
  EXPECT_TRUE(plan->check.ok());
}

}  // namespace
}  // namespace skyroute
