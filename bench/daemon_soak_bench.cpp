// The daemon held under load for long, skyrouted as a separate process on loopback:
//  - soak (default): 20 vehicles flying lane missions (each asks again before its trajectory
//    ends) and one obstacle update every 0.1 s crossing the vehicles in turn (one obstacle id per
//    vehicle, so 20 obstacles in force). Per window: the daemon's RSS, the latency from update to
//    the crossed vehicle's answer (new revision or replan status; only updates the ground station
//    finds meeting the vehicle, tests/daemon/obstacle_reach.hpp), answers missing after 5 s,
//    revisions skipped (a vehicle's revisions must come 0, 1, 2, ... per plan), the longest gap
//    between heartbeats, and requests without a terminal status.
//  - --flood S: `skyroute replay --rate 10000 --loop` for S seconds against the 20 vehicles, with
//    a request every second; prints the RSS before and the max during, the heartbeat gaps, the
//    largest number of updates one cycle coalesced (from the daemon's log) and unanswered requests.
// Usage: daemon_soak_bench [--minutes M] [--window-s S] [--flood S] [--domain N] (default 78)
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <map>
#include <regex>
#include <string>
#include <vector>

#include "bench/latency_scenario.hpp"
#include "service/dds/loopback.hpp"
#include "terrain/terrain_world.hpp"
#include "tests/daemon/daemon_process.hpp"
#include "tests/daemon/flood_feed.hpp"
#include "tests/daemon/ground_station.hpp"
#include "tests/daemon/obstacle_reach.hpp"

namespace {

using namespace skyroute;
using Clock = std::chrono::steady_clock;
constexpr int kVehicles = 20;

double percentile(std::vector<double> v, double f) {
  if (v.empty()) return NAN;
  std::sort(v.begin(), v.end());
  return v[std::min(v.size() - 1, static_cast<std::size_t>(std::ceil(f * static_cast<double>(v.size()))) - 1)];
}

struct Pending {  // an update waiting for its vehicle's answer
  std::string vehicle;
  std::uint32_t revision;
  std::string plan_id;
  Clock::time_point t0;
};

struct Window {
  std::vector<double> answer_ms;
  long rss_max_kb = 0;
  int missing = 0;        // no answer after 5 s
  double heartbeat_gap_s = 0.0;
};

// The soak's ground station side: missions, updates, and matching answers as they arrive.
class Soak {
 public:
  Soak(testing::Station& station, const Heightfield& terrain) : station_(station), terrain_(terrain) {}

  void askAll() {
    for (int v = 0; v < kVehicles; ++v) ask(v);
  }
  // Asks again for every vehicle whose trajectory ends within 30 s.
  void renewMissions() {
    const std::int64_t soon_ns = utcNowNs() + 30'000'000'000LL;
    for (int v = 0; v < kVehicles; ++v) {
      const TrajectoryData* t = station_.latest(name(v));
      if (t && t->samples.back().utc_ns < soon_ns && !waiting_[v]) ask(v);
    }
  }
  void writeUpdate(std::uint64_t k) {
    const int v = static_cast<int>(k % kVehicles);
    const TrajectoryData* t = station_.latest(name(v));
    if (!t || waiting_[v]) return;
    const ObstacleUpdateData u = bench::crossing(*t, utcNowNs(), 1 + static_cast<std::uint64_t>(v), 15.0 + (k % 4) * 5.0);
    if (testing::obstacleMeets(*t, u, utcNowNs(), 45.0, 5.0)) pending_.push_back({name(v), t->revision, t->plan_id, Clock::now()});
    (void)station_.obstacles->write(u);
  }
  // Matches the trajectories and statuses that arrived since the last call.
  void collect(Window& w) {
    for (; traj_seen_ < station_.trajectory_log.size(); ++traj_seen_) {
      const TrajectoryData& t = station_.trajectory_log[traj_seen_];
      auto [it, fresh] = last_revision_.try_emplace(t.plan_id, t.revision);
      if (!fresh) {
        if (t.revision > it->second + 1) skipped_ += static_cast<int>(t.revision - it->second - 1);
        it->second = std::max(it->second, t.revision);
      }
      if (t.revision == 0) waiting_[index(t.vehicle_id)] = false;
      answer(w, t.vehicle_id, station_.trajectory_times[traj_seen_], [&](const Pending& p) {
        return t.plan_id != p.plan_id || t.revision > p.revision;
      });
    }
    for (; status_seen_ < station_.status_log.size(); ++status_seen_) {
      const PlanStatusData& s = station_.status_log[status_seen_];
      if (isTerminal(s.state) && s.state != PlanState::kSucceeded && s.vehicle_id.rfind("uav-", 0) == 0) {
        waiting_[index(s.vehicle_id)] = false;  // refused or failed: asked again when due
      }
      if ((s.state == PlanState::kReplanned || s.state == PlanState::kHolding) && s.error_code != PlanErrorCode::kNone) {
        answer(w, s.vehicle_id, Clock::now(), [](const Pending&) { return true; });
      }
    }
    compactLogs();
    const auto now = Clock::now();
    for (auto it = pending_.begin(); it != pending_.end();) {
      if (now - it->t0 > std::chrono::seconds(5)) {
        ++w.missing;
        it = pending_.erase(it);
      } else {
        ++it;
      }
    }
  }
  int skipped() const { return skipped_; }
  std::size_t unansweredRequests() const {
    std::size_t n = 0;
    for (const std::string& id : asked_) n += station_.terminal(id) ? 0 : 1;
    return n;
  }

