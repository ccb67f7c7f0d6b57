// End-to-end latency over DDS with skyrouted as a separate process on loopback:
//  - request written -> its trajectory received, for 1 and 20 vehicles asking at once;
//  - obstacle update written -> the crossed vehicle's new revision received, with 1 and 20
//    vehicles flying (each update is a cylinder that sweeps across one vehicle's route and meets
//    it 10-40 s ahead, so a replan is due at once).
// With ../shared/data, the one-vehicle obstacle case also runs on N44W072 with seed 003's vehicle
// (V_ref 50 m/s) between the seed-003 scenario's start and goal. Prints p50/p90/p99/max (ms).
// Compare with Cyclone's own round trip: ddsperf ping/pong (docs/benchmarks/dds.md).
// Usage: e2e_latency_bench [--rounds N] [--config skyrouted.toml]
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <string>
#include <vector>

#include "bench/latency_scenario.hpp"
#include "bench/support/shared_data.hpp"
#include "service/dds/loopback.hpp"
#include "service/moving_obstacle_scenario.hpp"
#include "terrain/terrain_world.hpp"
#include "tests/daemon/daemon_process.hpp"
#include "tests/daemon/ground_station.hpp"

namespace {

using namespace skyroute;
using Clock = std::chrono::steady_clock;

struct Stats {
  double p50, p90, p99, max;
};

Stats stats(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  auto q = [&](double f) { return v[std::min(v.size() - 1, static_cast<std::size_t>(std::ceil(f * v.size())) - 1)]; };
  return {q(0.5), q(0.9), q(0.99), v.back()};
}

void row(const char* what, int vehicles, const std::vector<double>& ms) {
  if (ms.empty()) {
    std::printf("| %-40s | %3d | %4d | - | - | - | - |\n", what, vehicles, 0);
    return;
  }
  const Stats s = stats(ms);
  std::printf("| %-40s | %3d | %4zu | %8.1f | %8.1f | %8.1f | %8.1f |\n", what, vehicles, ms.size(), s.p50, s.p90, s.p99,
              s.max);
}

double msSince(Clock::time_point t0, Clock::time_point t1) {
  return std::chrono::duration<double, std::milli>(t1 - t0).count();
}

struct Setup {
  std::string dem;
  std::string config;  // skyrouted --config, "" = none
  std::shared_ptr<const Heightfield> terrain;
  int domain = 150;
};

struct Run {
  std::vector<double> request_ms;
  std::vector<double> obstacle_ms;
  int obstacle_misses = 0;
};

Run measure(const Setup& setup, int vehicles, int request_rounds, int obstacle_updates,
            const std::function<MissionRequestData(int vehicle, const std::string& id)>& mission_of) {
  Run run;
  std::vector<std::string> argv{SKYROUTED, "--domain", std::to_string(setup.domain), "--dem", setup.dem, "--log-level", "warn"};
  if (!setup.config.empty()) {
    argv.push_back("--config");
    argv.push_back(setup.config);
  }
  testing::ChildProcess daemon = testing::ChildProcess::spawn(argv, "bench_daemon");
  auto station = testing::Station::open(setup.domain);
  if (!station || !station->pumpUntil([&] { return station->heartbeats > 0; }, 120.0)) {
    std::fprintf(stderr, "daemon did not come up: %s\n", daemon.err().c_str());
    return run;
  }
  (void)station->requests->waitForReaders(1, 20.0);
  (void)station->trajectories->waitForWriters(1, 20.0);
  (void)station->obstacles->waitForReaders(1, 20.0);

  // Requests: every vehicle asks at once, `request_rounds` times.
  for (int round = 0; round < request_rounds; ++round) {
    std::vector<std::pair<std::string, Clock::time_point>> sent;
    for (int v = 0; v < vehicles; ++v) {
      const std::string id = "r" + std::to_string(round) + "-v" + std::to_string(v);
      const MissionRequestData m = mission_of(v, id);
      sent.emplace_back(id, Clock::now());
      (void)station->requests->write(m);
    }
    for (const auto& [id, t0] : sent) {
      constexpr std::size_t from = 0;
      const bool got = station->pumpUntil(
          [&] {
            for (std::size_t i = from; i < station->trajectory_log.size(); ++i)
              if (station->trajectory_log[i].request_id == id) return true;
            return false;
          },
          120.0);
      if (!got) continue;
      for (std::size_t i = 0; i < station->trajectory_log.size(); ++i) {
        if (station->trajectory_log[i].request_id == id && station->trajectory_log[i].revision == 0) {
          run.request_ms.push_back(msSince(t0, station->trajectory_times[i]));
          break;
        }
      }
    }
  }

  // Obstacle updates: one at a time, each crossing one vehicle's route; the previous one removed.
  std::uint64_t previous_id = 0;
  for (int u = 0; u < obstacle_updates; ++u) {
    const std::string vehicle = "uav-" + std::to_string(u % vehicles);
    const TrajectoryData* current = station->latest(vehicle);
    if (!current) break;
    const std::uint32_t revision = current->revision;
    if (previous_id != 0) {
      ObstacleUpdateData gone;
      gone.obstacle.id = previous_id;
      gone.remove = true;
      (void)station->obstacles->write(gone);
      station->pumpUntil([] { return false; }, 0.3);  // let the daemon settle
    }
    const ObstacleUpdateData update = bench::crossing(*current, utcNowNs(), 1000 + u, 15.0 + (u % 4) * 5.0);
    previous_id = update.obstacle.id;
    const std::size_t seen = station->trajectory_log.size();
    const auto t0 = Clock::now();
    (void)station->obstacles->write(update);
    bool got = station->pumpUntil(
        [&] {
          for (std::size_t i = seen; i < station->trajectory_log.size(); ++i)
            if (station->trajectory_log[i].vehicle_id == vehicle && station->trajectory_log[i].revision > revision) return true;
          return false;
        },
        5.0);
    if (!got) {
      ++run.obstacle_misses;
      continue;
    }
    for (std::size_t i = seen; i < station->trajectory_log.size(); ++i) {
      if (station->trajectory_log[i].vehicle_id == vehicle && station->trajectory_log[i].revision > revision) {
        run.obstacle_ms.push_back(msSince(t0, station->trajectory_times[i]));
        break;
      }
    }
  }
  daemon.signal(SIGTERM);
  daemon.wait(10.0);
  return run;
}

}  // namespace

