// GMTPA benchmark (seed 002, section 4): the paper's 12 x 11 experiment in three environments
// (empty, narrow gap, scattered obstacles; Fig. 4-6) with 2-5 vehicles and three times as many
// tasks, 50 random task placements each, for the greedy allocation (Algorithm 1 alone and with the
// improvement stage), the GA baseline and the exact solver, all followed by the same
// collision-free path stage; then the scale run of 20 vehicles
// and 60 tasks on the Moving AI multi-agent maps. Prints markdown tables.
//
//   gmtpa_bench [--placements N] [--skip-exact] [--scale-runs N]
#include <algorithm>
#include <cstdio>
#include <cstring>
#include <ctime>
#include <random>
#include <set>
#include <string>
#include <vector>

#include "bench/support/shared_data.hpp"
#include "planning/fleet/fleet_planner.hpp"
#include "terrain/movingai.hpp"

using namespace skyroute;

namespace {

// Rows are y = 0 (top) down, as in a .map file.
GridLayer gridFrom(const std::vector<std::string>& rows) { return GridLayer::fromRows(rows); }

struct Environment {
  const char* name;
  GridLayer grid;
};

std::vector<Environment> paperEnvironments() {
  std::vector<Environment> envs;
  envs.push_back({"empty", GridLayer(12, 11)});
  // Fig. 5: a wall across the middle with a one-cell gap; the vehicles start on one side.
  std::vector<std::string> gap(11, "......#.....");
  gap[5] = "............";
  envs.push_back({"narrow gap", gridFrom(gap)});
  // Fig. 6: blocks scattered over the area.
  envs.push_back({"obstacles", gridFrom({
                                   "............",
                                   ".##...##....",
                                   ".##...##..#.",
                                   "..........#.",
                                   "....##......",
                                   "....##...##.",
                                   ".........##.",
                                   ".##.........",
                                   ".##....##...",
                                   ".......##...",
                                   "............",
                               })});
  return envs;
}

// Fixed depots down the west edge, as the paper keeps the vehicles' positions fixed.
const GridCell kDepots[5] = {{0, 1}, {0, 3}, {0, 5}, {0, 7}, {0, 9}};

FleetProblem placement(const GridLayer& grid, int vehicles, int tasks, std::mt19937_64& rng) {
  FleetProblem p;
  std::set<std::pair<int, int>> used;
  for (int i = 0; i < vehicles; ++i) {
    p.vehicles.push_back({"v" + std::to_string(i), kDepots[i], 0});
    used.insert({kDepots[i].x, kDepots[i].y});
  }
  std::uniform_int_distribution<int> x(0, grid.width() - 1);
  std::uniform_int_distribution<int> y(0, grid.height() - 1);
  while (static_cast<int>(p.tasks.size()) < tasks) {
    const GridCell c{x(rng), y(rng)};
    if (grid.blocked(c) || !used.insert({c.x, c.y}).second) continue;
    p.tasks.push_back({"t" + std::to_string(p.tasks.size()), c});
  }
  return p;
}

// Processor time of this process: the machine is shared, and other jobs inflate wall time.
double cpuMs() {
  timespec ts{};
  clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &ts);
  return ts.tv_sec * 1e3 + ts.tv_nsec * 1e-6;
}

struct Tally {
  double makespan = 0, alloc_makespan = 0, alloc_ms = 0, total_ms = 0, cpu_ms = 0, conflicts = 0;
  int runs = 0, failures = 0, unchecked = 0;
  void add(const FleetPlan& plan, double cpu) {
    makespan += plan.makespan();
    alloc_makespan += plan.allocation.makespan_steps;
    alloc_ms += plan.allocation.time_s * 1e3;
    total_ms += plan.total_time_s * 1e3;
    cpu_ms += cpu;
    conflicts += plan.paths.conflicts_resolved;
    unchecked += plan.check.ok() ? 0 : 1;
    ++runs;
  }
  double mean(double v) const { return runs > 0 ? v / runs : 0.0; }
};

// Runs planFleet and adds it to the tally; returns the plan (or its error).
Result<FleetPlan> run(const GridLayer& grid, const FleetProblem& p, const FleetPlannerOptions& o, Tally& tally) {
  const double before = cpuMs();
  auto plan = planFleet(grid, p, o);
  const double cpu = cpuMs() - before;
  if (plan.ok()) tally.add(*plan, cpu);
  else ++tally.failures;
  return plan;
}

