// Allocation stage: the exact solver against brute force over every split and order, the greedy
// Algorithm 1 and the GA never better than exact (and greedy equal to it on the paper's obvious
// 5 x 5 example), seeded determinism; the improvement stage after Algorithm 1 never worse than
// its input, complete, within capacities, deterministic, and switchable off.
#include <algorithm>
#include <deque>
#include <random>

#include <gtest/gtest.h>

#include "planning/fleet/fleet_exact.hpp"
#include "planning/fleet/fleet_ga.hpp"
#include "planning/fleet/fleet_local_search.hpp"
#include "planning/fleet/fleet_planner.hpp"
#include "planning/fleet/gmtpa.hpp"

namespace skyroute {
namespace {

// Rows are y = 0 (top) down, as in a .map file.
GridLayer gridFrom(const std::vector<std::string>& rows) { return GridLayer::fromRows(rows); }

// The test's own breadth-first distance between two cells (no code shared with the planner).
int referenceSteps(const GridLayer& g, GridCell a, GridCell b) {
  std::vector<int> d(g.cellCount(), -1);
  std::deque<GridCell> q{a};
  d[g.index(a)] = 0;
  while (!q.empty()) {
    const GridCell c = q.front();
    q.pop_front();
    if (c == b) return d[g.index(c)];
    const GridCell next[4] = {{c.x + 1, c.y}, {c.x - 1, c.y}, {c.x, c.y + 1}, {c.x, c.y - 1}};
    for (const GridCell& n : next) {
      if (g.passable(n) && d[g.index(n)] < 0) {
        d[g.index(n)] = d[g.index(c)] + 1;
        q.push_back(n);
      }
    }
  }
  return -1;
}

// Least makespan over every assignment of tasks to vehicles and every order, by enumeration.
int bruteForceMakespan(const GridLayer& g, const FleetProblem& p) {
  const int nu = p.vehicleCount();
  const int nt = p.taskCount();
  int best = -1;
  std::vector<int> owner(static_cast<std::size_t>(nt), 0);
  while (true) {
    int makespan = 0;
    bool feasible = true;
    for (int i = 0; i < nu && feasible; ++i) {
      std::vector<int> mine;
      for (int j = 0; j < nt; ++j) {
        if (owner[j] == i) mine.push_back(j);
      }
      if (static_cast<int>(mine.size()) > p.capacity(i)) {
        feasible = false;
        break;
      }
      int least = mine.empty() ? 0 : -1;
      if (!mine.empty()) {
        do {
          int t = 0;
          GridCell at = p.vehicles[i].depot;
          bool ok = true;
          for (int j : mine) {
            const int d = referenceSteps(g, at, p.tasks[j].cell);
            ok = ok && d >= 0;
            t += d;
            at = p.tasks[j].cell;
          }
          const int back = referenceSteps(g, at, p.vehicles[i].depot);
          ok = ok && back >= 0;
          t += back;
          if (ok && (least < 0 || t < least)) least = t;
        } while (std::next_permutation(mine.begin(), mine.end()));
      }
      if (least < 0) feasible = false;
      makespan = std::max(makespan, least);
    }
    if (feasible && (best < 0 || makespan < best)) best = makespan;
    int k = 0;
    while (k < nt && ++owner[k] == nu) owner[k++] = 0;
    if (k == nt) break;
  }
  return best;
}

struct Instance {
  GridLayer grid;
  FleetProblem problem;
};

Instance randomInstance(std::mt19937_64& rng, int width, int height, int vehicles, int tasks, double obstacle_share) {
  while (true) {  // until the reachable region has room for every place
  Instance in;
  in.grid = GridLayer(width, height);
  std::bernoulli_distribution wall(obstacle_share);
  std::vector<GridCell> blocked;
  for (int y = 0; y < height; ++y) {
    for (int x = 0; x < width; ++x) {
      if (wall(rng)) blocked.push_back({x, y});
    }
  }
  in.grid.setStaticBlocked(blocked, true);
  // Places in the largest reachable region of the first free cell, all distinct.
  std::vector<GridCell> free;
  for (int y = 0; y < height; ++y) {
    for (int x = 0; x < width; ++x) {
      if (in.grid.passable({x, y})) free.push_back({x, y});
    }
  }
  std::vector<GridCell> region;
  for (const GridCell& c : free) {
    if (referenceSteps(in.grid, free.front(), c) >= 0) region.push_back(c);
  }
  if (static_cast<int>(region.size()) < vehicles + tasks) continue;
  std::shuffle(region.begin(), region.end(), rng);
  for (int i = 0; i < vehicles; ++i) in.problem.vehicles.push_back({"v" + std::to_string(i), region[i], 0});
  for (int j = 0; j < tasks; ++j) in.problem.tasks.push_back({"t" + std::to_string(j), region[vehicles + j]});
  return in;
  }
}

// Every task exactly once, capacities kept, and the reported costs are the sequences' own.
void expectValidAllocation(const FleetProblem& p, const TravelTimeTable& table, const FleetAllocation& a) {
  ASSERT_EQ(a.sequences.size(), p.vehicles.size());
  std::vector<int> seen(p.tasks.size(), 0);
  for (std::size_t i = 0; i < a.sequences.size(); ++i) {
    EXPECT_LE(static_cast<int>(a.sequences[i].size()), p.capacity(static_cast<int>(i)));
    for (int j : a.sequences[i]) ++seen[static_cast<std::size_t>(j)];
  }
  for (int s : seen) EXPECT_EQ(s, 1);
  FleetAllocation copy = a;
  refreshAllocationCosts(table, copy);
  EXPECT_EQ(copy.makespan_steps, a.makespan_steps);
  EXPECT_EQ(copy.sum_of_steps, a.sum_of_steps);
}

// Seed 002, section 4.1, Fig. 1-2: vehicle 1 should take tasks 1 and 2 near it, vehicle 2 tasks
// 3 and 4 near it; any other split sends a vehicle across the grid.
Instance papersFiveByFive() {
  Instance in;
  in.grid = gridFrom({
      ".....",
      ".#...",
      "...#.",
      ".....",
      ".....",
  });
  in.problem.vehicles = {{"1", {0, 0}, 0}, {"2", {4, 4}, 0}};
  in.problem.tasks = {{"1", {0, 2}}, {"2", {2, 0}}, {"3", {4, 2}}, {"4", {2, 4}}};
  return in;
}

TEST(FleetAllocation, ExactEqualsBruteForceAndNobodyBeatsExact) {
  std::mt19937_64 rng(20260402);
  for (int trial = 0; trial < 30; ++trial) {
    const int vehicles = 1 + trial % 3;
    const int tasks = 2 + trial % 5;
    Instance in = randomInstance(rng, 7, 6, vehicles, tasks, 0.2);
    if (trial % 4 == 0) in.problem.vehicles[0].max_tasks = 2;
    if (!validateFleetProblem(in.grid, in.problem).ok()) continue;
    const TravelTimeTable table = TravelTimeTable::build(in.grid, in.problem);
    const int reference = bruteForceMakespan(in.grid, in.problem);
    const auto exact = allocateExact(in.problem, table);
    if (reference < 0) {
      EXPECT_FALSE(exact.ok());
      continue;
    }
    ASSERT_TRUE(exact.ok()) << exact.error().describe();
    EXPECT_EQ(exact->makespan_steps, reference) << "trial " << trial;

    const auto greedy = allocateGreedy(in.problem, table);
    FleetGaOptions ga_options;
    ga_options.seed = 7 + trial;
    ga_options.generations = 60;
    const auto ga = allocateGenetic(in.problem, table, ga_options);
    for (const auto* a : {&greedy, &ga}) {
      ASSERT_TRUE(a->ok()) << a->error().describe();
      EXPECT_GE((*a)->makespan_steps, reference);
      expectValidAllocation(in.problem, table, **a);
    }
  }
}

TEST(FleetAllocation, GreedyEqualsExactOnThePapersObviousFiveByFive) {
  const Instance in = papersFiveByFive();
  const GridLayer& g = in.grid;
  const FleetProblem& p = in.problem;
  const TravelTimeTable table = TravelTimeTable::build(g, p);
  const auto greedy = allocateGreedy(p, table);
  const auto exact = allocateExact(p, table);
  ASSERT_TRUE(greedy.ok());
  ASSERT_TRUE(exact.ok());
  EXPECT_EQ(greedy->makespan_steps, exact->makespan_steps);
  EXPECT_EQ(exact->makespan_steps, bruteForceMakespan(g, p));
  // The improvement stage keeps it: already optimal, nothing to change.
  const FleetAllocation improved = improveAllocation(p, table, *greedy);
  EXPECT_EQ(improved.makespan_steps, exact->makespan_steps);
  EXPECT_EQ(improved.sequences, greedy->sequences);
  auto sorted = [](std::vector<int> v) {
    std::sort(v.begin(), v.end());
    return v;
  };
  EXPECT_EQ(sorted(greedy->sequences[0]), (std::vector<int>{0, 1}));
  EXPECT_EQ(sorted(greedy->sequences[1]), (std::vector<int>{2, 3}));
}

TEST(FleetAllocation, GreedyInsertsWhereTheMakespanRisesLeast) {
  // One vehicle, tasks on a line: the greedy insertion must produce the out-and-back order.
  GridLayer g(9, 1);
  FleetProblem p;
  p.vehicles = {{"v", {0, 0}, 0}};
  p.tasks = {{"a", {6, 0}}, {"b", {2, 0}}, {"c", {8, 0}}, {"d", {4, 0}}};
  const TravelTimeTable table = TravelTimeTable::build(g, p);
  const auto greedy = allocateGreedy(p, table);
  ASSERT_TRUE(greedy.ok());
  EXPECT_EQ(greedy->makespan_steps, 16);
  // Deterministic: the same call gives the same sequences.
  EXPECT_EQ(allocateGreedy(p, table)->sequences, greedy->sequences);
}

TEST(FleetAllocation, GeneticAlgorithmIsSeeded) {
  std::mt19937_64 rng(99);
  Instance in = randomInstance(rng, 12, 11, 4, 12, 0.15);
  ASSERT_TRUE(validateFleetProblem(in.grid, in.problem).ok());
  const TravelTimeTable table = TravelTimeTable::build(in.grid, in.problem);
  FleetGaOptions o;
  o.seed = 42;
  o.generations = 80;
  const auto a = allocateGenetic(in.problem, table, o);
  const auto b = allocateGenetic(in.problem, table, o);
  ASSERT_TRUE(a.ok());
  ASSERT_TRUE(b.ok());
  EXPECT_EQ(a->sequences, b->sequences);
  const auto exact = allocateExact(in.problem, table);
  ASSERT_TRUE(exact.ok());
  EXPECT_GE(a->makespan_steps, exact->makespan_steps);
}

TEST(FleetImprovement, NeverWorseCompleteWithinCapacitiesAndDeterministic) {
  std::mt19937_64 rng(20261122);
  int greedy_total = 0;
  int improved_total = 0;
  int exact_total = 0;
  for (int trial = 0; trial < 40; ++trial) {
    const int vehicles = 2 + trial % 4;
    const int tasks = 3 * vehicles - trial % 3;
    Instance in = randomInstance(rng, 12, 11, vehicles, tasks, 0.15);
    if (trial % 5 == 0) in.problem.vehicles[0].max_tasks = 1;
    if (trial % 7 == 0) in.problem.vehicles[1].max_tasks = 2;
    if (!validateFleetProblem(in.grid, in.problem).ok()) continue;
    const TravelTimeTable table = TravelTimeTable::build(in.grid, in.problem);
    const auto greedy = allocateGreedy(in.problem, table);
    ASSERT_TRUE(greedy.ok()) << greedy.error().describe();
    FleetImprovementReport report;
    const FleetAllocation improved = improveAllocation(in.problem, table, *greedy, {}, &report);
    expectValidAllocation(in.problem, table, improved);
    EXPECT_EQ(report.start_makespan_steps, greedy->makespan_steps);
    EXPECT_LE(improved.makespan_steps, greedy->makespan_steps) << "trial " << trial;
    if (improved.makespan_steps == greedy->makespan_steps) {
      EXPECT_LE(improved.sum_of_steps, greedy->sum_of_steps) << "trial " << trial;
    }
    // Same input, same options: the same allocation, move for move.
    const FleetAllocation again = improveAllocation(in.problem, table, *greedy);
    EXPECT_EQ(again.sequences, improved.sequences) << "trial " << trial;
    if (tasks <= 12) {
      const auto exact = allocateExact(in.problem, table);
      ASSERT_TRUE(exact.ok());
      EXPECT_GE(improved.makespan_steps, exact->makespan_steps) << "trial " << trial;
      greedy_total += greedy->makespan_steps;
      improved_total += improved.makespan_steps;
      exact_total += exact->makespan_steps;
    }
  }
  // The stage earns its keep: on these instances it closes most of the greedy's gap to the optimum.
  ASSERT_GT(greedy_total, exact_total);
  EXPECT_LT(improved_total - exact_total, (greedy_total - exact_total) / 4)
      << "greedy " << greedy_total << ", improved " << improved_total << ", exact " << exact_total;
}

TEST(FleetImprovement, ThePlannerRunsItAfterGreedyUnlessSwitchedOff) {
  const Instance in = papersFiveByFive();
  const auto greedy = allocateGreedy(in.problem, TravelTimeTable::build(in.grid, in.problem));
  ASSERT_TRUE(greedy.ok());
  FleetPlannerOptions off;
  off.improvement.enabled = false;
  const auto pure = planFleet(in.grid, in.problem, off);
  const auto with = planFleet(in.grid, in.problem);
  ASSERT_TRUE(pure.ok());
  ASSERT_TRUE(with.ok());
  EXPECT_EQ(pure->allocation.sequences, greedy->sequences);
  EXPECT_EQ(pure->allocation.algorithm, "greedy");
  EXPECT_EQ(with->allocation.algorithm, "greedy+improvement");
  EXPECT_EQ(with->improvement.start_makespan_steps, greedy->makespan_steps);
}

TEST(FleetImprovement, MovesATaskOffTheMakespanVehicle) {
  // An empty 7 x 7 grid, depots at two corners of the west edge. Algorithm 1 gives the middle
  // task (3,3) to the north vehicle early on, when that was cheapest, and the far task (6,2) to it
  // later: 18 steps. Moving (3,3) to the south vehicle gives the optimum of 16.
  const GridLayer g(7, 7);
  FleetProblem p;
  p.vehicles = {{"north", {0, 0}, 0}, {"south", {0, 6}, 0}};
  p.tasks = {{"t0", {3, 0}}, {"t1", {0, 2}}, {"t2", {3, 3}}, {"t3", {6, 2}}, {"t4", {4, 6}}};
  const TravelTimeTable table = TravelTimeTable::build(g, p);
  const auto greedy = allocateGreedy(p, table);
  const auto exact = allocateExact(p, table);
  ASSERT_TRUE(greedy.ok());
  ASSERT_TRUE(exact.ok());
  ASSERT_EQ(greedy->makespan_steps, 18);
  ASSERT_EQ(exact->makespan_steps, 16);
  FleetImprovementReport report;
  const FleetAllocation improved = improveAllocation(p, table, *greedy, {}, &report);
  expectValidAllocation(p, table, improved);
  EXPECT_EQ(improved.makespan_steps, 16);
  EXPECT_GE(report.moves, 1);
  EXPECT_EQ(std::count(improved.sequences[1].begin(), improved.sequences[1].end(), 2), 1);  // (3,3) went south
  // With the stage off, the same call hands Algorithm 1's allocation back unchanged.
  FleetImprovementOptions off;
  off.enabled = false;
  EXPECT_EQ(improveAllocation(p, table, *greedy, off).sequences, greedy->sequences);
}

TEST(FleetAllocation, ExactRefusesLargeInstances) {
  GridLayer g(30, 30);
  FleetProblem p;
  p.vehicles = {{"v", {0, 0}, 0}};
  for (int j = 0; j < 17; ++j) p.tasks.push_back({"t" + std::to_string(j), {j + 1, 3}});
  const auto exact = allocateExact(p, TravelTimeTable::build(g, p));
  ASSERT_FALSE(exact.ok());
  EXPECT_EQ(exact.error().code, ErrorCode::kInvalidArgument);
}

}  // namespace
}  // namespace skyroute
