// End-to-end latency over DDS with skyrouted as a separate process on loopback:
//  - request written -> its trajectory received, for 1 and 20 vehicles asking at once;
//  - obstacle update written -> the answer of every vehicle the obstacle will meet (a new
//    revision, or a replan status saying why there is none), with 1 and 20 vehicles flying. Each
//    update is a cylinder that sweeps across one vehicle's route and meets it 15-30 s ahead; which
//    vehicles it meets is decided at the ground station from their trajectories
//    (tests/daemon/obstacle_reach.hpp). Answers missing after 5 s or later than 1 s are counted.
// With ../shared/data, the one-vehicle obstacle case also runs on N44W072 with seed 003's vehicle
// (V_ref 50 m/s) between the seed-003 scenario's start and goal. Prints p50/p90/p99/max (ms).
// Compare with Cyclone's own round trip: ddsperf ping/pong (docs/benchmarks/dds.md).
// Usage: e2e_latency_bench [--rounds N] [--updates N] [--vehicles N] [--config skyrouted.toml]
//   [--domain N] [--log-level L] [--daemon-log FILE]
// DDS domains N and N+1, N+2 for the N44W072 row (default 150); --vehicles runs that fleet size
// alone on domain N; --daemon-log keeps the daemon's log.
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
#include "tests/daemon/update_answers.hpp"

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
  std::string log_level = "warn";
  std::string daemon_log;  // the daemon's log is copied here ("" = not kept)
};

struct Run {
  std::vector<double> request_ms;
  std::vector<double> obstacle_ms;   // the crossed vehicle's answer
  std::vector<double> neighbour_ms;  // other vehicles the obstacle also meets
  int affected = 0;                  // vehicle answers due (the independent check)
  int obstacle_misses = 0;           // ... not given within 5 s
  int late = 0;                      // ... given after more than 1 s
  int by_status = 0;                 // ... given by a replan status (no better revision)
  int target_missed = 0;             // updates whose crossing missed its vehicle (the check says)
};

Run measure(const Setup& setup, int vehicles, int request_rounds, int obstacle_updates,
            const std::function<MissionRequestData(int vehicle, const std::string& id)>& mission_of) {
  Run run;
  std::vector<std::string> argv{SKYROUTED, "--domain", std::to_string(setup.domain), "--dem", setup.dem,
                                "--log-level", setup.log_level};
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
  // Every vehicle the obstacle will meet (decided here from its trajectory) must answer: a new
  // revision, or a replan status saying why there is none.
  std::vector<std::string> names;
  for (int v = 0; v < vehicles; ++v) names.push_back("uav-" + std::to_string(v));
  std::uint64_t previous_id = 0;
  for (int u = 0; u < obstacle_updates; ++u) {
    const std::string vehicle = names[static_cast<std::size_t>(u % vehicles)];
    const TrajectoryData* current = station->latest(vehicle);
    if (!current) break;
    if (previous_id != 0) {
      ObstacleUpdateData gone;
      gone.obstacle.id = previous_id;
      gone.remove = true;
      (void)station->obstacles->write(gone);
      station->pumpUntil([] { return false; }, 0.3);  // let the daemon settle
    }
    const ObstacleUpdateData update = bench::crossing(*station->latest(vehicle), utcNowNs(), 1000 + u, 15.0 + (u % 4) * 5.0);
    previous_id = update.obstacle.id;
    const testing::UpdateAnswers answers = testing::writeAndAwaitAnswers(*station, names, update, 5.0);
    run.affected += static_cast<int>(answers.affected.size());
    for (const auto& [who, ms] : answers.answer_ms) {
      if (ms > 1000.0) ++run.late;
      if (answers.by_status.at(who)) ++run.by_status;
      if (who == vehicle) {
        run.obstacle_ms.push_back(ms);
      } else {
        run.neighbour_ms.push_back(ms);
      }
    }
    run.obstacle_misses += static_cast<int>(answers.unanswered.size());
    if (std::find(answers.affected.begin(), answers.affected.end(), vehicle) == answers.affected.end()) ++run.target_missed;
  }
  if (!setup.daemon_log.empty()) {
    std::FILE* f = std::fopen(setup.daemon_log.c_str(), "w");
    if (f) {
      const std::string text = daemon.err();
      std::fwrite(text.data(), 1, text.size(), f);
      std::fclose(f);
    }
  }
  daemon.signal(SIGTERM);
  daemon.wait(10.0);
  return run;
}

