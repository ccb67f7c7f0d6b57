// What a replan cut short by its budget does to the seed-003 flight (Table 1 on N44W072, the
// scenario of tests/service/flight_replanner_test.cpp: V_ref = 50 m/s, a step every t_ref = 0.1 s,
// the test's options). A wall-clock cut depends on the machine's load; --cut-attempts cuts every
// replan after that many attempts instead (ReplanOptions::replan_budget_attempts), the way the
// deadline does, so a run is reproducible.
// Each run prints: arrival, replans adopted, failed replans by kind, holds adopted, the minimum
// separation from the obstacles (CollisionWorld::obstacleDistance, beyond the vehicle's radius),
// when and where it happens, and whether the vehicle was holding then.
//
// Usage: budget_cut_bench [--seeds N] [--first-seed S] [--budget-ms MS] [--cut-attempts N]
//                         [--timeline FROM_S TO_S]
// (MS: replan_budget_ms, default 0 = none; N: attempts per replan, default 0 = none; the timeline
// prints every cycle's outcome between FROM_S and TO_S of the first seed)
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <limits>
#include <map>
#include <string>

#include "bench/seed003_world.hpp"
#include "service/flight_replanner.hpp"
#include "service/moving_obstacle_scenario.hpp"

namespace {

using namespace skyroute;

// The test's options (iteration budgets for the first plan, the scenario's wide corridor).
ReplanOptions scenarioOptions(std::uint64_t seed, double budget_ms, int cut_attempts) {
  ReplanOptions options;
  options.route.seed = seed;
  options.route.leg_budget_ms = 0.0;
  options.route.leg_max_iterations = 3000;
  options.route.corridor_margin_m = 4000.0;
  options.replan_budget_ms = budget_ms;
  options.replan_budget_attempts = cut_attempts;
  return options;
}

}  // namespace

int main(int argc, char** argv) {
  int seeds = 1;
  std::uint64_t first_seed = 7;
  double budget_ms = 0.0;
  int cut_attempts = 0;
  double timeline_from_s = -1.0, timeline_to_s = -1.0;
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    const bool has_value = i + 1 < argc;
    if (a == "--seeds" && has_value) seeds = std::atoi(argv[++i]);
    else if (a == "--first-seed" && has_value) first_seed = std::strtoull(argv[++i], nullptr, 10);
    else if (a == "--budget-ms" && has_value) budget_ms = std::atof(argv[++i]);
    else if (a == "--cut-attempts" && has_value) cut_attempts = std::atoi(argv[++i]);
    else if (a == "--timeline" && i + 2 < argc) {
      timeline_from_s = std::atof(argv[++i]);
      timeline_to_s = std::atof(argv[++i]);
    } else {
      std::fprintf(stderr, "unknown or incomplete option %s\n", a.c_str());
      return 2;
    }
  }
  const CollisionWorldOptions world_options = seed003ScenarioWorldOptions();
  auto flight = skyroute::bench::loadSeed003Flight();
  if (!flight) return 1;
  TerrainWorld* world = &flight->world;
  const MovingObstacleScenario& scenario = flight->scenario;
  const VehicleLimits limits = seed003ScenarioLimits();

  std::printf("budget %.1f ms, cut after %d attempts\n", budget_ms, cut_attempts);
  std::printf("| seed | arrived | arrival s | replans | failed | holds | collisions | min sep m | at s | holding then | min sep not holding m | "
              "slowest cycle ms | nearest obstacle | failures by kind |\n");
  std::printf("|---|---|---|---|---|---|---|---|---|---|---|---|---|---|\n");
  for (int k = 0; k < seeds; ++k) {
    const std::uint64_t seed = first_seed + static_cast<std::uint64_t>(k);
    const ReplanOptions options = scenarioOptions(seed, budget_ms, cut_attempts);
    auto started = FlightReplanner::start(world->collision, {scenario.start_m, scenario.goal_m}, limits, options, 0.0);
    if (!started.ok()) {
      std::printf("| %llu | start failed: %s |\n", static_cast<unsigned long long>(seed), started.error().describe().c_str());
      continue;
    }
    FlightReplanner& r = **started;
    int replans = 0, failed = 0, holds = 0, collisions = 0;
    double max_cycle_ms = 0.0;  // wall time of the slowest step
    std::map<std::string, int> kinds;
    double min_sep_m = std::numeric_limits<double>::infinity(), min_sep_s = 0.0;
    double moving_sep_m = std::numeric_limits<double>::infinity();  // while no hold is in force
    bool min_sep_holding = false;
    std::uint64_t nearest_id = 0;
    double t = 0.0;
    for (; t < 1200.0 && !r.finished(t); t += options.period_s) {
      const auto cycle_started = std::chrono::steady_clock::now();
      const ReplanStep step = r.step(t);
      max_cycle_ms = std::max(max_cycle_ms,
                              std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - cycle_started).count());
      replans += step.replanned ? 1 : 0;
      holds += step.holding ? 1 : 0;
      if (step.failure) {
        ++failed;
        std::string kind = step.failure->describe();
        if (kind.size() > 70) kind.resize(70);
        ++kinds[kind];
      }
      if (k == 0 && t >= timeline_from_s && t <= timeline_to_s) {
        std::printf("  t=%.1f rev %u conflict=%d replanned=%d local=%d holding=%d sep=%.0f %s\n", t, r.revision(),
                    step.conflict_ahead, step.replanned, step.local, r.holding(),
                    world->collision->obstacleDistance(r.stateAt(t).position_m, t),
                    step.failure ? step.failure->describe().c_str() : "");
      }
      for (double s = t; s < t + options.period_s; s += 0.01) {
        const Eigen::Vector3d p = r.stateAt(s).position_m;
        for (const Obstacle& o : scenario.obstacles) {
          if (o.contains(p, s, world_options.vehicle_radius_m)) ++collisions;
        }
        const double d = world->collision->obstacleDistance(p, s);
        if (!r.holding()) moving_sep_m = std::min(moving_sep_m, d);
        if (d < min_sep_m) {
          min_sep_m = d;
          min_sep_s = s;
          min_sep_holding = r.holding();
          double best = std::numeric_limits<double>::infinity();
          for (const Obstacle& o : scenario.obstacles) {
            const double c = (o.centerAt(s) - p).norm();
            if (c < best) {
              best = c;
              nearest_id = o.id;
            }
          }
        }
      }
    }
    std::string by_kind;
    for (const auto& [kind, n] : kinds) by_kind += std::to_string(n) + " x " + kind + "; ";
    std::printf("| %llu | %s | %.1f | %d | %d | %d | %d | %.1f | %.1f | %s | %.1f | %.1f | %llu | %s |\n",
                static_cast<unsigned long long>(seed), r.finished(t) ? "yes" : "NO", r.arrivalWorldS(), replans, failed,
                holds, collisions, min_sep_m, min_sep_s, min_sep_holding ? "yes" : "no", moving_sep_m, max_cycle_ms,
                static_cast<unsigned long long>(nearest_id), by_kind.c_str());
    std::fflush(stdout);
  }
  return 0;
}
