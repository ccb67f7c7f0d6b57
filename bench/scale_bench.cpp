// Many vehicles across several daemons, every daemon a separate skyrouted process on loopback:
// N vehicles (default 1,000), each with its own mission over the embedded terrain, and an obstacle
// feed whose updates each cross one vehicle's route, served by 1 daemon and by D daemons of one
// shard group (service.shard_group, docs/dds.md "Shards"). Per daemon count it prints:
//  - requests per second: every request written at once, N over the time to the last first
//    trajectory (the burst's throughput), and p50/p99 request written -> its first trajectory;
//  - p99 obstacle update -> answer of every vehicle the update meets (a new revision, or a replan
//    status saying why there is none; tests/daemon/update_answers.hpp decides who it meets from
//    the trajectories received), the updates paced at --update-hz;
//  - RSS per daemon after the feed (max and sum);
//  - DDS traffic: bytes and packets per second on the loopback interface (/proc/net/dev) during
//    the requests and during the feed. Everything on `lo` counts, so run it on an otherwise quiet
//    machine.
// Usage: scale_bench [--vehicles N] [--daemons 1,4] [--updates U] [--update-hz R] [--threads T]
//   [--domain D] [--seed S] [--log-level L]
// Domain D for the first daemon count, D + 1 for the next, ... (default 155).
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <deque>
#include <fstream>
#include <map>
#include <random>
#include <set>
#include <sstream>
#include <string>
#include <vector>

#include "bench/latency_scenario.hpp"
#include "bench/support/bench_stats.hpp"
#include "service/dds/loopback.hpp"
#include "terrain/terrain_world.hpp"
#include "tests/daemon/daemon_process.hpp"
#include "tests/daemon/ground_station.hpp"
#include "tests/daemon/update_answers.hpp"

