// The daemon held under load for long, skyrouted as a separate process on loopback:
//  - soak (default): tests/daemon/soak_scenario.hpp (20 vehicles on lane missions, a crossing
//    obstacle update every 0.1 s), a table row per window (RSS, update -> answer latency, answers
//    missing after 5 s, heartbeat gap), then revisions lost and requests without a terminal
//    status; the exit status says whether the run held the soak's bounds.
//  - --flood S: `skyroute replay --rate 10000 --loop` for S seconds against the 20 vehicles, with
//    a request every second; prints the RSS before and the max during, the heartbeat gaps, the
//    largest number of updates one cycle coalesced (from the daemon's log) and unanswered requests.
// Usage: daemon_soak_bench [--minutes M] [--window-s S] [--flood S] [--domain N] (default 78)
#include <algorithm>
#include <cstdio>
#include <cstring>
#include <regex>
#include <string>
#include <vector>

#include "bench/latency_scenario.hpp"
#include "service/dds/loopback.hpp"
#include "terrain/terrain_world.hpp"
#include "tests/daemon/daemon_process.hpp"
#include "tests/daemon/flood_feed.hpp"
#include "tests/daemon/ground_station.hpp"
#include "tests/daemon/soak_scenario.hpp"

namespace {

using namespace skyroute;
constexpr int kVehicles = testing::Soak::kVehicles;

// The soak of tests/daemon/soak_scenario.hpp, a table row per window. Exits non-zero when the
// run breaks a bound the soak test also asserts (docs/benchmarks.md): an update unanswered, a
// revision lost, a request without a terminal status, RSS growth of 5 % or more from the second (the first with two)
// window to the last, a heartbeat gap over 3 s (a stalled DDS thread), or the daemon gone.
bool soakTable(testing::Station& station, testing::ChildProcess& daemon, const Heightfield& terrain, double minutes,
             double window_s) {
  std::printf("| window | updates answered | p50 ms | p99 ms | max ms | missing | RSS max MiB | heartbeat gap max s |\n");
  std::printf("|---|---:|---:|---:|---:|---:|---:|---:|\n");
  const testing::SoakSummary soak =
      testing::runSoak(station, daemon, terrain, minutes, window_s, [](int w, const testing::SoakWindow& window) {
        std::printf("| %d | %zu | %.1f | %.1f | %.1f | %d | %.1f | %.2f |\n", w, window.answer_ms.size(),
                    testing::soakPercentile(window.answer_ms, 0.5), testing::soakPercentile(window.answer_ms, 0.99),
                    testing::soakPercentile(window.answer_ms, 1.0), window.missing,
                    static_cast<double>(window.rss_max_kb) / 1024.0, window.heartbeat_gap_s);
        std::fflush(stdout);
      });
  std::printf("updates missing an answer: %d (the drain's count in the last window); revisions published %zu, lost %d, "
              "superseded before the station read them %d; requests %zu, without a terminal status %zu; RSS growth "
              "after the warm-up window %.2f %%; longest heartbeat gap %.2f s; daemon %s\n",
              soak.missing(), soak.revisions_published, soak.revisions_lost, soak.revisions_superseded, soak.requests,
              soak.requests_unanswered, 100.0 * soak.rssGrowth(), soak.longestHeartbeatGapS(),
              soak.daemon_running ? "running" : "EXITED");
  return soak.missing() == 0 && soak.revisions_lost == 0 && soak.requests_unanswered == 0 && soak.rssGrowth() < 0.05 &&
         soak.longestHeartbeatGapS() <= 3.0 && soak.daemon_running;
}

void runFlood(testing::Station& station, testing::ChildProcess& daemon, const Heightfield& terrain, double flood_s,
              int domain) {
  std::vector<std::string> asked;
  for (int v = 0; v < kVehicles; ++v) (void)station.requests->write(bench::laneMission(terrain, "lane-" + std::to_string(v), v, kVehicles));
  station.pumpUntil([&] { return station.trajectory_log.size() >= kVehicles; }, 120.0);
  const long rss_before_kb = daemon.rssKb();
  const std::string feed = testing::tempPath("flood_bench", "feed.jsonl");
  testing::writeFloodFeed(feed, terrain, 40, 7);
  testing::ChildProcess replay = testing::ChildProcess::spawn(
      {SKYROUTE_CLI, "replay", feed, "--domain", std::to_string(domain), "--readers", "2", "--rate", "10000", "--loop",
       "--duration", std::to_string(flood_s)},
      "flood_replay");
  station.pumpUntil([&] { return !station.obstacle_log.empty(); }, 20.0);
  const std::size_t heartbeat_from = station.heartbeat_stamps_ns.size();
  long rss_max_kb = 0;
  int ticks = 0;
  while (replay.running()) {
    station.pumpUntil([] { return false; }, 0.25);
    station.obstacle_log.clear();
    rss_max_kb = std::max(rss_max_kb, daemon.rssKb());
    if (++ticks % 4 == 0) {
      asked.push_back("flood-" + std::to_string(asked.size()));
      (void)station.requests->write(bench::laneMission(terrain, asked.back(), static_cast<int>(asked.size()) % kVehicles, kVehicles));
    }
  }
  const double gap_s = testing::longestHeartbeatGapS(station, heartbeat_from);
  double shortest_s = 1e9;
  for (std::size_t i = heartbeat_from + 1; i < station.heartbeat_stamps_ns.size(); ++i) {
    shortest_s = std::min(shortest_s, static_cast<double>(station.heartbeat_stamps_ns[i] - station.heartbeat_stamps_ns[i - 1]) * 1e-9);
  }
  (void)replay.wait(30.0);
  station.waitTerminal(asked, 60.0);
  std::size_t unanswered = 0;
  for (const std::string& id : asked) unanswered += station.terminal(id) ? 0 : 1;
  static const std::regex coalesced("updates_coalesced=([0-9]+)");
  const std::string log = daemon.err();
  std::uint64_t most = 0;
  for (std::sregex_iterator it(log.begin(), log.end(), coalesced), end; it != end; ++it) {
    most = std::max<std::uint64_t>(most, std::stoull((*it)[1].str()));
  }
  std::printf("flood %.0f s: %s", flood_s, replay.out().c_str());
  std::printf("RSS before %.1f MiB, max during %.1f MiB; heartbeat interval min %.3f s, max %.3f s (period 1 s); "
              "most updates coalesced in one replan %llu; requests %zu, without a terminal status %zu; daemon %s\n",
              static_cast<double>(rss_before_kb) / 1024.0, static_cast<double>(rss_max_kb) / 1024.0, shortest_s, gap_s,
              static_cast<unsigned long long>(most), asked.size(), unanswered, daemon.running() ? "running" : "EXITED");
  std::remove(feed.c_str());
}

}  // namespace

