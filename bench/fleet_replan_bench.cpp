// Fleet replan latency (fleet_replanner.hpp) without DDS or the engine's scheduling: the 5-vehicle,
// 15-task fleet of tests/service/fleet_replan_test.cpp on the embedded terrain, planned once; each
// round a fresh replanner of that plan meets three columns (every altitude of the band, radius
// 120 m, 8-14 m/s) aimed from random headings at three random vehicles, at random times 60-600 s
// after the update, and one step of the replanner is timed (wall clock, budget included). The
// revisions are then checked by sampling (every 0.05 s, from the update to each vehicle's end)
// against the columns' actual motion: "hits" counts vehicles found inside a column (grown by the
// vehicle radius). A step the budget cut short is followed by another (0.1 s later), as the engine
// does; "first step" is the first one's latency, "all steps" the sum. "unresolved": vehicles still
// meeting a column after the last step (no candidate passed). Seeded: the same --seed gives the
// same columns.
// Usage: fleet_replan_bench [--rounds N] [--seed S] [--budget-s B]
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <random>
#include <set>
#include <string>

#include <spdlog/spdlog.h>

#include "bench/support/bench_stats.hpp"
#include "service/fleet_replanner.hpp"
#include "service/shipped_data.hpp"

namespace {

using namespace skyroute;

MissionPointData above(const Heightfield& terrain, double e, double n, double agl_m) {
  return MissionPointData::enu(Eigen::Vector3d(e, n, terrain.heightAt(e, n) + agl_m));
}

}  // namespace

