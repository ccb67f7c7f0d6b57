// RRT* tree reuse on replanning (planning.rrt_tree_reuse), with and without, in one process: the
// same seeds, the same first plan and the same rule for the obstacle updates.
//
// Scenario (the embedded default terrain, the seed-003 vehicle at V_ref = 50 m/s): the route
// crosses the map west to east round a fixed cylinder in its middle (a fifth of the map across),
// so the first leg's RRT* grows a real tree. While the vehicle flies, every 8 s a new fixed
// cylinder (300 m radius) appears on the trajectory in force 30 s ahead of the vehicle (so every
// update meets it), shifted sideways by a seeded offset, and the one before it goes;
// FlightReplanner::step runs every t_ref = 0.1 s as in the daemon (the pipeline's replanning
// options). The same seeded offsets in both runs: the updates are the same until the runs' trajectories differ,
// and then the same rule on each run's own trajectory. No new cylinder while the vehicle holds or
// when the meeting point is less than 500 m ahead (a slow vehicle).
//
// Reported per config: replan latency (cycles that planned: the trajectory ahead meets an
// obstacle, or the vehicle holds and plans on from the hold) in wall
// and thread processor time, adopted replans and how many grew the kept tree, the flown length
// (km, summed every 10 ms) and arrival time, and collisions (every 10 ms, with the obstacle in
// force, grown by the vehicle radius) as a safety check.
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

#include "bench/support/bench_progress.hpp"
#include "service/flight_replanner.hpp"
#include "service/mission_pipeline.hpp"
#include "service/moving_obstacle_scenario.hpp"
#include "terrain/terrain_world.hpp"

namespace {

using namespace skyroute;

double threadCpuMs() {
  timespec ts{};
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts);
  return ts.tv_sec * 1e3 + ts.tv_nsec * 1e-6;
}

double quantile(std::vector<double> v, double q) {
  if (v.empty()) return NAN;
  std::sort(v.begin(), v.end());
  const auto rank = static_cast<std::size_t>(std::ceil(q * static_cast<double>(v.size())));
  return v[std::clamp<std::size_t>(rank, 1, v.size()) - 1];
}

Obstacle fixedCylinder(std::uint64_t id, const Eigen::Vector3d& centre_m, double radius_m) {
  Obstacle o;
  o.id = id;
  o.shape = ObstacleShape::kCylinder;
  o.size_m = Eigen::Vector3d(radius_m, 0.0, 20000.0);  // too tall to climb over
  o.center_m = centre_m;
  return o;
}

// Every kUpdateEveryS from kFirstUpdateS, a cylinder of kRadiusM appears on the trajectory in
// force kAheadS ahead (shifted sideways by a seeded offset) and the one before goes.
constexpr double kFirstUpdateS = 8.0;
constexpr double kUpdateEveryS = 8.0;
constexpr double kAheadS = 30.0;
constexpr double kRadiusM = 300.0;
constexpr double kMinAheadM = 500.0;  // the meeting point at least this far from the vehicle

struct Config {
  std::string name;
  ReplanOptions options;
};

struct Totals {
  std::vector<double> wall_ms, cpu_ms;
  int seeds = 0, arrived = 0, collisions = 0, adopted = 0, reusing = 0, failed = 0;
  double flown_m = 0.0, arrival_s = 0.0;
  std::size_t reused_nodes = 0;
};

}  // namespace