int main(int argc, char** argv) {
  int rounds = 20;
  Setup setup;
  for (int i = 1; i + 1 < argc; ++i) {
    if (std::strcmp(argv[i], "--rounds") == 0) rounds = std::atoi(argv[i + 1]);
    if (std::strcmp(argv[i], "--config") == 0) setup.config = argv[i + 1];  // passed to skyrouted
  }
  dds::useLoopbackOnly();

  setup.dem = std::string(SKYROUTE_DATA_DIR) + "/default_terrain.tif";
  CollisionWorldOptions options;
  options.build_octree = false;
  setup.terrain = loadTerrainWorld(setup.dem, options).value().heightfield;

  std::printf("| measurement (embedded terrain unless noted) | vehicles | samples | p50 ms | p90 ms | p99 ms | max ms |\n");
  std::printf("|---|---:|---:|---:|---:|---:|---:|\n");
  for (int vehicles : {1, 20}) {
    const int request_rounds = vehicles == 1 ? rounds : std::max(1, rounds / 10);
    Run r = measure(setup, vehicles, request_rounds, rounds, [&](int v, const std::string& id) {
      return bench::laneMission(*setup.terrain, id, v, vehicles);
    });
    row("request -> trajectory received", vehicles, r.request_ms);
    row("obstacle update -> new revision received", vehicles, r.obstacle_ms);
    if (r.obstacle_misses > 0) std::printf("(%d obstacle updates got no revision within 5 s)\n", r.obstacle_misses);
    ++setup.domain;
  }

  const std::string n44 = std::string(SKYROUTE_SHARED_DATA_DIR) + "/dem/N44W072.hgt";
  if (std::FILE* f = std::fopen(n44.c_str(), "rb")) {
    std::fclose(f);
    Setup s3 = setup;
    s3.dem = n44;
    s3.terrain = loadTerrainWorld(n44, options).value().heightfield;
    const MovingObstacleScenario scenario = seed003Table1Scenario(*s3.terrain);
    Run r = measure(s3, 1, 1, rounds, [&](int, const std::string& id) { return bench::seed003Mission(scenario, id); });
    row("N44W072 seed-003 vehicle: obstacle -> revision", 1, r.obstacle_ms);
  } else {
    bench::skipCaseForMissingData("(N44W072 seed-003 case skipped: " + n44 + " not found)", n44 + " not found");
  }
  return 0;
}