int main(int argc, char** argv) {
  int rounds = 30;
  std::uint64_t seed = 1;
  double budget_s = 0.5;
  for (int i = 1; i < argc; ++i) {
    if (!std::strcmp(argv[i], "--rounds") && i + 1 < argc) rounds = std::atoi(argv[++i]);
    else if (!std::strcmp(argv[i], "--seed") && i + 1 < argc) seed = std::strtoull(argv[++i], nullptr, 10);
    else if (!std::strcmp(argv[i], "--budget-s") && i + 1 < argc) budget_s = std::atof(argv[++i]);
  }
  spdlog::set_level(spdlog::level::warn);
  auto path = defaultTerrainPath(argv[0]);
  if (!path.ok()) return std::fprintf(stderr, "%s\n", path.error().describe().c_str()), 1;
  auto world = WorldModel::load(*path, WorldModelOptions{});
  if (!world.ok()) return std::fprintf(stderr, "%s\n", world.error().describe().c_str()), 1;
  const Heightfield& terrain = (*world)->terrain();

  FleetRequestData r;
  r.request_id = "bench";
  r.vehicle_ids = {"a", "b", "c", "d", "e"};
  r.begins = {above(terrain, -4000, -4000, 100), above(terrain, 4000, -4000, 100), above(terrain, -4000, 4000, 100),
              above(terrain, 4000, 4000, 100), above(terrain, 0, -4500, 100)};
  r.ends = r.begins;
  const double spots[15][2] = {{-2500, -1500}, {-1000, -3000}, {1500, -2500}, {3000, -1000}, {2500, 1500},
                               {-3000, 1000},  {-1500, 3000},  {0, 0},        {1500, 3500},  {-3500, -2500},
                               {2000, -500},   {-500, 1800},   {3500, 2800},  {-2000, 500},  {500, -1500}};
  for (const auto& s : spots) r.tasks.push_back(above(terrain, s[0], s[1], 150));
  FleetMissionOptions mission;
  mission.min_separation_m = 150.0;
  const double start_s = 1.8e9;
  const FleetPlanOutput plan = planFleetMission(r, **world, mission, static_cast<std::int64_t>(start_s * 1e9));
  if (!plan.ok()) return std::fprintf(stderr, "fleet plan failed: %s\n", plan.status.message.c_str()), 1;
  FleetReplanOptions options;
  options.budget_s = budget_s;

  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  bench::Sample latency_ms, total_latency_ms, candidates;
  int affected = 0, changed = 0, unfinished = 0, pending = 0, hits = 0, unresolved = 0;
  const double now_s = start_s + 60.0;
  for (int round = 0; round < rounds; ++round) {
    auto replanner = FleetReplanner::create(r, plan, *world, mission, options, start_s);
    if (!replanner.ok()) return std::fprintf(stderr, "%s\n", replanner.error().describe().c_str()), 1;
    std::set<std::size_t> targets;
    while (targets.size() < 3) targets.insert(static_cast<std::size_t>(unit(rng) * 5.0) % 5);
    std::vector<ObstacleUpdateData> updates;
    for (std::size_t v : targets) {
      const double in_s = 60.0 + 540.0 * unit(rng);
      const double heading = 2.0 * M_PI * unit(rng);
      const double speed = 8.0 + 6.0 * unit(rng);
      const Eigen::Vector2d velocity(speed * std::cos(heading), speed * std::sin(heading));
      const Eigen::Vector3d meet = (*replanner)->positionAt(v, now_s + in_s);
      ObstacleUpdateData u;
      u.obstacle.id = 1000 + updates.size();
      u.obstacle.shape = ObstacleShape::kCylinder;
      u.obstacle.size_m = Eigen::Vector3d(120.0, 120.0, 2500.0);
      const Eigen::Vector2d from = meet.head<2>() - velocity * in_s;
      u.obstacle.center_m = Eigen::Vector3d(from.x(), from.y(), 1000.0);
      u.constant_velocity_enu_mps = Eigen::Vector3d(velocity.x(), velocity.y(), 0.0);
      u.valid_from_utc_ns = static_cast<std::int64_t>(now_s * 1e9);
      (*world)->apply(u);
      updates.push_back(u);
    }
    // Steps as the engine runs them: another one a cycle later while the budget cut one short.
    std::set<std::size_t> met, revised;
    double total_ms = 0.0;
    int steps = 0;
    std::size_t built = 0;
    FleetReplanStep step;
    do {
      const auto t0 = std::chrono::steady_clock::now();
      step = (*replanner)->step(now_s + 0.1 * steps);
      const double ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
      if (steps == 0) latency_ms.add(ms);
      total_ms += ms;
      built += step.candidates;
      met.insert(step.affected.begin(), step.affected.end());
      revised.insert(step.changed.begin(), step.changed.end());
      unfinished += step.unfinished ? 1 : 0;
      ++steps;
    } while (step.unfinished && steps < 10);
    total_latency_ms.add(total_ms);
    candidates.add(static_cast<double>(built));
    affected += static_cast<int>(met.size());
    changed += static_cast<int>(revised.size());
    unresolved += static_cast<int>(step.unresolved.size());
    pending += static_cast<int>(step.pending.size());
    for (std::size_t v = 0; v < r.vehicle_ids.size(); ++v) {
      const FleetVehicleFlight& f = (*replanner)->vehicle(v);
      bool hit = false;
      for (double t = now_s; t <= f.start_world_s + f.trajectory.duration_s() && !hit; t += 0.05) {
        const Eigen::Vector3d p = (*replanner)->positionAt(v, t);
        for (const ObstacleUpdateData& u : updates) hit = hit || worldObstacle(u, 3600.0).contains(p, t, 5.0);
      }
      hits += hit ? 1 : 0;
    }
    for (ObstacleUpdateData u : updates) {
      u.remove = true;
      (*world)->apply(u);
    }
  }
  std::printf("fleet replan, 5 vehicles / 15 tasks, 3 crossing columns, %d rounds, seed %llu, budget %.2f s\n", rounds,
              static_cast<unsigned long long>(seed), budget_s);
  std::printf("| first step p50 ms | p99 ms | all steps p50 ms | p99 ms | candidates mean | affected | revised | "
              "budget cuts | unresolved | pending | hits |\n");
  std::printf("|---|---|---|---|---|---|---|---|---|---|---|\n");
  std::printf("| %.0f | %.0f | %.0f | %.0f | %.1f | %d | %d | %d | %d | %d | %d |\n", bench::quantile(latency_ms.v, 0.5),
              bench::quantile(latency_ms.v, 0.99), bench::quantile(total_latency_ms.v, 0.5),
              bench::quantile(total_latency_ms.v, 0.99), candidates.mean(), affected, changed, unfinished, unresolved,
              pending, hits);
  return 0;
}
