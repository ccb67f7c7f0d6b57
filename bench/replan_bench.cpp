// Replanning latency in the seed-003 moving-obstacle scenario (Table 1 on N44W072): the vehicle
// flies at V_ref = 50 m/s and FlightReplanner::step runs every t_ref = 0.1 s, as in
// tests/service/flight_replanner_test.cpp. Every cycle is timed in wall time and in the thread's
// processor time (the machine is shared and loaded: processor time is the cost of the work, wall
// time is what the vehicle would wait). Cycles are split into
//   - replans: the trajectory ahead meets an obstacle, so a new one is planned (latency from the
//     obstacle update to the new trajectory, whether or not it is adopted),
//   - check-only cycles: the trajectory ahead is clear, only the conflict check runs.
// Each seed also reports arrival, collisions (independent 10 ms check) and minimum separation.
//
// The flight is planned and replanned as the daemon does it: the mission pipeline's replanning
// options for the plan's seed and default budget (pipelineReplanOptions), the first legs by the
// registry's default leg planner (legPathPlanner), then FlightReplanner::step every cycle. Only
// the scenario's corridor is wider (the obstacles are kilometres across).
//
// Usage: replan_bench [--seeds N] [--first-seed S] [--config NAME] [--budget-ms MS]
//                     [--replan-iterations N] [--max-commit-s S] [--replan-accel-fraction F]
//                     [--tree-reuse off|on|both]
// (NAME: deadline | no-deadline | both; MS: replan_budget_ms, default the pipeline's; N: RRT*
// iterations per leg when replanning, default the pipeline's, 0 = the first plan's)
// "deadline" is the pipeline's defaults (a wall-clock budget per replan); "no deadline" sets
// replan_budget_ms = 0, so attempts end only on their iteration budgets (reproducible, and what
// the work costs when nothing cuts it short).
// --tree-reuse (default off) runs each config without and/or with ReplanOptions::rrt_tree_reuse
// (planning.rrt_tree_reuse): the same seeds and the same obstacles, in one process, so the
// latency rows and the flown length (km, summed every 10 ms) compare the two directly.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <ctime>
#include <limits>
#include <string>
#include <vector>

#include "bench/support/bench_stats.hpp"
#include "bench/seed003_world.hpp"
#include "bench/support/bench_progress.hpp"
#include "service/flight_replanner.hpp"
#include "service/mission_pipeline.hpp"
#include "service/planner_registry.hpp"
#include "service/moving_obstacle_scenario.hpp"
#include "terrain/terrain_world.hpp"

namespace {

using skyroute::bench::Sample;
using skyroute::bench::quantile;
using skyroute::bench::threadCpuMs;

using namespace skyroute;



struct Samples {
  std::vector<double> wall_ms, cpu_ms;
};

struct SeedOutcome {
  std::uint64_t seed = 0;
  bool arrived = false;
  double arrival_s = NAN;
  int collisions = 0;  // 10 ms samples inside an obstacle grown by the vehicle radius, or under the clearance
  double min_separation_m = std::numeric_limits<double>::infinity();
  int replans = 0, adopted = 0, failed = 0;
  double max_replan_wall_ms = 0.0;
  double flown_m = 0.0;               // length of the flown curve, summed every 10 ms
  std::size_t reused_tree_nodes = 0;  // over the adopted replans
};

struct Config {
  std::string name;
  ReplanOptions options;
};

// Overrides of the pipeline's replanning options from the command line (< 0: the pipeline's).
struct ReplanOverrides {
  double max_commit_s = -1.0;
  double replan_accel_fraction = -1.0;
};

ReplanOptions scenarioOptions(bool deadline, double budget_ms, long replan_iterations, const ReplanOverrides& overrides) {
  // The daemon's options for a plan (the seed is set per run), with the scenario's corridor.
  const PipelineOptions pipeline;
  ReplanOptions options = pipelineReplanOptions(pipeline, pipeline.budget, pipeline.seed);
  options.route.corridor_margin_m = 4000.0;
  if (budget_ms > 0.0) options.replan_budget_ms = budget_ms;
  if (!deadline) options.replan_budget_ms = 0.0;
  if (replan_iterations >= 0) options.replan_leg_max_iterations = static_cast<std::uint64_t>(replan_iterations);
  if (overrides.max_commit_s >= 0.0) options.max_commit_s = overrides.max_commit_s;
  if (overrides.replan_accel_fraction > 0.0) options.replan_accel_fraction = overrides.replan_accel_fraction;
  return options;
}

}  // namespace