std::string fixed(double v, int decimals) {
  char buf[64];
  std::snprintf(buf, sizeof buf, "%.*f", decimals, v);
  return buf;
}

void paperExperiment(int placements, bool exact) {
  std::printf("## Paper experiment: 12 x 11 grid, %d placements per row\n\n", placements);
  std::printf("Makespans are final (collision-free) steps, alloc. makespans the allocators' estimates; "
              "times are mean processor ms per instance of the whole pipeline; Alg. 1 = pure greedy, "
              "+impr. = greedy followed by the improvement stage.\n\n");
  std::printf("| environment | vehicles | tasks | makespan Alg. 1 | makespan Alg. 1 + impr. | makespan GA | "
              "makespan exact | +impr. - GA | alloc. makespan Alg. 1 / +impr. / GA / exact | gap to exact Alg. 1 / +impr. | "
              "CPU ms Alg. 1 | CPU ms +impr. | CPU ms GA | CPU ms exact | GA / +impr. CPU | conflicts resolved (+impr.) | "
              "failures |\n");
  std::printf("|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|\n");
  double worst_diff = -1e9;
  for (const Environment& env : paperEnvironments()) {
    for (int nu = 2; nu <= 5; ++nu) {
      const int nt = 3 * nu;
      std::mt19937_64 rng(1000 + nu);
      Tally pure, improved, ga, ex;
      double gap_pure = 0.0, gap_improved = 0.0;
      int gap_runs = 0;
      for (int k = 0; k < placements; ++k) {
        const FleetProblem p = placement(env.grid, nu, nt, rng);
        FleetPlannerOptions o;
        o.ga.seed = static_cast<std::uint64_t>(k + 1);
        o.improvement.enabled = false;
        const auto g = run(env.grid, p, o, pure);
        o.improvement.enabled = true;
        const auto gi = run(env.grid, p, o, improved);
        o.allocator = FleetAllocator::kGenetic;
        run(env.grid, p, o, ga);
        if (exact) {
          o.allocator = FleetAllocator::kExact;
          const auto e = run(env.grid, p, o, ex);
          if (e.ok() && g.ok() && gi.ok()) {
            const double best = std::max(1, e->allocation.makespan_steps);
            gap_pure += 100.0 * (g->allocation.makespan_steps - e->allocation.makespan_steps) / best;
            gap_improved += 100.0 * (gi->allocation.makespan_steps - e->allocation.makespan_steps) / best;
            ++gap_runs;
          }
        }
      }
      const double diff = improved.mean(improved.makespan) - ga.mean(ga.makespan);
      worst_diff = std::max(worst_diff, diff);
      const std::string ex_makespan = exact ? fixed(ex.mean(ex.makespan), 2) : "-";
      const std::string ex_alloc = exact ? fixed(ex.mean(ex.alloc_makespan), 2) : "-";
      const std::string gaps =
          gap_runs ? fixed(gap_pure / gap_runs, 2) + " % / " + fixed(gap_improved / gap_runs, 2) + " %" : "-";
      const std::string ex_cpu = exact ? fixed(ex.mean(ex.cpu_ms), 3) : "-";
      std::printf("| %s | %d | %d | %.2f | %.2f | %.2f | %s | %+.2f | %.2f / %.2f / %.2f / %s | %s | %.3f | %.3f | %.1f | %s | "
                  "%.0fx | %.2f | %d/%d/%d/%d |\n",
                  env.name, nu, nt, pure.mean(pure.makespan), improved.mean(improved.makespan), ga.mean(ga.makespan),
                  ex_makespan.c_str(), diff, pure.mean(pure.alloc_makespan), improved.mean(improved.alloc_makespan),
                  ga.mean(ga.alloc_makespan), ex_alloc.c_str(), gaps.c_str(), pure.mean(pure.cpu_ms),
                  improved.mean(improved.cpu_ms), ga.mean(ga.cpu_ms), ex_cpu.c_str(),
                  improved.cpu_ms > 0 ? ga.cpu_ms / improved.cpu_ms : 0.0, improved.mean(improved.conflicts),
                  pure.failures + pure.unchecked, improved.failures + improved.unchecked, ga.failures + ga.unchecked,
                  ex.failures + ex.unchecked);
      std::fflush(stdout);
    }
  }
  std::printf("\nWorst row, greedy + improvement minus GA (final makespan): %+.2f steps\n\n", worst_diff);
}