namespace {

using namespace skyroute;
using Clock = std::chrono::steady_clock;

struct Settings {
  int vehicles = 1000;
  std::vector<int> daemon_counts{1, 4};
  int updates = 200;
  double update_hz = 10.0;
  int threads = 1;  // planning.threads of each daemon
  int domain = 155;
  std::uint64_t seed = 1;
  std::string log_level = "warn";
  std::string dem;
};

// Bytes and packets through the loopback interface so far (receive side: on `lo` every byte sent
// is received once).
struct LoopbackCounters {
  double bytes = 0.0, packets = 0.0;
  static LoopbackCounters now() {
    std::ifstream in("/proc/net/dev");
    std::string line;
    while (std::getline(in, line)) {
      const auto colon = line.find(':');
      if (colon == std::string::npos) continue;
      std::string name = line.substr(0, colon);
      name.erase(0, name.find_first_not_of(' '));
      if (name != "lo") continue;
      std::istringstream fields(line.substr(colon + 1));
      LoopbackCounters c;
      fields >> c.bytes >> c.packets;
      return c;
    }
    return {};
  }
};

double secondsSince(Clock::time_point t0) { return std::chrono::duration<double>(Clock::now() - t0).count(); }

// Vehicle v's mission: a begin and an end drawn (from the vehicle's own seed) anywhere 5 % in from
// the terrain's sides, at least 40 % of its width apart, through a point near their middle, 300 m
// above the ground: routes that cross each other everywhere, as a real fleet's do.
MissionRequestData scatteredMission(const Heightfield& terrain, const std::string& id, int vehicle, std::uint64_t seed) {
  std::mt19937_64 rng(seed * 1000003ULL + static_cast<std::uint64_t>(vehicle));
  const Eigen::AlignedBox2d box = terrain.boundsEn();
  const Eigen::Vector2d lo = box.min() + 0.05 * box.sizes(), hi = box.max() - 0.05 * box.sizes();
  std::uniform_real_distribution<double> ue(lo.x(), hi.x()), un(lo.y(), hi.y()), offset(-300.0, 300.0);
  Eigen::Vector2d a, b;
  do {
    a = {ue(rng), un(rng)};
    b = {ue(rng), un(rng)};
  } while ((a - b).norm() < 0.4 * box.sizes().x());
  const Eigen::Vector2d mid = 0.5 * (a + b) + Eigen::Vector2d(offset(rng), offset(rng));
  MissionRequestData m;
  m.request_id = id;
  m.vehicle_id = "uav-" + std::to_string(vehicle);
  m.begin = bench::above(terrain, a.x(), a.y(), 300);
  m.points = {bench::above(terrain, std::clamp(mid.x(), lo.x(), hi.x()), std::clamp(mid.y(), lo.y(), hi.y()), 300)};
  m.end = bench::above(terrain, b.x(), b.y(), 300);
  m.limits = bench::seed003Vehicle();
  m.limits.ceiling_amsl_m = 12000.0;
  return m;
}

struct RunResult {
  int daemons = 0;
  int planned = 0;                 // vehicles whose first trajectory arrived
  double burst_s = 0.0;            // first request written -> last first trajectory
  std::vector<double> request_ms;  // request written -> its first trajectory
  std::vector<double> update_ms;   // update written -> each met vehicle's answer
  int answers_due = 0, answers_missing = 0;
  std::vector<long> rss_kb;        // per daemon, after the feed
  double request_bytes_per_s = 0.0, request_packets_per_s = 0.0;
  double feed_bytes_per_s = 0.0, feed_packets_per_s = 0.0;
  double feed_s = 0.0;
  double samples_per_trajectory = 0.0;  // mean over the first trajectories
  std::string failure;             // why the run stopped short ("" = it did not)
};

std::string writeConfig(const Settings& s, int k) {
  const std::string path = testing::tempPath("scale_bench", "shard" + std::to_string(k) + ".toml");
  std::ofstream out(path);
  out << "[dds]\nservice_id = \"scale-" << k << "\"\n";
  out << "[service]\n";
  out << "shard_group = \"scale\"\n";  // one daemon too: the same code path
  out << "[ros2]\nenabled = false\n";
  out << "[planning]\nthreads = " << s.threads << "\nmax_queue = " << s.vehicles + 16
      << "\nmax_stored_results = " << s.vehicles + 16 << "\nseed = " << s.seed << "\n";
  return path;
}

RunResult run(const Settings& s, const Heightfield& terrain, int daemons, int domain) {
  RunResult r;
  r.daemons = daemons;
  std::vector<testing::ChildProcess> procs;
  for (int k = 0; k < daemons; ++k) {
    procs.push_back(testing::ChildProcess::spawn({SKYROUTED, "--domain", std::to_string(domain), "--dem", s.dem,
                                                  "--log-level", s.log_level, "--config", writeConfig(s, k)},
                                                 "scale_daemon" + std::to_string(k)));
  }
  auto station = testing::Station::open(domain);
  if (!station) {
    r.failure = "no DDS participant";
    return r;
  }
  const bool up = station->requests->waitForReaders(static_cast<std::uint32_t>(daemons), 60.0).ok() &&
                  station->trajectories->waitForWriters(static_cast<std::uint32_t>(daemons), 60.0).ok() &&
                  station->obstacles->waitForReaders(static_cast<std::uint32_t>(daemons), 60.0).ok();
  if (!up) {
    r.failure = "daemons did not come up: " + procs.front().err();
    return r;
  }
  // Heartbeats from every daemon, so the shards have seen each other before the burst.
  station->pumpUntil([&] { return station->heartbeats >= 2 * daemons; }, 30.0);

  // The burst: every vehicle's request at once.
  std::map<std::string, Clock::time_point> sent;
  std::map<std::string, double> first_ms;
  const LoopbackCounters lo0 = LoopbackCounters::now();
  const Clock::time_point burst0 = Clock::now();
  for (int v = 0; v < s.vehicles; ++v) {
    const MissionRequestData m = scatteredMission(terrain, "scale-" + std::to_string(v), v, s.seed);
    sent[m.vehicle_id] = Clock::now();
    (void)station->requests->write(m);
  }
  std::size_t seen = 0;
  Clock::time_point last_progress = Clock::now();
  station->pumpUntil(
      [&] {
        for (; seen < station->trajectory_log.size(); ++seen) {
          const TrajectoryData& t = station->trajectory_log[seen];
          auto it = sent.find(t.vehicle_id);
          if (it == sent.end() || first_ms.count(t.vehicle_id)) continue;
          first_ms[t.vehicle_id] = std::chrono::duration<double, std::milli>(station->trajectory_times[seen] - it->second).count();
        }
        if (secondsSince(last_progress) > 10.0) {
          last_progress = Clock::now();
          std::fprintf(stderr, "  %d daemon(s): %zu of %d vehicles planned after %.0f s\n", daemons, first_ms.size(),
                       s.vehicles, secondsSince(burst0));
        }
        return static_cast<int>(first_ms.size()) == s.vehicles;
      },
      1800.0);
  r.burst_s = secondsSince(burst0);
  const LoopbackCounters lo1 = LoopbackCounters::now();
  r.request_bytes_per_s = (lo1.bytes - lo0.bytes) / r.burst_s;
  r.request_packets_per_s = (lo1.packets - lo0.packets) / r.burst_s;
  r.planned = static_cast<int>(first_ms.size());
  {
    std::set<std::string> counted;
    double samples = 0.0;
    for (const TrajectoryData& t : station->trajectory_log)
      if (counted.insert(t.vehicle_id).second) samples += static_cast<double>(t.samples.size());
    r.samples_per_trajectory = counted.empty() ? 0.0 : samples / static_cast<double>(counted.size());
  }
  for (const auto& [vehicle, ms] : first_ms) r.request_ms.push_back(ms);
  if (r.planned < s.vehicles) r.failure = std::to_string(s.vehicles - r.planned) + " vehicles unplanned after 30 min";

  // The feed: each update crosses one vehicle's route (vehicles taken in a seeded order) to meet
  // it 15-30 s ahead; at most 20 obstacles are in force, the oldest removed first.
  std::vector<std::string> names;
  for (int v = 0; v < s.vehicles; ++v) names.push_back("uav-" + std::to_string(v));
  std::vector<std::string> order = names;
  std::shuffle(order.begin(), order.end(), std::mt19937_64(s.seed));
  std::deque<std::uint64_t> in_force;
  const LoopbackCounters lo2 = LoopbackCounters::now();
  const Clock::time_point feed0 = Clock::now();
  const double period_s = 1.0 / std::max(0.01, s.update_hz);
  for (int u = 0; u < s.updates && r.failure.empty(); ++u) {
    const Clock::time_point tick = feed0 + std::chrono::duration_cast<Clock::duration>(std::chrono::duration<double>(u * period_s));
    station->pumpUntil([&] { return Clock::now() >= tick; }, std::max(0.0, std::chrono::duration<double>(tick - Clock::now()).count()));
    const TrajectoryData* current = station->latest(order[static_cast<std::size_t>(u) % order.size()]);
    if (!current) continue;
    if (in_force.size() >= 20) {
      ObstacleUpdateData gone;
      gone.obstacle.id = in_force.front();
      gone.remove = true;
      in_force.pop_front();
      (void)station->obstacles->write(gone);
    }
    const ObstacleUpdateData update = bench::crossing(*current, utcNowNs(), 5000 + static_cast<std::uint64_t>(u), 15.0 + (u % 4) * 5.0);
    in_force.push_back(update.obstacle.id);
    const testing::UpdateAnswers answers = testing::writeAndAwaitAnswers(*station, names, update, 5.0);
    r.answers_due += static_cast<int>(answers.affected.size());
    r.answers_missing += static_cast<int>(answers.unanswered.size());
    for (const auto& [who, ms] : answers.answer_ms) r.update_ms.push_back(ms);
    if ((u + 1) % 50 == 0) std::fprintf(stderr, "  %d daemon(s): %d of %d updates\n", daemons, u + 1, s.updates);
  }
  r.feed_s = secondsSince(feed0);
  const LoopbackCounters lo3 = LoopbackCounters::now();
  r.feed_bytes_per_s = (lo3.bytes - lo2.bytes) / r.feed_s;
  r.feed_packets_per_s = (lo3.packets - lo2.packets) / r.feed_s;
  for (testing::ChildProcess& p : procs) r.rss_kb.push_back(p.rssKb());
  for (testing::ChildProcess& p : procs) p.signal(SIGTERM);
  for (testing::ChildProcess& p : procs) {
    if (p.wait(20.0) != 0 && r.failure.empty()) r.failure = "a daemon did not stop cleanly: " + p.err().substr(0, 400);
  }
  return r;
}

std::vector<int> parseCounts(const char* text) {
  std::vector<int> out;
  std::stringstream in(text);
  std::string item;
  while (std::getline(in, item, ',')) out.push_back(std::max(1, std::atoi(item.c_str())));
  return out;
}

}  // namespace