void printAnswers(const Run& r, int vehicles) {
  row("obstacle update -> crossed vehicle's answer", vehicles, r.obstacle_ms);
  if (!r.neighbour_ms.empty()) row("obstacle update -> other met vehicles' answer", vehicles, r.neighbour_ms);
  std::printf("(answers due %d: %d missing after 5 s, %d later than 1 s, %d by a replan status; %d crossings "
              "missed their vehicle)\n",
              r.affected, r.obstacle_misses, r.late, r.by_status, r.target_missed);
}

}  // namespace

int main(int argc, char** argv) {
  int rounds = 20;
  int updates = -1;  // obstacle updates per run (default: rounds)
  std::vector<int> fleet_sizes{1, 20};
  bool n44_case = true;
  Setup setup;
  for (int i = 1; i + 1 < argc; ++i) {
    if (std::strcmp(argv[i], "--rounds") == 0) rounds = std::atoi(argv[i + 1]);
    if (std::strcmp(argv[i], "--updates") == 0) updates = std::atoi(argv[i + 1]);
    if (std::strcmp(argv[i], "--vehicles") == 0) {  // one fleet size only, no N44W072 row
      fleet_sizes = {std::max(1, std::atoi(argv[i + 1]))};
      n44_case = false;
    }
    if (std::strcmp(argv[i], "--config") == 0) setup.config = argv[i + 1];  // passed to skyrouted
    // The first of the two DDS domains the runs use (one per vehicle count; default 150).
    if (std::strcmp(argv[i], "--domain") == 0) setup.domain = std::atoi(argv[i + 1]);
    if (std::strcmp(argv[i], "--log-level") == 0) setup.log_level = argv[i + 1];  // the daemon's
    if (std::strcmp(argv[i], "--daemon-log") == 0) setup.daemon_log = argv[i + 1];
  }
  if (updates < 0) updates = rounds;
  dds::useLoopbackOnly();

  setup.dem = std::string(SKYROUTE_DATA_DIR) + "/default_terrain.tif";
  CollisionWorldOptions options;
  options.build_octree = false;
  setup.terrain = loadTerrainWorld(setup.dem, options).value().heightfield;

  std::printf("| measurement (embedded terrain unless noted) | vehicles | samples | p50 ms | p90 ms | p99 ms | max ms |\n");
  std::printf("|---|---:|---:|---:|---:|---:|---:|\n");
  for (int vehicles : fleet_sizes) {
    const int request_rounds = vehicles == 1 ? rounds : std::max(1, rounds / 10);
    Run r = measure(setup, vehicles, request_rounds, updates, [&](int v, const std::string& id) {
      return bench::laneMission(*setup.terrain, id, v, vehicles);
    });
    row("request -> trajectory received", vehicles, r.request_ms);
    printAnswers(r, vehicles);
    ++setup.domain;
  }
  if (!n44_case) return 0;

  const std::string n44 = std::string(SKYROUTE_SHARED_DATA_DIR) + "/dem/N44W072.hgt";
  if (std::FILE* f = std::fopen(n44.c_str(), "rb")) {
    std::fclose(f);
    Setup s3 = setup;
    s3.dem = n44;
    s3.terrain = loadTerrainWorld(n44, options).value().heightfield;
    const MovingObstacleScenario scenario = seed003Table1Scenario(*s3.terrain);
    Run r = measure(s3, 1, 1, updates, [&](int, const std::string& id) { return bench::seed003Mission(scenario, id); });
    row("N44W072 seed-003 vehicle: obstacle -> answer", 1, r.obstacle_ms);
  } else {
    bench::skipCaseForMissingData("(N44W072 seed-003 case skipped: " + n44 + " not found)", n44 + " not found");
  }
  return 0;
}
