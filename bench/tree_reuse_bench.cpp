// RRT* tree reuse on replanning (planning.rrt_tree_reuse), with and without, in one process on
// identical problems: the same seeds, the same first plan, the same obstacle updates.
//
// Scenario (the embedded default terrain, the seed-003 vehicle at V_ref = 50 m/s): the route
// crosses the map west to east round a fixed cylinder in its middle (a fifth of the map across),
// so the first leg's RRT* grows a real tree. An event u of a seed: the flight is planned (the
// pipeline's replanning options, the seed's first plan, the same in every config), then at
// t_u = 10 + 15 u s a fixed cylinder of 300 m radius appears on the first trajectory 30 s ahead
// (shifted sideways by an offset drawn from the seed and u), and FlightReplanner::step(t_u) runs
// the replanning cycle that answers it. Every config answers the very same event, so latencies
// and lengths pair up; with tree reuse the replan grows the first plan's tree re-rooted at the
// takeover point.
//
// Reported per config: the cycle's latency in wall and thread processor time, how many events got
// a new plan (and how many of those grew the kept tree), held, or failed, and for the events both
// it and its twin (the same deadline, the other tree reuse setting) answered with a new plan the
// mean length (km) of the new trajectory from t_u to the goal (sampled every 50 ms); collisions of those trajectories with the cylinders or the terrain
// (checked every 50 ms, grown by the vehicle radius) as a safety check.
//
// Usage: tree_reuse_bench [--seeds N] [--first-seed S] [--config deadline|no-deadline|both]
// "deadline" is the pipeline's defaults (replan_budget_ms 12); "no deadline" sets it to 0, so the
// attempts end on their iteration budgets (replanning.leg_max_iterations = 400): the work itself.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <ctime>
#include <limits>
#include <optional>
#include <random>
#include <string>
#include <vector>

#include "bench/support/bench_stats.hpp"
#include "bench/support/bench_progress.hpp"
#include "service/flight_replanner.hpp"
#include "service/mission_pipeline.hpp"
#include "service/moving_obstacle_scenario.hpp"
#include "terrain/terrain_world.hpp"

namespace {

using skyroute::bench::Sample;
using skyroute::bench::quantile;
using skyroute::bench::threadCpuMs;

using namespace skyroute;



Obstacle fixedCylinder(std::uint64_t id, const Eigen::Vector3d& centre_m, double radius_m) {
  Obstacle o;
  o.id = id;
  o.shape = ObstacleShape::kCylinder;
  o.size_m = Eigen::Vector3d(radius_m, 0.0, 20000.0);  // too tall to climb over
  o.center_m = centre_m;
  return o;
}

constexpr double kFirstEventS = 10.0;
constexpr double kEventEveryS = 15.0;
constexpr double kAheadS = 30.0;
constexpr double kRadiusM = 300.0;
constexpr double kSideM = 150.0;  // the cylinder's sideways offset at most

struct Config {
  std::string name;
  ReplanOptions options;
};

// One config's answer to one event.
struct Answer {
  bool replanned = false, holding = false, failed = false;
  double wall_ms = 0.0, cpu_ms = 0.0;
  std::size_t reused_nodes = 0;
  double length_m = NAN;  // the new trajectory from the event to the goal
  // The new plan's first leg, when RRT* searched it (not a retimed stretch): re-rooting plus
  // search time, samples drawn, and the sample that found its first path (0: the kept tree
  // reached the goal's neighbourhood already).
  bool searched = false;
  double search_ms = 0.0;
  double samples = 0.0, first_path_sample = 0.0;
  int collisions = 0;
};

}  // namespace