int main(int argc, char** argv) {
  double minutes = 60.0, window_s = 300.0, flood_s = 0.0;
  int domain = 78;
  for (int i = 1; i + 1 < argc; ++i) {
    if (std::strcmp(argv[i], "--minutes") == 0) minutes = std::atof(argv[i + 1]);
    if (std::strcmp(argv[i], "--window-s") == 0) window_s = std::max(1.0, std::atof(argv[i + 1]));
    if (std::strcmp(argv[i], "--flood") == 0) flood_s = std::atof(argv[i + 1]);
    if (std::strcmp(argv[i], "--domain") == 0) domain = std::atoi(argv[i + 1]);
  }
  dds::useLoopbackOnly();
  const std::string dem = std::string(SKYROUTE_DATA_DIR) + "/default_terrain.tif";
  CollisionWorldOptions options;
  options.build_octree = false;
  const std::shared_ptr<const Heightfield> terrain = loadTerrainWorld(dem, options).value().heightfield;
  testing::ChildProcess daemon =
      testing::ChildProcess::spawn({SKYROUTED, "--domain", std::to_string(domain), "--dem", dem}, "soak_daemon");
  auto station = testing::Station::open(domain);
  if (!station || !station->pumpUntil([&] { return station->heartbeats > 0; }, 120.0)) {
    std::fprintf(stderr, "daemon did not come up: %s\n", daemon.err().c_str());
    return 1;
  }
  (void)station->requests->waitForReaders(1, 20.0);
  (void)station->obstacles->waitForReaders(1, 20.0);
  bool held = true;
  if (flood_s > 0.0) {
    runFlood(*station, daemon, *terrain, flood_s, domain);
  } else {
    held = soakTable(*station, daemon, *terrain, minutes, window_s);
  }
  daemon.signal(SIGTERM);
  return daemon.wait(10.0) == 0 && held ? 0 : 1;
}