 private:
  static std::string name(int v) { return "uav-" + std::to_string(v); }
  static int index(const std::string& vehicle) { return std::stoi(vehicle.substr(4)); }
  void ask(int v) {
    asked_.push_back("soak-" + std::to_string(asked_.size()));
    waiting_[v] = true;
    (void)station_.requests->write(bench::laneMission(terrain_, asked_.back(), v, kVehicles));
  }
  // Keeps each vehicle's last trajectory received (an hour of revisions would not fit in memory;
  // Station::latest then finds the one in force, even across plans) and no statuses but the
  // requests' terminal ones.
  void compactLogs() {
    std::map<std::string, std::size_t> last;
    for (std::size_t i = 0; i < station_.trajectory_log.size(); ++i) last[station_.trajectory_log[i].vehicle_id] = i;
    std::vector<TrajectoryData> kept;
    std::vector<Clock::time_point> times;
    for (const auto& [vehicle, i] : last) {
      kept.push_back(std::move(station_.trajectory_log[i]));
      times.push_back(station_.trajectory_times[i]);
    }
    station_.trajectory_log = std::move(kept);
    station_.trajectory_times = std::move(times);
    traj_seen_ = station_.trajectory_log.size();
    std::erase_if(station_.status_log, [](const PlanStatusData& s) { return !isTerminal(s.state); });
    status_seen_ = station_.status_log.size();
  }
  template <class Answers>
  void answer(Window& w, const std::string& vehicle, Clock::time_point at, Answers answers) {
    for (auto it = pending_.begin(); it != pending_.end();) {
      if (it->vehicle == vehicle && at >= it->t0 && answers(*it)) {
        w.answer_ms.push_back(std::chrono::duration<double, std::milli>(at - it->t0).count());
        it = pending_.erase(it);
      } else {
        ++it;
      }
    }
  }

  testing::Station& station_;
  const Heightfield& terrain_;
  std::vector<Pending> pending_;
  std::map<std::string, std::uint32_t> last_revision_;  // plan id -> highest revision seen
  std::map<int, bool> waiting_;                          // vehicle asked again, no trajectory yet
  std::vector<std::string> asked_;
  std::size_t traj_seen_ = 0, status_seen_ = 0;
  int skipped_ = 0;
};

double longestHeartbeatGapS(const testing::Station& station, std::size_t from) {
  double gap = 0.0;
  for (std::size_t i = from + 1; i < station.heartbeat_stamps_ns.size(); ++i) {
    gap = std::max(gap, static_cast<double>(station.heartbeat_stamps_ns[i] - station.heartbeat_stamps_ns[i - 1]) * 1e-9);
  }
  return gap;
}

void runSoak(testing::Station& station, testing::ChildProcess& daemon, const Heightfield& terrain, double minutes,
             double window_s) {
  Soak soak(station, terrain);
  soak.askAll();
  station.pumpUntil([&] { return station.trajectory_log.size() >= kVehicles; }, 120.0);
  std::printf("| window | updates answered | p50 ms | p99 ms | max ms | missing | RSS max MiB | heartbeat gap max s |\n");
  std::printf("|---|---:|---:|---:|---:|---:|---:|---:|\n");
  const auto start = Clock::now();
  std::uint64_t k = 0;
  for (int w = 0; Clock::now() - start < std::chrono::duration<double>(minutes * 60.0); ++w) {
    Window window;
    const std::size_t heartbeat_from = station.heartbeat_stamps_ns.size();
    const auto window_end = start + std::chrono::duration_cast<Clock::duration>(std::chrono::duration<double>((w + 1) * window_s));
    auto next_update = Clock::now();
    while (Clock::now() < window_end && daemon.running()) {
      station.pumpUntil([&] { return Clock::now() >= next_update; }, 0.1);
      soak.collect(window);
      if (Clock::now() >= next_update) {
        soak.writeUpdate(k++);
        next_update += std::chrono::milliseconds(100);
        if (k % 10 == 0) {
          soak.renewMissions();
          window.rss_max_kb = std::max(window.rss_max_kb, daemon.rssKb());
        }
      }
    }
    window.heartbeat_gap_s = longestHeartbeatGapS(station, heartbeat_from);
    std::printf("| %d | %zu | %.1f | %.1f | %.1f | %d | %.1f | %.2f |\n", w + 1, window.answer_ms.size(),
                percentile(window.answer_ms, 0.5), percentile(window.answer_ms, 0.99), percentile(window.answer_ms, 1.0),
                window.missing, static_cast<double>(window.rss_max_kb) / 1024.0, window.heartbeat_gap_s);
    std::fflush(stdout);
    if (!daemon.running()) break;
  }
  station.pumpUntil([] { return false; }, 5.0);
  std::printf("revisions skipped: %d; requests without a terminal status: %zu; daemon %s\n", soak.skipped(),
              soak.unansweredRequests(), daemon.running() ? "running" : "EXITED");
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
  const double gap_s = longestHeartbeatGapS(station, heartbeat_from);
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
  if (flood_s > 0.0) {
    runFlood(*station, daemon, *terrain, flood_s, domain);
  } else {
    runSoak(*station, daemon, *terrain, minutes, window_s);
  }
  daemon.signal(SIGTERM);
  return daemon.wait(10.0) == 0 ? 0 : 1;
}