int main(int argc, char** argv) {
  Settings s;
  for (int i = 1; i + 1 < argc; ++i) {
    if (std::strcmp(argv[i], "--vehicles") == 0) s.vehicles = std::max(1, std::atoi(argv[i + 1]));
    if (std::strcmp(argv[i], "--daemons") == 0) s.daemon_counts = parseCounts(argv[i + 1]);
    if (std::strcmp(argv[i], "--updates") == 0) s.updates = std::max(0, std::atoi(argv[i + 1]));
    if (std::strcmp(argv[i], "--update-hz") == 0) s.update_hz = std::atof(argv[i + 1]);
    if (std::strcmp(argv[i], "--threads") == 0) s.threads = std::max(1, std::atoi(argv[i + 1]));
    if (std::strcmp(argv[i], "--domain") == 0) s.domain = std::atoi(argv[i + 1]);
    if (std::strcmp(argv[i], "--seed") == 0) s.seed = std::strtoull(argv[i + 1], nullptr, 10);
    if (std::strcmp(argv[i], "--log-level") == 0) s.log_level = argv[i + 1];
  }
  dds::useLoopbackOnly();
  s.dem = std::string(SKYROUTE_DATA_DIR) + "/default_terrain.tif";
  CollisionWorldOptions options;
  options.build_octree = false;
  const auto terrain = loadTerrainWorld(s.dem, options).value().heightfield;

  std::vector<RunResult> results;
  int domain = s.domain;
  for (int d : s.daemon_counts) {
    std::fprintf(stderr, "%d vehicles on %d daemon(s), domain %d\n", s.vehicles, d, domain);
    results.push_back(run(s, *terrain, d, domain++));
  }
  std::printf("%d vehicles, %d obstacle updates paced at %.1f Hz (each waits for its answers, up to 5 s), "
              "planning.threads %d per daemon\n\n",
              s.vehicles, s.updates, s.update_hz, s.threads);
  std::printf("| daemons | planned | requests/s | request -> trajectory p50 ms | p99 ms | update -> answer p50 ms | p99 "
              "ms | answers due / missing | RSS max MiB/daemon | RSS sum MiB | lo MB/s requests | lo kpkt/s requests | lo "
              "MB/s feed | lo kpkt/s feed |\n");
  std::printf("|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|\n");
  const double base_rps = results.empty() || results.front().burst_s <= 0 ? 0.0 : results.front().planned / results.front().burst_s;
  for (const RunResult& r : results) {
    long rss_max = 0, rss_sum = 0;
    for (long kb : r.rss_kb) {
      rss_max = std::max(rss_max, kb);
      rss_sum += std::max(0L, kb);
    }
    std::printf("| %d | %d | %.1f | %.0f | %.0f | %.1f | %.1f | %d / %d | %.1f | %.1f | %.2f | %.1f | %.2f | %.1f |\n",
                r.daemons, r.planned, r.burst_s > 0 ? r.planned / r.burst_s : 0.0, bench::quantile(r.request_ms, 0.5),
                bench::quantile(r.request_ms, 0.99), bench::quantile(r.update_ms, 0.5), bench::quantile(r.update_ms, 0.99),
                r.answers_due, r.answers_missing, rss_max / 1024.0, rss_sum / 1024.0, r.request_bytes_per_s / 1e6,
                r.request_packets_per_s / 1e3, r.feed_bytes_per_s / 1e6, r.feed_packets_per_s / 1e3);
  }
  for (const RunResult& r : results) {
    if (r.burst_s > 0 && base_rps > 0)
      std::printf("%d daemon(s): throughput x%.2f of the first row\n", r.daemons, (r.planned / r.burst_s) / base_rps);
    if (r.feed_s > 0) std::printf("%d daemon(s): feed ran at %.1f updates/s\n", r.daemons, s.updates / r.feed_s);
    // A TrajectorySample is 14 doubles and an int64 on the wire: 120 B.
    std::printf("%d daemon(s): %.0f samples per trajectory (about %.0f kB each, %.1f MB for every vehicle's current one)\n",
                r.daemons, r.samples_per_trajectory, r.samples_per_trajectory * 120.0 / 1e3,
                r.samples_per_trajectory * 120.0 * r.planned / 1e6);
    if (!r.failure.empty()) std::printf("%d daemon(s): %s\n", r.daemons, r.failure.c_str());
  }
  return std::all_of(results.begin(), results.end(), [](const RunResult& r) { return r.failure.empty(); }) ? 0 : 1;
}