int main(int argc, char** argv) {
  int seeds = 3;
  std::uint64_t first_seed = 1;
  std::string which = "both";
  for (int i = 1; i + 1 < argc; i += 2) {
    const std::string a = argv[i];
    if (a == "--seeds") seeds = std::atoi(argv[i + 1]);
    else if (a == "--first-seed") first_seed = std::strtoull(argv[i + 1], nullptr, 10);
    else if (a == "--config") which = argv[i + 1];
    else {
      std::fprintf(stderr, "unknown option %s\n", a.c_str());
      return 2;
    }
  }
  CollisionWorldOptions world_options = seed003ScenarioWorldOptions();
  world_options.ceiling_m = 12000.0;
  const std::string dem = std::string(SKYROUTE_DATA_DIR) + "/default_terrain.tif";
  auto loaded = loadTerrainWorld(dem, world_options);
  if (!loaded.ok()) {
    std::fprintf(stderr, "%s: %s\n", dem.c_str(), loaded.error().describe().c_str());
    return 1;
  }
  const Heightfield& terrain = *loaded->heightfield;
  const std::shared_ptr<CollisionWorld>& world = loaded->collision;
  const Eigen::AlignedBox2d box = terrain.boundsEn();
  auto above = [&](double e, double n) { return Eigen::Vector3d(e, n, terrain.heightAt(e, n) + 300.0); };
  const double w = box.sizes().x(), north = box.center().y();
  const std::vector<Eigen::Vector3d> points{above(box.min().x() + 0.05 * w, north), above(box.max().x() - 0.05 * w, north)};
  const Obstacle detour = fixedCylinder(1, Eigen::Vector3d(box.center().x(), north, 0.0), 0.1 * w);
  const VehicleLimits limits = seed003ScenarioLimits();

  std::vector<Config> configs;
  const PipelineOptions pipeline;
  for (bool deadline : {true, false}) {
    if (which != "both" && which != (deadline ? "deadline" : "no-deadline")) continue;
    ReplanOptions options = pipelineReplanOptions(pipeline, pipeline.budget, pipeline.seed);
    if (!deadline) options.replan_budget_ms = 0.0;
    for (bool reuse : {false, true}) {
      options.rrt_tree_reuse = reuse;
      configs.push_back({std::string(deadline ? "deadline" : "no deadline") + (reuse ? " + tree reuse" : ""), options});
    }
  }
  if (configs.empty()) {
    std::fprintf(stderr, "unknown config %s\n", which.c_str());
    return 2;
  }

  // answers[c][e]: config c's answer to event e (events of every seed, in order).
  std::vector<std::vector<Answer>> answers(configs.size());
  skyroute::bench::BenchProgress progress("tree_reuse_bench", static_cast<std::size_t>(seeds));
  for (int k = 0; k < seeds; ++k) {
    const std::uint64_t seed = first_seed + static_cast<std::uint64_t>(k);
    for (int u = 0;; ++u) {
      const double t_u = kFirstEventS + kEventEveryS * u;
      bool past_end = false;
      for (std::size_t c = 0; c < configs.size() && !past_end; ++c) {
        for (const Obstacle& o : world->obstacles()) world->removeObstacle(o.id);  // the event before's
        world->upsertObstacle(detour);
        ReplanOptions options = configs[c].options;
        options.route.seed = seed;
        auto started = FlightReplanner::start(world, points, limits, options, 0.0);
        if (!started.ok()) {
          std::fprintf(stderr, "seed %llu: start failed: %s\n", static_cast<unsigned long long>(seed),
                       started.error().describe().c_str());
          past_end = true;
          break;
        }
        FlightReplanner& r = **started;
        if (t_u + kAheadS > r.arrivalWorldS() - 10.0) {
          past_end = true;
          break;
        }
        const TrajectoryState at = r.stateAt(t_u + kAheadS);
        Eigen::Vector3d v = at.velocity_mps;
        v.z() = 0.0;
        const Eigen::Vector3d across = v.norm() > 1e-6 ? Eigen::Vector3d(Eigen::Vector3d(-v.y(), v.x(), 0.0) / v.norm())
                                                        : Eigen::Vector3d(Eigen::Vector3d::UnitY());
        std::mt19937_64 rng(seed * 1000 + static_cast<std::uint64_t>(u));
        const Eigen::Vector3d centre = at.position_m + std::uniform_real_distribution<double>(-kSideM, kSideM)(rng) * across;
        const Obstacle cylinder = fixedCylinder(100, Eigen::Vector3d(centre.x(), centre.y(), 0.0), kRadiusM);
        world->upsertObstacle(cylinder);

        Answer a;
        const double cpu0 = threadCpuMs();
        const auto wall0 = std::chrono::steady_clock::now();
        const ReplanStep step = r.step(t_u);
        a.wall_ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - wall0).count();
        a.cpu_ms = threadCpuMs() - cpu0;
        a.replanned = step.replanned && !step.holding;
        a.holding = step.holding;
        a.failed = !step.replanned && !step.holding;
        a.reused_nodes = step.reused_tree_nodes;
        if (a.replanned && r.route().legs.front().rrt.tree_size > 0) {
          const RouteLeg& leg = r.route().legs.front();
          a.searched = true;
          a.search_ms = leg.tree_reuse_ms + leg.rrt.time_s * 1e3;
          a.samples = static_cast<double>(leg.rrt.iterations);
          a.first_path_sample = static_cast<double>(leg.rrt.first_solution_iteration);
        }
        if (a.replanned) {
          a.length_m = 0.0;
          for (double t = t_u; t < r.arrivalWorldS(); t += 0.05) {
            const Eigen::Vector3d p = r.stateAt(t).position_m;
            a.length_m += (r.stateAt(std::min(t + 0.05, r.arrivalWorldS())).position_m - p).norm();
            const bool hit = p.z() - terrain.heightAt(p.x(), p.y()) < world_options.min_clearance_m - 0.5 ||
                             detour.contains(p, t, world_options.vehicle_radius_m) ||
                             cylinder.contains(p, t, world_options.vehicle_radius_m);
            a.collisions += hit ? 1 : 0;
          }
        }
        answers[c].push_back(a);
      }
      if (past_end) {
        // Drop the event's partial answers: every config must answer the same events.
        std::size_t complete = answers.front().size();
        for (const auto& per_config : answers) complete = std::min(complete, per_config.size());
        for (auto& per_config : answers) per_config.resize(complete);
        break;
      }
    }
    progress.done("seed " + std::to_string(seed));
  }

  const std::size_t events = answers.front().size();
  std::printf("%zu events (%d seeds from %llu), each answered by every config\n\n", events, seeds,
              static_cast<unsigned long long>(first_seed));
  std::printf("| config | new plan | of which from the kept tree | held | failed | wall p50 ms | wall p90 | wall p99 | wall max | cpu p50 ms | cpu p99 | reused nodes mean | length km mean (paired) | collisions |\n");
  std::printf("|---|---|---|---|---|---|---|---|---|---|---|---|---|---|\n");
  std::vector<std::string> search_rows;
  for (std::size_t c = 0; c < configs.size(); ++c) {
    // Events that both this config and its twin (the same deadline, the other tree reuse setting)
    // answered with a new plan: their lengths compare like with like.
    std::vector<bool> paired(events);
    for (std::size_t e = 0; e < events; ++e) paired[e] = answers[c][e].replanned && answers[c ^ 1][e].replanned;
    const auto n_paired = static_cast<std::size_t>(std::count(paired.begin(), paired.end(), true));
    std::vector<double> wall, cpu;
    int replanned = 0, reusing = 0, held = 0, failed = 0, collisions = 0;
    double reused = 0.0, length = 0.0;
    for (std::size_t e = 0; e < events; ++e) {
      const Answer& a = answers[c][e];
      wall.push_back(a.wall_ms);
      cpu.push_back(a.cpu_ms);
      replanned += a.replanned ? 1 : 0;
      reusing += a.reused_nodes > 0 ? 1 : 0;
      held += a.holding ? 1 : 0;
      failed += a.failed ? 1 : 0;
      collisions += a.collisions;
      reused += static_cast<double>(a.reused_nodes);
      if (paired[e]) length += a.length_m;
    }
    std::printf("| %s | %d/%zu | %d | %d | %d | %.1f | %.1f | %.1f | %.1f | %.1f | %.1f | %.0f | %.3f (%zu) | %d |\n",
                configs[c].name.c_str(), replanned, events, reusing, held, failed, quantile(wall, 0.5),
                quantile(wall, 0.9), quantile(wall, 0.99), quantile(wall, 1.0), quantile(cpu, 0.5), quantile(cpu, 0.99),
                reused / std::max<double>(1.0, static_cast<double>(events)),
                n_paired ? length / static_cast<double>(n_paired) / 1e3 : NAN, n_paired, collisions);
    std::vector<double> search_ms;
    double samples = 0.0, first_path = 0.0;
    for (const Answer& a : answers[c]) {
      if (!a.searched) continue;
      search_ms.push_back(a.search_ms);
      samples += a.samples;
      first_path += a.first_path_sample;
    }
    const double n = std::max<double>(1.0, static_cast<double>(search_ms.size()));
    char line[256];
    std::snprintf(line, sizeof line, "| %s | %zu | %.2f | %.2f | %.2f | %.0f | %.0f |", configs[c].name.c_str(),
                  search_ms.size(), quantile(search_ms, 0.5), quantile(search_ms, 0.9), quantile(search_ms, 0.99),
                  samples / n, first_path / n);
    search_rows.emplace_back(line);
  }
  std::printf("\nThe new plans' first leg searched by RRT* (re-rooting included):\n\n");
  std::printf("| config | legs | search p50 ms | p90 | p99 | samples mean | first path at sample (mean) |\n");
  std::printf("|---|---|---|---|---|---|---|\n");
  for (const std::string& row : search_rows) std::printf("%s\n", row.c_str());
  return 0;
}