int main(int argc, char** argv) {
  int seeds = 5;
  std::uint64_t first_seed = 1;
  std::string which = "both";
  std::string tree_reuse = "off";
  double budget_ms = 0.0;         // 0: the pipeline's default
  long replan_iterations = -1;    // < 0: the pipeline's default
  ReplanOverrides overrides;
  for (int i = 1; i + 1 < argc; i += 2) {
    const std::string a = argv[i];
    if (a == "--seeds") seeds = std::atoi(argv[i + 1]);
    else if (a == "--first-seed") first_seed = std::strtoull(argv[i + 1], nullptr, 10);
    else if (a == "--config") which = argv[i + 1];
    else if (a == "--budget-ms") budget_ms = std::atof(argv[i + 1]);
    else if (a == "--replan-iterations") replan_iterations = std::atol(argv[i + 1]);
    else if (a == "--max-commit-s") overrides.max_commit_s = std::atof(argv[i + 1]);
    else if (a == "--replan-accel-fraction") overrides.replan_accel_fraction = std::atof(argv[i + 1]);
    else if (a == "--tree-reuse") tree_reuse = argv[i + 1];
    else {
      std::fprintf(stderr, "unknown option %s\n", a.c_str());
      return 2;
    }
  }
  const CollisionWorldOptions world_options = seed003ScenarioWorldOptions();
  auto flight = skyroute::bench::loadSeed003Flight();
  if (!flight) return 1;
  TerrainWorld* world = &flight->world;
  const MovingObstacleScenario& scenario = flight->scenario;
  const VehicleLimits limits = seed003ScenarioLimits();

  // The first legs by the configuration's default planner, as the pipeline picks it.
  const PipelineOptions pipeline;
  const RoutePlannerInfo* planner = nullptr;
  if (auto unknown = findRoutePlanner(pipeline.default_planner, &planner)) {
    std::fprintf(stderr, "%s\n", unknown->describe().c_str());
    return 1;
  }
  const LegPathPlanner first_legs = legPathPlanner(planner->kind, pipeline.grid_legs);

  std::vector<Config> configs;
  if (which == "deadline" || which == "both") configs.push_back({"deadline", scenarioOptions(true, budget_ms, replan_iterations, overrides)});
  if (which == "no-deadline" || which == "both") configs.push_back({"no deadline", scenarioOptions(false, budget_ms, replan_iterations, overrides)});
  if (configs.empty()) {
    std::fprintf(stderr, "unknown config %s\n", which.c_str());
    return 2;
  }
  if (tree_reuse != "off" && tree_reuse != "on" && tree_reuse != "both") {
    std::fprintf(stderr, "unknown --tree-reuse %s (off, on or both)\n", tree_reuse.c_str());
    return 2;
  }
  {
    std::vector<Config> with_reuse;
    for (const Config& c : configs) {
      if (tree_reuse != "on") with_reuse.push_back(c);
      if (tree_reuse == "off") continue;
      Config reusing = c;
      reusing.name += " + tree reuse";
      reusing.options.rrt_tree_reuse = true;
      with_reuse.push_back(reusing);
    }
    configs = std::move(with_reuse);
  }

  std::printf("| config | seed | arrived | arrival s | collisions | min sep m | replans | adopted | failed | max replan ms | flown km | reused nodes |\n");
  std::printf("|---|---|---|---|---|---|---|---|---|---|---|---|\n");
  struct Totals {
    Samples replan, check, start;
    std::vector<SeedOutcome> outcomes;
  };
  std::vector<Totals> totals(configs.size());
  skyroute::bench::BenchProgress progress("replan_bench", configs.size() * static_cast<std::size_t>(seeds));
  for (std::size_t c = 0; c < configs.size(); ++c) {
    for (int k = 0; k < seeds; ++k) {
      ReplanOptions options = configs[c].options;
      SeedOutcome out;
      out.seed = first_seed + static_cast<std::uint64_t>(k);
      options.route.seed = out.seed;
      const double w0 = threadCpuMs();
      const auto t0 = std::chrono::steady_clock::now();
      auto started = FlightReplanner::start(world->collision, {scenario.start_m, scenario.goal_m}, limits, options, 0.0,
                                            first_legs);
      totals[c].start.cpu_ms.push_back(threadCpuMs() - w0);
      totals[c].start.wall_ms.push_back(
          std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count());
      if (!started.ok()) {
        std::printf("| %s | %llu | start failed: %s |\n", configs[c].name.c_str(),
                    static_cast<unsigned long long>(out.seed), started.error().describe().c_str());
        totals[c].outcomes.push_back(out);
        progress.done(configs[c].name + " seed " + std::to_string(out.seed));
        continue;
      }
      FlightReplanner& r = **started;
      double t = 0.0;
      for (; t < 1200.0 && !r.finished(t); t += options.period_s) {
        const double cpu0 = threadCpuMs();
        const auto wall0 = std::chrono::steady_clock::now();
        const ReplanStep step = r.step(t);
        const double wall = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - wall0).count();
        const double cpu = threadCpuMs() - cpu0;
        Samples& s = step.conflict_ahead ? totals[c].replan : totals[c].check;
        s.wall_ms.push_back(wall);
        s.cpu_ms.push_back(cpu);
        if (step.conflict_ahead) {
          ++out.replans;
          out.max_replan_wall_ms = std::max(out.max_replan_wall_ms, wall);
          if (step.replanned) ++out.adopted;
          out.reused_tree_nodes += step.reused_tree_nodes;
          if (step.failure) ++out.failed;
        }
        for (double ts = t; ts < t + options.period_s; ts += 0.01) {
          const Eigen::Vector3d p = r.stateAt(ts).position_m;
          if (ts > 0.0) out.flown_m += (p - r.stateAt(ts - 0.01).position_m).norm();
          bool hit = p.z() - world->heightfield->heightAt(p.x(), p.y()) < world_options.min_clearance_m - 0.5;
          for (const Obstacle& o : scenario.obstacles) hit = hit || o.contains(p, ts, world_options.vehicle_radius_m);
          out.collisions += hit ? 1 : 0;
          out.min_separation_m = std::min(out.min_separation_m, world->collision->obstacleDistance(p, ts));
        }
      }
      out.arrived = r.finished(t);
      out.arrival_s = r.arrivalWorldS();
      std::printf("| %s | %llu | %s | %.1f | %d | %.0f | %d | %d | %d | %.1f | %.3f | %zu |\n", configs[c].name.c_str(),
                  static_cast<unsigned long long>(out.seed), out.arrived ? "yes" : "NO", out.arrival_s, out.collisions,
                  out.min_separation_m, out.replans, out.adopted, out.failed, out.max_replan_wall_ms, out.flown_m / 1e3,
                  out.reused_tree_nodes);
      std::fflush(stdout);
      totals[c].outcomes.push_back(out);
      progress.done(configs[c].name + " seed " + std::to_string(out.seed));
    }
  }

  std::printf("\n| config | cycles | count | wall p50 | wall p90 | wall p99 | wall max | cpu p50 | cpu p90 | cpu p99 | cpu max |\n");
  std::printf("|---|---|---|---|---|---|---|---|---|---|---|\n");
  for (std::size_t c = 0; c < configs.size(); ++c) {
    auto row = [&](const char* what, const Samples& s) {
      std::printf("| %s | %s | %zu | %.2f | %.2f | %.2f | %.2f | %.2f | %.2f | %.2f | %.2f |\n", configs[c].name.c_str(),
                  what, s.wall_ms.size(), quantile(s.wall_ms, 0.5), quantile(s.wall_ms, 0.9), quantile(s.wall_ms, 0.99),
                  quantile(s.wall_ms, 1.0), quantile(s.cpu_ms, 0.5), quantile(s.cpu_ms, 0.9), quantile(s.cpu_ms, 0.99),
                  quantile(s.cpu_ms, 1.0));
    };
    row("replan", totals[c].replan);
    row("check only", totals[c].check);
    row("initial plan", totals[c].start);
  }

  std::printf("\n| config | seeds arrived | collisions | flown km mean | arrival s mean | adopted replans | reused nodes |\n");
  std::printf("|---|---|---|---|---|---|---|\n");
  for (std::size_t c = 0; c < configs.size(); ++c) {
    int arrived = 0, collisions = 0, adopted = 0;
    double flown = 0.0, arrival = 0.0;
    std::size_t reused = 0;
    for (const SeedOutcome& o : totals[c].outcomes) {
      arrived += o.arrived ? 1 : 0;
      collisions += o.collisions;
      adopted += o.adopted;
      flown += o.flown_m;
      arrival += std::isnan(o.arrival_s) ? 0.0 : o.arrival_s;
      reused += o.reused_tree_nodes;
    }
    const double n = std::max<double>(1.0, static_cast<double>(totals[c].outcomes.size()));
    std::printf("| %s | %d/%zu | %d | %.3f | %.1f | %d | %zu |\n", configs[c].name.c_str(), arrived,
                totals[c].outcomes.size(), collisions, flown / n / 1e3, arrival / n, adopted, reused);
  }
  return 0;
}
