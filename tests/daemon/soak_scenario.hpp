// The daemon held under steady load, seen from a ground station: 20 vehicles fly lane missions
// (each asks again 30 s before its trajectory ends) while one obstacle update every 0.1 s crosses
// the vehicles in turn (one obstacle id per vehicle, so 20 obstacles are always in force). Used
// by bench/daemon_soak_bench (an hour, 5-minute windows) and by the 2-minute soak test in CI
// (tests/daemon/soak_e2e_test.cpp), so both measure the same thing.
//
// Per window: the daemon's RSS, the latency from an update to the crossed vehicle's answer (a new
// revision or a replan status; only updates the ground station finds meeting the vehicle,
// tests/daemon/obstacle_reach.hpp), answers missing after 5 s, and the longest gap between
// heartbeats. Over the run: revisions lost and requests without a terminal status.
//
// A revision is lost when the daemon published it (its log line `event=replanned` or
// `event=replan_hold` names the plan and the revision) but the trajectory in force at the ground
// station at the end is older than the newest one published for its plan. The trajectory topic
// keeps the last revision per vehicle by design, so a revision replaced before the station read
// it is superseded, not lost: the newest always arrives. Those are counted apart as `superseded`.
#pragma once

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <functional>
#include <map>
#include <sstream>
#include <string>
#include <vector>

#include "bench/latency_scenario.hpp"
#include "tests/daemon/daemon_process.hpp"
#include "tests/daemon/ground_station.hpp"
#include "tests/daemon/obstacle_reach.hpp"

namespace skyroute::testing {

struct SoakWindow {
  std::vector<double> answer_ms;  // update -> the crossed vehicle's answer
  long rss_max_kb = 0;
  int missing = 0;                // no answer after 5 s
  double heartbeat_gap_s = 0.0;   // longest interval between two heartbeats in the window
};

struct SoakSummary {
  std::vector<SoakWindow> windows;
  int revisions_lost = 0;
  int revisions_superseded = 0;
  std::size_t revisions_published = 0;  // replans and holds, from the daemon's log
  std::size_t requests = 0;
  std::size_t requests_unanswered = 0;  // no terminal status by the end
  bool daemon_running = true;

  int missing() const {
    int n = 0;
    for (const SoakWindow& w : windows) n += w.missing;
    return n;
  }
  double longestHeartbeatGapS() const {
    double gap = 0.0;
    for (const SoakWindow& w : windows) gap = std::max(gap, w.heartbeat_gap_s);
    return gap;
  }
  // The window RSS growth is measured from: the first one ends the warm-up (missions planned,
  // caches, allocator arenas and per-mission search maps filled), and with short windows it may
  // end before the warm-up does (a 30 s window: 86.9 MiB, then 90.1, 92.2, 92.1; with 60 s
  // windows 91.4, 93.3, 93.8, 93.8), so with three windows or more growth counts from the second.
  const SoakWindow& rssBaseWindow() const { return windows.size() >= 3 ? windows[1] : windows.front(); }
  // RSS growth from the base window to the last.
  double rssGrowth() const {
    if (windows.size() < 2 || rssBaseWindow().rss_max_kb <= 0) return 0.0;
    return static_cast<double>(windows.back().rss_max_kb) / static_cast<double>(rssBaseWindow().rss_max_kb) - 1.0;
  }
};

inline double soakPercentile(std::vector<double> v, double f) {
  if (v.empty()) return NAN;
  std::sort(v.begin(), v.end());
  const auto rank = static_cast<std::size_t>(std::ceil(f * static_cast<double>(v.size())));
  return v[std::min(v.size() - 1, rank == 0 ? 0 : rank - 1)];
}

inline double longestHeartbeatGapS(const Station& station, std::size_t from) {
  double gap = 0.0;
  for (std::size_t i = from + 1; i < station.heartbeat_stamps_ns.size(); ++i) {
    gap = std::max(gap, static_cast<double>(station.heartbeat_stamps_ns[i] - station.heartbeat_stamps_ns[i - 1]) * 1e-9);
  }
  return gap;
}

// The ground station's side of the soak: missions, updates, and matching answers as they arrive.
class Soak {
 public:
  static constexpr int kVehicles = 20;
  using Clock = std::chrono::steady_clock;