void scaleRun(const std::string& map_name, int runs) {
  const std::string path = std::string(SKYROUTE_SHARED_DATA_DIR) + "/movingai/" + map_name;
  auto grid = loadMovingAiMap(path);
  if (!grid) {
    bench::skipCaseForMissingData("| " + map_name + " | - | - | - | - | - | - | skipped: " + grid.error().describe() + " |",
                                  grid.error().describe());
    return;
  }
  // Places in the largest 4-connected region.
  std::vector<int> best_map;
  std::size_t best_size = 0;
  std::vector<bool> seen(grid->cellCount(), false);
  for (std::size_t i = 0; i < grid->cellCount(); ++i) {
    if (seen[i] || grid->blocked(grid->cellOf(i))) continue;
    auto map = bfsDistanceMap4(*grid, grid->cellOf(i));
    std::size_t size = 0;
    for (std::size_t k = 0; k < map.size(); ++k) {
      if (map[k] != kUnreachableSteps) {
        seen[k] = true;
        ++size;
      }
    }
    if (size > best_size) {
      best_size = size;
      best_map = std::move(map);
    }
  }
  std::vector<GridCell> region;
  for (std::size_t k = 0; k < best_map.size(); ++k) {
    if (best_map[k] != kUnreachableSteps) region.push_back(grid->cellOf(k));
  }
  double sum_ms = 0, max_ms = 0, sum_makespan = 0, sum_alloc = 0, sum_alg1 = 0, sum_conf = 0, sum_alloc_ms = 0, sum_path_ms = 0;
  int ok = 0, clean = 0;
  for (int r = 0; r < runs; ++r) {
    std::mt19937_64 rng(77 + r);
    std::shuffle(region.begin(), region.end(), rng);
    FleetProblem p;
    for (int i = 0; i < 20; ++i) p.vehicles.push_back({"v" + std::to_string(i), region[i], 0});
    for (int j = 0; j < 60; ++j) p.tasks.push_back({"t" + std::to_string(j), region[20 + j]});
    const auto plan = planFleet(*grid, p);
    if (!plan) {
      std::printf("<!-- %s run %d failed: %s -->\n", map_name.c_str(), r, plan.error().describe().c_str());
      continue;
    }
    ++ok;
    clean += plan->check.ok() ? 1 : 0;
    const double ms = plan->total_time_s * 1e3;
    sum_ms += ms;
    max_ms = std::max(max_ms, ms);
    sum_alloc_ms += plan->allocation.time_s * 1e3;
    sum_path_ms += plan->paths.time_s * 1e3;
    sum_makespan += plan->makespan();
    sum_alloc += plan->allocation.makespan_steps;
    sum_alg1 += plan->improvement.start_makespan_steps;
    sum_conf += plan->paths.conflicts_resolved;
  }
  const double n = std::max(1, ok);
  std::printf("| %s | %d/%d | %d/%d | %.1f (%.1f; Alg. 1 alone %.1f) | %.1f | %.2f / %.2f | %.1f | %.1f |\n",
              map_name.c_str(), ok, runs, clean, ok, sum_makespan / n, sum_alloc / n, sum_alg1 / n, sum_conf / n, sum_alloc_ms / n, sum_path_ms / n, sum_ms / n,
              max_ms);
}

}  // namespace

int main(int argc, char** argv) {
  int placements = 50;
  int scale_runs = 10;
  bool exact = true;
  for (int i = 1; i < argc; ++i) {
    if (std::strcmp(argv[i], "--placements") == 0 && i + 1 < argc) placements = std::atoi(argv[++i]);
    else if (std::strcmp(argv[i], "--scale-runs") == 0 && i + 1 < argc) scale_runs = std::atoi(argv[++i]);
    else if (std::strcmp(argv[i], "--skip-exact") == 0) exact = false;
    else {
      std::fprintf(stderr, "usage: gmtpa_bench [--placements N] [--scale-runs N] [--skip-exact]\n");
      return 2;
    }
  }
  paperExperiment(placements, exact);
  std::printf("## Scale: 20 vehicles, 60 tasks, greedy + improvement, %d random placements per map\n\n", scale_runs);
  std::printf("| map | planned | conflict-free | makespan (alloc. estimate) | conflicts resolved | alloc / paths (ms) | "
              "mean total (ms) | max total (ms) |\n|---|---|---|---|---|---|---|---|\n");
  scaleRun("random-64-64-20.map", scale_runs);
  scaleRun("room-32-32-4.map", scale_runs);
  return 0;
}