int main(int argc, char** argv) {
  int seeds = 5;
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
  const Eigen::AlignedBox2d box = terrain.boundsEn();
  auto above = [&](double e, double n) { return Eigen::Vector3d(e, n, terrain.heightAt(e, n) + 300.0); };
  const double w = box.sizes().x(), north = box.center().y();
  const std::vector<Eigen::Vector3d> points{above(box.min().x() + 0.05 * w, north), above(box.max().x() - 0.05 * w, north)};
  const Obstacle detour = fixedCylinder(1, Eigen::Vector3d(box.center().x(), north, 0.0), 0.1 * w);
  const VehicleLimits limits = seed003ScenarioLimits();

  std::vector<Config> base;
  const PipelineOptions pipeline;
  for (bool deadline : {true, false}) {
    if (which != "both" && which != (deadline ? "deadline" : "no-deadline")) continue;
    ReplanOptions options = pipelineReplanOptions(pipeline, pipeline.budget, pipeline.seed);
    if (!deadline) options.replan_budget_ms = 0.0;
    base.push_back({deadline ? "deadline" : "no deadline", options});
  }
  if (base.empty()) {
    std::fprintf(stderr, "unknown config %s\n", which.c_str());
    return 2;
  }
  std::vector<Config> configs;
  for (const Config& c : base) {
    configs.push_back(c);
    Config reusing = c;
    reusing.name += " + tree reuse";
    reusing.options.rrt_tree_reuse = true;
    configs.push_back(reusing);
  }

  std::printf("| config | seed | arrived | arrival s | flown km | collisions | replan cycles | adopted | from the kept tree | reused nodes | replan p50 ms | replan max ms |\n");
  std::printf("|---|---|---|---|---|---|---|---|---|---|---|---|\n");
  std::vector<Totals> totals(configs.size());
  skyroute::bench::BenchProgress progress("tree_reuse_bench", configs.size() * static_cast<std::size_t>(seeds));
  for (int k = 0; k < seeds; ++k) {
    const std::uint64_t seed = first_seed + static_cast<std::uint64_t>(k);
    for (std::size_t c = 0; c < configs.size(); ++c) {
      ReplanOptions options = configs[c].options;
      options.route.seed = seed;
      const std::shared_ptr<CollisionWorld>& world = loaded->collision;
      for (const Obstacle& o : world->obstacles()) world->removeObstacle(o.id);  // the run before's
      world->upsertObstacle(detour);
      auto started = FlightReplanner::start(world, points, limits, options, 0.0);
      if (!started.ok()) {
        std::printf("| %s | %llu | start failed: %s |\n", configs[c].name.c_str(), static_cast<unsigned long long>(seed),
                    started.error().describe().c_str());
        continue;
      }
      FlightReplanner& r = **started;
      Totals& tot = totals[c];
      ++tot.seeds;
      std::vector<double> seed_wall;
      int cycles = 0, adopted = 0, reusing = 0, collisions = 0;
      std::size_t reused = 0;
      double flown_m = 0.0;
      // The same offsets in every config of this seed.
      std::mt19937_64 rng(seed);
      std::uniform_real_distribution<double> side(-150.0, 150.0);
      std::optional<Obstacle> in_force;
      double next_update_s = kFirstUpdateS;
      std::uint64_t next_id = 100;
      double t = 0.0;
      for (; t < 1200.0 && !r.finished(t); t += options.period_s) {
        if (t >= next_update_s - 1e-9) {
          next_update_s += kUpdateEveryS;
          const double meet_s = t + kAheadS;
          if (in_force) world->removeObstacle(in_force->id);
          in_force.reset();
          const TrajectoryState at = r.stateAt(meet_s);
          // Only ahead of a vehicle under way: a cylinder dropped on a slow or holding vehicle
          // would sit where it is (a test of the hold, not of replanning).
          const bool under_way = (at.position_m - r.stateAt(t).position_m).norm() > kMinAheadM;
          if (meet_s < r.arrivalWorldS() - 10.0 && !r.holding() && under_way) {
            Eigen::Vector3d v = at.velocity_mps;
            v.z() = 0.0;
            const Eigen::Vector3d across = v.norm() > 1e-6 ? Eigen::Vector3d(Eigen::Vector3d(-v.y(), v.x(), 0.0) / v.norm())
                                                            : Eigen::Vector3d(Eigen::Vector3d::UnitY());
            const Eigen::Vector3d centre = at.position_m + side(rng) * across;
            in_force = fixedCylinder(next_id++, Eigen::Vector3d(centre.x(), centre.y(), 0.0), kRadiusM);
            world->upsertObstacle(*in_force);
          }
        }
        const double cpu0 = threadCpuMs();
        const auto wall0 = std::chrono::steady_clock::now();
        const ReplanStep step = r.step(t);
        const double wall = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - wall0).count();
        const double cpu = threadCpuMs() - cpu0;
        if (step.conflict_ahead || step.replanned || step.failure) {  // a cycle that planned
          ++cycles;
          tot.wall_ms.push_back(wall);
          tot.cpu_ms.push_back(cpu);
          seed_wall.push_back(wall);
          if (step.failure) ++tot.failed;
        }
        if (step.replanned) {
          ++adopted;
          if (step.reused_tree_nodes > 0) ++reusing;
          reused += step.reused_tree_nodes;
        }
        for (double ts = t; ts < t + options.period_s - 1e-9; ts += 0.01) {
          const Eigen::Vector3d p = r.stateAt(ts).position_m;
          flown_m += (r.stateAt(ts + 0.01).position_m - p).norm();
          bool hit = p.z() - terrain.heightAt(p.x(), p.y()) < world_options.min_clearance_m - 0.5;
          hit = hit || detour.contains(p, ts, world_options.vehicle_radius_m);
          hit = hit || (in_force && in_force->contains(p, ts, world_options.vehicle_radius_m));
          collisions += hit ? 1 : 0;
        }
      }
      const bool arrived = r.finished(t);
      tot.arrived += arrived ? 1 : 0;
      tot.collisions += collisions;
      tot.adopted += adopted;
      tot.reusing += reusing;
      tot.reused_nodes += reused;
      tot.flown_m += flown_m;
      tot.arrival_s += r.arrivalWorldS();
      std::printf("| %s | %llu | %s | %.1f | %.3f | %d | %d | %d | %d | %zu | %.2f | %.2f |\n", configs[c].name.c_str(),
                  static_cast<unsigned long long>(seed), arrived ? "yes" : "NO", r.arrivalWorldS(), flown_m / 1e3,
                  collisions, cycles, adopted, reusing, reused, quantile(seed_wall, 0.5), quantile(seed_wall, 1.0));
      std::fflush(stdout);
      progress.done(configs[c].name + " seed " + std::to_string(seed));
    }
  }

  std::printf("\n| config | replan cycles | wall p50 ms | wall p90 | wall p99 | wall max | cpu p50 ms | cpu p99 | adopted | from the kept tree | failed cycles | arrived | collisions | flown km mean | arrival s mean |\n");
  std::printf("|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|\n");
  for (std::size_t c = 0; c < configs.size(); ++c) {
    const Totals& t = totals[c];
    const double n = std::max(1, t.seeds);
    std::printf("| %s | %zu | %.2f | %.2f | %.2f | %.2f | %.2f | %.2f | %d | %d | %d | %d/%d | %d | %.3f | %.1f |\n",
                configs[c].name.c_str(), t.wall_ms.size(), quantile(t.wall_ms, 0.5), quantile(t.wall_ms, 0.9),
                quantile(t.wall_ms, 0.99), quantile(t.wall_ms, 1.0), quantile(t.cpu_ms, 0.5), quantile(t.cpu_ms, 0.99),
                t.adopted, t.reusing, t.failed, t.arrived, t.seeds, t.collisions, t.flown_m / n / 1e3, t.arrival_s / n);
  }
  return 0;
}