  Soak(Station& station, const Heightfield& terrain) : station_(station), terrain_(terrain) {}

  void askAll() {
    for (int v = 0; v < kVehicles; ++v) ask(v);
  }
  // Asks again for every vehicle whose trajectory ends within 30 s.
  void renewMissions() {
    const std::int64_t soon_ns = utcNowNs() + 30'000'000'000LL;
    for (int v = 0; v < kVehicles; ++v) {
      const TrajectoryData* t = station_.lastReceived(name(v));
      if (t && t->samples.back().utc_ns < soon_ns && !waiting_[v]) ask(v);
    }
  }
  void writeUpdate(std::uint64_t k) {
    const int v = static_cast<int>(k % kVehicles);
    const TrajectoryData* t = station_.lastReceived(name(v));
    if (!t || waiting_[v]) return;
    const ObstacleUpdateData u =
        bench::crossing(*t, utcNowNs(), 1 + static_cast<std::uint64_t>(v), 15.0 + static_cast<double>(k % 4) * 5.0);
    if (obstacleMeets(*t, u, utcNowNs(), 45.0, 5.0)) pending_.push_back({name(v), t->revision, t->plan_id, Clock::now()});
    (void)station_.obstacles->write(u);
  }
  // Matches the trajectories and statuses that arrived since the last call.
  void collect(SoakWindow& w) {
    for (; traj_seen_ < station_.trajectory_log.size(); ++traj_seen_) {
      const TrajectoryData& t = station_.trajectory_log[traj_seen_];
      auto [it, fresh] = received_.try_emplace(t.request_id, t.revision);
      if (!fresh) {
        if (t.revision > it->second + 1) superseded_ += static_cast<int>(t.revision - it->second - 1);
        it->second = std::max(it->second, t.revision);
      }
      if (!ours(t.vehicle_id)) continue;  // another station's vehicle on the same domain
      if (t.revision == 0) waiting_[index(t.vehicle_id)] = false;
      answer(w, t.vehicle_id, station_.trajectory_times[traj_seen_], [&](const Pending& p) {
        return t.plan_id != p.plan_id || t.revision > p.revision;
      });
    }
    for (; status_seen_ < station_.status_log.size(); ++status_seen_) {
      const PlanStatusData& s = station_.status_log[status_seen_];
      if (!ours(s.vehicle_id)) continue;
      if (isTerminal(s.state) && s.state != PlanState::kSucceeded) {
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
  // Revisions the daemon's log says it published for the plan in force at each vehicle but newer
  // than the trajectory there; `published` counts them all.
  int lostRevisions(const std::string& daemon_log, std::size_t* published) const {
    std::map<std::string, std::uint32_t> newest;  // plan id -> highest revision published
    std::size_t count = 0;
    std::istringstream lines(daemon_log);
    for (std::string l; std::getline(lines, l);) {
      if (l.find("event=replanned ") == std::string::npos && l.find("event=replan_hold ") == std::string::npos) continue;
      const std::size_t plan = l.find(" plan="), revision = l.find(" revision=");
      if (plan == std::string::npos || revision == std::string::npos) continue;
      const std::string plan_id = l.substr(plan + 6, l.find(' ', plan + 6) - (plan + 6));
      std::uint32_t& n = newest[plan_id];
      n = std::max(n, static_cast<std::uint32_t>(std::stoul(l.substr(revision + 10))));
      ++count;
    }
    if (published) *published = count;
    int lost = 0;
    for (int v = 0; v < kVehicles; ++v) {
      const TrajectoryData* t = station_.lastReceived(name(v));
      if (!t) continue;
      const auto found = newest.find(t->plan_id);
      if (found != newest.end() && found->second > t->revision) lost += static_cast<int>(found->second - t->revision);
    }
    return lost;
  }
  int superseded() const { return superseded_; }
  std::size_t requests() const { return asked_.size(); }
  std::size_t unansweredRequests() const {
    std::size_t n = 0;
    for (const std::string& id : asked_) n += station_.terminal(id) ? 0 : 1;
    return n;
  }

 private:
  struct Pending {  // an update waiting for its vehicle's answer
    std::string vehicle;
    std::uint32_t revision;
    std::string plan_id;
    Clock::time_point t0;
  };

  static std::string name(int v) { return "uav-" + std::to_string(v); }
  static int index(const std::string& vehicle) { return std::stoi(vehicle.substr(4)); }
  static bool ours(const std::string& vehicle) {
    if (vehicle.size() < 5 || vehicle.size() > 6 || vehicle.rfind("uav-", 0) != 0) return false;
    for (std::size_t i = 4; i < vehicle.size(); ++i) {
      if (vehicle[i] < '0' || vehicle[i] > '9') return false;
    }
    return index(vehicle) < kVehicles;
  }
  void ask(int v) {
    asked_.push_back("soak-" + std::to_string(asked_.size()));
    waiting_[v] = true;
    (void)station_.requests->write(bench::laneMission(terrain_, asked_.back(), v, kVehicles));
  }
  // Keeps each vehicle's last trajectory received (an hour of revisions would not fit in memory;
  // Station::lastReceived is still the one in force) and no statuses but the
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
  void answer(SoakWindow& w, const std::string& vehicle, Clock::time_point at, Answers answers) {
    for (auto it = pending_.begin(); it != pending_.end();) {
      if (it->vehicle == vehicle && at >= it->t0 && answers(*it)) {
        w.answer_ms.push_back(std::chrono::duration<double, std::milli>(at - it->t0).count());
        it = pending_.erase(it);
      } else {
        ++it;
      }
    }
  }

  Station& station_;
  const Heightfield& terrain_;
  std::vector<Pending> pending_;
  std::map<std::string, std::uint32_t> received_;  // request id -> highest revision received
  std::map<int, bool> waiting_;                    // vehicle asked again, no trajectory yet
  std::vector<std::string> asked_;
  std::size_t traj_seen_ = 0, status_seen_ = 0;
  int superseded_ = 0;
};

// Runs the soak for `minutes` in windows of `window_s`; `on_window` sees each window as it ends
// (the benchmark prints it). The daemon must already serve the station.
inline SoakSummary runSoak(Station& station, ChildProcess& daemon, const Heightfield& terrain, double minutes,
                           double window_s, const std::function<void(int, const SoakWindow&)>& on_window = {}) {
  using Clock = Soak::Clock;
  Soak soak(station, terrain);
  SoakSummary summary;
  soak.askAll();
  station.pumpUntil([&] { return station.trajectory_log.size() >= Soak::kVehicles; }, 120.0);
  const auto start = Clock::now();
  std::uint64_t k = 0;
  for (int w = 0; Clock::now() - start < std::chrono::duration<double>(minutes * 60.0); ++w) {
    SoakWindow window;
    const std::size_t heartbeat_from = station.heartbeat_stamps_ns.size();
    const auto window_end =
        start + std::chrono::duration_cast<Clock::duration>(std::chrono::duration<double>((w + 1) * window_s));
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
    if (on_window) on_window(w + 1, window);
    summary.windows.push_back(std::move(window));
    if (!daemon.running()) break;
  }
  // The answers still under way (an update unanswered 5 s after it was written is missing),
  // then the last statuses and trajectories; they count in the last window.
  SoakWindow drain;
  station.pumpUntil([] { return false; }, 6.0);
  soak.collect(drain);
  if (!summary.windows.empty()) {
    SoakWindow& last = summary.windows.back();
    last.answer_ms.insert(last.answer_ms.end(), drain.answer_ms.begin(), drain.answer_ms.end());
    last.missing += drain.missing;
  }
  summary.revisions_lost = soak.lostRevisions(daemon.err(), &summary.revisions_published);
  summary.revisions_superseded = soak.superseded();
  summary.requests = soak.requests();
  summary.requests_unanswered = soak.unansweredRequests();
  summary.daemon_running = daemon.running();
  return summary;
}

}  // namespace skyroute::testing
