// Daemons in a shard group (service.shard_group), end to end: three skyrouted processes on one
// domain split thirty vehicles so that each vehicle is planned and answered by exactly one of them
// (counted by the PlanStatus writers, service_id, and the trajectory writers, source_instance,
// per vehicle). One is killed (SIGKILL) while its vehicles fly: each of them gets its next
// revision from a survivor, of the same plan and numbered right after the last one (no gap, no
// repeat), and afterwards only that survivor plans it. A fleet request is planned by one daemon
// for all its vehicles. A daemon that joins takes new requests and leaves the others in place.
// A shard killed and restarted on its journal (--state-dir) still has its copies of the requests
// it read: when the owner of some of those vehicles dies later, it takes over the ones it ranks
// next for. A shard paused (SIGSTOP) longer than its lease, whose vehicles the others take over
// meanwhile, publishes none of them when it runs again, and no plan id and revision ever stand
// for two different trajectories. DDS domains 131-134 and 232.
#include <gtest/gtest.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <csignal>
#include <cstdint>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <map>
#include <optional>
#include <set>
#include <string>
#include <utility>
#include <vector>

#include "service/shard_assignment.hpp"
#include "tests/daemon/daemon_fixture.hpp"
#include "tests/daemon/obstacle_reach.hpp"

namespace skyroute::testing {
namespace {

using Clock = std::chrono::steady_clock;

std::size_t countOf(const std::string& text, const std::string& what) {
  std::size_t n = 0;
  for (std::size_t at = text.find(what); at != std::string::npos; at = text.find(what, at + 1)) ++n;
  return n;
}

// What a trajectory says, whoever sent it and whenever: its samples' times and positions (to the
// millimetre), hashed (FNV-1a 64). A revision sent again unchanged hashes alike.
std::uint64_t contentHash(const TrajectoryData& t) {
  std::uint64_t h = 14695981039346656037ULL;
  const auto mix = [&h](std::int64_t value) {
    for (int byte = 0; byte < 8; ++byte) {
      h ^= (static_cast<std::uint64_t>(value) >> (8 * byte)) & 0xffU;
      h *= 1099511628211ULL;
    }
  };
  mix(static_cast<std::int64_t>(t.samples.size()));
  for (const TrajectorySampleData& s : t.samples) {
    mix(s.utc_ns);
    for (int axis = 0; axis < 3; ++axis) mix(std::llround(s.position_enu_m[axis] * 1000.0));
  }
  return h;
}

double durationS(const TrajectoryData& t) {
  return t.samples.empty() ? 0.0 : static_cast<double>(t.samples.back().utc_ns - t.samples.front().utc_ns) * 1e-9;
}

class ShardE2E : public DaemonFixture {
 protected:
  void TearDown() override {
    for (ChildProcess& shard : shards_) {
      if (shard.running()) {
        shard.signal(SIGTERM);
        EXPECT_EQ(shard.wait(10.0), 0) << shard.err();
      }
    }
    for (const std::string& path : config_paths_) std::filesystem::remove(path);
    for (const std::string& dir : state_dirs_) std::filesystem::remove_all(dir);
    DaemonFixture::TearDown();
  }

  static std::string serviceId(std::size_t i) { return std::string("shard-") + static_cast<char>('a' + i); }

  // Starts shard i on `domain_` (its service id in a configuration file, the group on the command
  // line), with a state journal of its own when journaled_ is set.
  void spawnShard(std::size_t i) {
    const std::string path = e2eTempPath("shard_" + std::to_string(domain_) + "_" + serviceId(i) + ".toml");
    std::ofstream(path) << "[dds]\nservice_id = \"" << serviceId(i) << "\"\n";
    config_paths_.push_back(path);
    if (shards_.size() <= i) shards_.resize(i + 1);
    std::vector<std::string> argv{SKYROUTED, "--domain", std::to_string(domain_), "--config", path, "--shard-group", "g"};
    if (journaled_) {
      const std::string dir = e2eTempPath("shard_state_" + std::to_string(domain_) + "_" + serviceId(i));
      if (std::find(state_dirs_.begin(), state_dirs_.end(), dir) == state_dirs_.end()) {
        std::filesystem::remove_all(dir);
        state_dirs_.push_back(dir);
      }
      argv.insert(argv.end(), {"--state-dir", dir});
    }
    // A restarted shard writes to its predecessor's log files: those go (with it) first.
    shards_[i] = ChildProcess();
    shards_[i] = ChildProcess::spawn(argv, "skyrouted_" + std::to_string(domain_) + "_" + serviceId(i));
    ASSERT_TRUE(shards_[i].started());
  }

  // Waits until shards 0..n-1 all serve and each sees all of them as settled members; then one
  // join margin more, so every one of them owns the requests that follow.
  void waitForGroup(std::size_t n) {
    std::string members;
    for (std::size_t i = 0; i < n; ++i) members += (i ? "," : "") + serviceId(i);
    for (std::size_t i = 0; i < n; ++i) {
      const std::string line = "members=[" + members + "] self=" + serviceId(i) + " settled=true";
      ASSERT_TRUE(station_->pumpUntil(
          [&] { return shards_[i].err().find(line) != std::string::npos || !shards_[i].running(); }, 60.0))
          << serviceId(i) << " never saw " << line << "\n" << shards_[i].err();
      ASSERT_TRUE(shards_[i].running()) << shards_[i].err();
    }
    ASSERT_TRUE(station_->requests->waitForReaders(static_cast<std::uint32_t>(n), 20.0).ok());
    ASSERT_TRUE(station_->trajectories->waitForWriters(static_cast<std::uint32_t>(n), 20.0).ok());
    ASSERT_TRUE(station_->statuses->waitForWriters(static_cast<std::uint32_t>(n), 20.0).ok());
    station_->pumpUntil([] { return false; }, 1.1);  // the join margin (MissionService::kShardJoinMarginS)
  }

  void startGroup(int domain, std::size_t n) {
    domain_ = domain;
    for (std::size_t i = 0; i < n; ++i) spawnShard(i);
    station_ = Station::open(domain);
    ASSERT_TRUE(station_);
    waitForGroup(n);
  }

  // A short mission in its own lane, so vehicles never meet.
  MissionRequestData laneMission(const std::string& vehicle, int lane, const std::string& prefix = "req-") const {
    MissionRequestData m;
    m.request_id = prefix + vehicle;
    m.vehicle_id = vehicle;
    const double north = -2900.0 + 200.0 * lane;
    m.begin = above(-1500, north, 300);
    m.points = {above(0, north + 80, 300)};
    m.end = above(1500, north, 300);
    return m;
  }

  void sendMissions(const std::vector<std::string>& vehicles, int first_lane, const std::string& prefix = "req-") {
    for (std::size_t i = 0; i < vehicles.size(); ++i) {
      ASSERT_TRUE(station_->requests->write(laneMission(vehicles[i], first_lane + static_cast<int>(i), prefix)).ok());
    }
    std::vector<std::string> ids;
    for (const std::string& v : vehicles) ids.push_back(prefix + v);
    ASSERT_TRUE(station_->waitTerminal(ids, 180.0)) << logs();
    for (const std::string& id : ids) ASSERT_EQ(station_->terminal(id)->state, PlanState::kSucceeded) << id;
    ASSERT_TRUE(station_->pumpUntil(
        [&] {
          return std::all_of(vehicles.begin(), vehicles.end(), [&](const auto& v) {
            for (const TrajectoryData& t : station_->trajectory_log)
              if (t.vehicle_id == v && t.request_id == prefix + v) return true;
            return false;
          });
        },
        10.0))
        << logs();
  }

  // The service ids that wrote a status for the vehicle, and the instances that wrote its trajectories.
  std::set<std::string> statusWriters(const std::string& vehicle) const {
    std::set<std::string> out;
    for (const PlanStatusData& s : station_->status_log)
      if (s.vehicle_id == vehicle) out.insert(s.service_id);
    return out;
  }
  std::set<std::string> statusWritersOf(const std::string& request_id) const {
    std::set<std::string> out;
    for (const PlanStatusData& s : station_->status_log)
      if (s.request_id == request_id) out.insert(s.service_id);
    return out;
  }
  std::set<std::string> trajectoryWriters(const std::string& vehicle, std::size_t from_entry = 0) const {
    std::set<std::string> out;
    for (std::size_t i = from_entry; i < station_->trajectory_log.size(); ++i)
      if (station_->trajectory_log[i].vehicle_id == vehicle) out.insert(station_->trajectory_log[i].source_instance);
    return out;
  }
  std::string logs() const {
    std::string out;
    for (std::size_t i = 0; i < shards_.size(); ++i) out += "--- " + serviceId(i) + ":\n" + shards_[i].err() + "\n";
    return out + killed_log_;
  }

  // The instance id shard i logged when it became active (its trajectories' source_instance).
  std::string activeInstance(std::size_t i) const {
    const std::string& log = shards_[i].err();
    const std::string marker = "event=active service_id=" + serviceId(i) + " domain=" + std::to_string(domain_) + " instance=";
    const std::size_t at = log.rfind(marker);
    if (at == std::string::npos) return {};
    const std::size_t from = at + marker.size();
    return log.substr(from, log.find_first_of(" \n", from) - from);
  }

  // Kills shard i (SIGKILL) and keeps its log for the failure messages.
  void killShard(std::size_t i) {
    shards_[i].signal(SIGKILL);
    ASSERT_EQ(shards_[i].wait(10.0), 128 + SIGKILL);
    killed_log_ += "--- killed " + serviceId(i) + ":\n" + shards_[i].err();
  }

  int domain_ = 0;
  bool journaled_ = false;
  std::vector<ChildProcess> shards_;
  std::vector<std::string> config_paths_;
  std::vector<std::string> state_dirs_;
  std::string killed_log_;
};

TEST_F(ShardE2E, ThreeShardsPlanEachVehicleOnceAndTheSurvivorsResumeAKilledShardsVehicles) {
  ASSERT_NO_FATAL_FAILURE(startGroup(131, 3));
  std::vector<std::string> vehicles;
  for (int i = 0; i < 30; ++i) vehicles.push_back("s-" + std::to_string(100 + i));
  ASSERT_NO_FATAL_FAILURE(sendMissions(vehicles, 0));

  // Exactly one daemon answers and plans each vehicle, and each daemon has some.
  std::map<std::string, std::vector<std::string>> vehicles_of;  // service id -> its vehicles
  std::map<std::string, std::string> instance_of;               // service id -> its instance id
  for (const std::string& v : vehicles) {
    const std::set<std::string> writers = statusWriters(v);
    ASSERT_EQ(writers.size(), 1u) << v << " has statuses from " << writers.size() << " daemons\n" << logs();
    EXPECT_EQ(trajectoryWriters(v).size(), 1u) << v;
    vehicles_of[*writers.begin()].push_back(v);
    for (const PlanStatusData& s : station_->status_log)
      if (s.vehicle_id == v) instance_of[s.service_id] = s.service_instance;
  }
  std::size_t plans = 0;
  for (std::size_t i = 0; i < 3; ++i) {
    EXPECT_GE(vehicles_of[serviceId(i)].size(), 3u) << serviceId(i) << " plans too few of the 30 vehicles";
    plans += countOf(shards_[i].err(), "event=plan_succeeded");
  }
  EXPECT_EQ(plans, vehicles.size()) << "every vehicle planned once in all";

  // Kill the shard with the most vehicles while they fly.
  const auto victim_it = std::max_element(vehicles_of.begin(), vehicles_of.end(),
                                          [](const auto& a, const auto& b) { return a.second.size() < b.second.size(); });
  const std::string victim = victim_it->first;
  const std::vector<std::string> moved = victim_it->second;
  const std::size_t victim_index = static_cast<std::size_t>(victim.back() - 'a');
  std::map<std::string, TrajectoryData> last;  // the revision in force when it died
  for (const std::string& v : moved) last[v] = *station_->latest(v);
  const std::size_t log_mark = station_->trajectory_log.size();
  const auto killed = Clock::now();
  shards_[victim_index].signal(SIGKILL);
  ASSERT_EQ(shards_[victim_index].wait(10.0), 128 + SIGKILL);
  killed_log_ = "--- killed " + victim + ":\n" + shards_[victim_index].err();
  ChildProcess gone = std::move(shards_[victim_index]);

  // Each of its vehicles: the next revision of the same plan from a survivor.
  std::map<std::string, double> moved_after_s;
  auto taken = [&](const std::string& v) {
    for (std::size_t i = log_mark; i < station_->trajectory_log.size(); ++i) {
      const TrajectoryData& t = station_->trajectory_log[i];
      if (t.vehicle_id == v && t.source_instance != instance_of[victim]) {
        if (!moved_after_s.contains(v)) {
          moved_after_s[v] = std::chrono::duration<double>(station_->trajectory_times[i] - killed).count();
        }
        return true;
      }
    }
    return false;
  };
  ASSERT_TRUE(station_->pumpUntil([&] { return std::all_of(moved.begin(), moved.end(), taken); }, 30.0)) << logs();
  double slowest_s = 0.0;
  for (const std::string& v : moved) {
    slowest_s = std::max(slowest_s, moved_after_s[v]);
    const TrajectoryData* first_new = nullptr;
    for (std::size_t i = log_mark; i < station_->trajectory_log.size() && !first_new; ++i) {
      const TrajectoryData& t = station_->trajectory_log[i];
      if (t.vehicle_id == v && t.source_instance != instance_of[victim]) first_new = &t;
    }
    ASSERT_NE(first_new, nullptr);
    EXPECT_EQ(first_new->plan_id, last[v].plan_id) << v;
    EXPECT_EQ(first_new->revision, last[v].revision + 1) << v << ": the survivor's first revision";
    EXPECT_EQ(first_new->request_id, last[v].request_id) << v;
  }
  std::cout << "[ shard ] " << moved.size() << " vehicles of " << victim << " moved; the last one's new revision "
            << slowest_s << " s after the kill\n";
  EXPECT_LT(slowest_s, 2.0) << "vehicles of a killed shard should move within 2 s\n" << logs();

  // Settled: for two more seconds every vehicle is written by one daemon only, and each moved
  // vehicle was resumed by one survivor.
  const std::size_t settled_mark = station_->trajectory_log.size();
  station_->pumpUntil([] { return false; }, 2.0);
  std::string survivors_log;
  for (std::size_t i = 0; i < 3; ++i)
    if (i != victim_index) survivors_log += shards_[i].err();
  for (const std::string& v : vehicles) {
    EXPECT_LE(trajectoryWriters(v, settled_mark).size(), 1u) << v << " written by two daemons after the move";
    EXPECT_LE(statusWriters(v).size(), 1u) << v;
  }
  for (const std::string& v : moved) {
    EXPECT_EQ(countOf(survivors_log, "event=flight_resumed request=req-" + v + " "), 1u) << v << "\n" << logs();
    EXPECT_EQ(trajectoryWriters(v, log_mark).size(), 1u) << v;
  }
}

TEST_F(ShardE2E, FleetRequestAcrossTheShardsIsPlannedByOneDaemon) {
  ASSERT_NO_FATAL_FAILURE(startGroup(132, 3));
  dds::Writer<FleetRequestData> fleets = dds::Writer<FleetRequestData>::create(station_->participant.get()).value();
  ASSERT_TRUE(fleets.waitForReaders(3, 20.0).ok());
  FleetRequestData r;
  r.request_id = "fleet-shards";
  r.vehicle_ids = {"f-1", "f-2", "f-3", "f-4"};
  r.begins = {above(-4000, -4000, 100), above(4000, -4000, 100), above(-4000, 4000, 100), above(4000, 4000, 100)};
  r.ends = r.begins;
  r.tasks = {above(-2500, -1500, 150), above(-1000, -3000, 150), above(1500, -2500, 150), above(3000, -1000, 150),
             above(2500, 1500, 150), above(-3000, 1000, 150), above(-1500, 3000, 150), above(0, 0, 150)};
  ASSERT_TRUE(fleets.write(r).ok());
  ASSERT_TRUE(station_->pumpUntil(
      [&] {
        return std::all_of(r.vehicle_ids.begin(), r.vehicle_ids.end(), [&](const std::string& v) {
          const TrajectoryData* t = station_->latest(v);
          return t && t->request_id == r.request_id;
        });
      },
      120.0))
      << logs();
  station_->pumpUntil([] { return false; }, 0.5);
  std::set<std::string> writers;
  for (const std::string& v : r.vehicle_ids) {
    const std::set<std::string> of_v = trajectoryWriters(v);
    writers.insert(of_v.begin(), of_v.end());
  }
  EXPECT_EQ(writers.size(), 1u) << "one daemon writes every vehicle of the fleet";
  std::size_t planners = 0;
  for (std::size_t i = 0; i < 3; ++i) planners += countOf(shards_[i].err(), "event=fleet_accepted request=fleet-shards");
  EXPECT_EQ(planners, 1u) << logs();

  // skyroute status lists the group's members.
  const Ran status = runToEnd({SKYROUTE_CLI, "status", "--domain", "132", "--wait", "5"}, "shard_status", 30.0);
  ASSERT_EQ(status.code, 0) << status.err;
  for (std::size_t i = 0; i < 3; ++i) {
    EXPECT_EQ(countOf(status.out, "service=" + serviceId(i) + " "), 1u) << status.out;
  }
  EXPECT_EQ(countOf(status.out, "shard_group=g "), 3u) << status.out;
}

TEST_F(ShardE2E, AJoiningShardTakesNewRequestsAndLeavesTheFlyingOnesInPlace) {
  ASSERT_NO_FATAL_FAILURE(startGroup(133, 2));
  std::vector<std::string> before;
  for (int i = 0; i < 8; ++i) before.push_back("j-" + std::to_string(100 + i));
  ASSERT_NO_FATAL_FAILURE(sendMissions(before, 0));
  std::map<std::string, std::string> writer_before;
  for (const std::string& v : before) writer_before[v] = *trajectoryWriters(v).begin();

  ASSERT_NO_FATAL_FAILURE(spawnShard(2));
  ASSERT_NO_FATAL_FAILURE(waitForGroup(3));
  std::vector<std::string> after;
  for (int i = 0; i < 12; ++i) after.push_back("k-" + std::to_string(100 + i));
  const std::size_t join_mark = station_->trajectory_log.size();
  ASSERT_NO_FATAL_FAILURE(sendMissions(after, 8));
  station_->pumpUntil([] { return false; }, 1.0);

  for (const std::string& v : before) {
    const std::set<std::string> writers = trajectoryWriters(v, join_mark);
    EXPECT_TRUE(writers.empty() || (writers.size() == 1 && *writers.begin() == writer_before[v]))
        << v << " changed hands when a daemon joined";
  }
  std::size_t by_joiner = 0;
  for (const std::string& v : after) {
    ASSERT_EQ(statusWriters(v).size(), 1u) << v << "\n" << logs();
    EXPECT_EQ(trajectoryWriters(v).size(), 1u) << v;
    if (*statusWriters(v).begin() == serviceId(2)) ++by_joiner;
  }
  EXPECT_GE(by_joiner, 1u) << "the joined daemon plans some of the new vehicles";
  for (std::size_t i = 0; i < 3; ++i) EXPECT_EQ(countOf(shards_[i].err(), "event=vehicle_moved"), 0u) << serviceId(i);

  // New requests for the old vehicles: each goes to the owner of its new request, and a vehicle
  // that changes hands between two live daemons is let go by the old one (its trajectory instance
  // unregistered), so the ground station follows the new owner's plan and nobody else's.
  const std::size_t again_mark = station_->trajectory_log.size();
  ASSERT_NO_FATAL_FAILURE(sendMissions(before, 0, "again-"));
  station_->pumpUntil([] { return false; }, 1.0);
  std::size_t changed_hands = 0;
  for (const std::string& v : before) {
    const std::set<std::string> answered = statusWritersOf("again-" + v);
    ASSERT_EQ(answered.size(), 1u) << v;
    const std::set<std::string> writers = trajectoryWriters(v, again_mark);
    EXPECT_EQ(writers.size(), 1u) << v << " written by two daemons after its new request";
    ASSERT_NE(station_->latest(v), nullptr);
    // The station holds the new plan (the one with the highest revision may be the old plan's).
    const TrajectoryData* last = nullptr;
    for (std::size_t i = again_mark; i < station_->trajectory_log.size(); ++i)
      if (station_->trajectory_log[i].vehicle_id == v) last = &station_->trajectory_log[i];
    ASSERT_NE(last, nullptr);
    EXPECT_EQ(last->request_id, "again-" + v);
    const std::string old_owner = *statusWritersOf("req-" + v).begin();  // who answered its first request
    const std::string new_owner = *answered.begin();
    const std::string moved_line = "event=vehicle_moved vehicle=" + v + " from=" + old_owner + " to=" + new_owner;
    const std::string& old_log = shards_[static_cast<std::size_t>(old_owner.back() - 'a')].err();
    if (new_owner != old_owner) {
      ++changed_hands;
      EXPECT_EQ(countOf(old_log, moved_line), 1u) << "the old owner logs the move\n" << logs();
    } else {
      EXPECT_EQ(countOf(old_log, "event=vehicle_moved vehicle=" + v + " "), 0u) << v;
    }
  }
  std::cout << "[ shard ] " << changed_hands << " of " << before.size() << " vehicles changed hands with their new request\n";
  EXPECT_GE(changed_hands, 1u) << "the test needs a vehicle that changes hands";
}

TEST_F(ShardE2E, AShardRestartedOnItsJournalTakesOverTheVehiclesItRanksNextForWhenTheirOwnerDies) {
  journaled_ = true;
  ASSERT_NO_FATAL_FAILURE(startGroup(134, 3));
  std::vector<std::string> vehicles;
  for (int i = 0; i < 15; ++i) vehicles.push_back("r-" + std::to_string(100 + i));
  ASSERT_NO_FATAL_FAILURE(sendMissions(vehicles, 0));
  // Two heartbeats: shard-c's journal then says it read every request up to after these.
  station_->pumpUntil([] { return false; }, 2.5);

  // shard-c is killed; the survivors take its vehicles, then it comes back on its journal.
  constexpr std::size_t kC = 2;
  const std::string old_c = activeInstance(kC);
  ASSERT_FALSE(old_c.empty()) << shards_[kC].err();
  std::size_t mark = station_->trajectory_log.size();
  ASSERT_NO_FATAL_FAILURE(killShard(kC));
  std::vector<std::string> of_c;
  for (const std::string& v : vehicles)
    if (trajectoryWriters(v) == std::set<std::string>{old_c}) of_c.push_back(v);
  const auto written_since = [&](const std::string& v, std::size_t from, const std::string& instance) {
    for (std::size_t i = from; i < station_->trajectory_log.size(); ++i)
      if (station_->trajectory_log[i].vehicle_id == v && station_->trajectory_log[i].source_instance == instance) return true;
    return false;
  };
  ASSERT_TRUE(station_->pumpUntil(
      [&] {
        return std::all_of(of_c.begin(), of_c.end(), [&](const std::string& v) {
          return !trajectoryWriters(v, mark).empty() && !written_since(v, mark, old_c);
        });
      },
      20.0))
      << logs();
  ASSERT_NO_FATAL_FAILURE(spawnShard(kC));
  ASSERT_TRUE(station_->pumpUntil(
      [&] {
        return shards_[kC].err().find("members=[shard-a,shard-b,shard-c] self=shard-c settled=true") != std::string::npos ||
               !shards_[kC].running();
      },
      60.0))
      << shards_[kC].err();
  ASSERT_TRUE(shards_[kC].running()) << shards_[kC].err();
  EXPECT_NE(shards_[kC].err().find("event=shard_copies_recovered requests=" + std::to_string(vehicles.size()) + " past_lives=1"),
            std::string::npos)
      << shards_[kC].err();
  const std::string new_c = activeInstance(kC);
  ASSERT_FALSE(new_c.empty());
  // Back, it takes the vehicles it ranks first for again (their owners let go of them).
  ASSERT_TRUE(station_->pumpUntil(
      [&] { return std::all_of(of_c.begin(), of_c.end(), [&](const std::string& v) { return written_since(v, mark, new_c); }); },
      10.0))
      << logs();
  station_->pumpUntil([] { return false; }, 1.0);

  // The shard (a or b) owning most of the vehicles for which shard-c ranks next.
  std::map<std::string, std::vector<std::string>> next_is_c;  // owner -> its vehicles for which shard-c ranks next
  for (const std::string& v : vehicles) {
    const TrajectoryData* latest = station_->latest(v);
    ASSERT_NE(latest, nullptr);
    for (std::size_t i = 0; i < kC; ++i) {
      if (latest->source_instance != activeInstance(i)) continue;
      const std::string other = serviceId(1 - i);
      if (rendezvousOwner({other, serviceId(kC)}, "vehicle:" + v) == serviceId(kC)) next_is_c[serviceId(i)].push_back(v);
    }
  }
  const auto victim_it = std::max_element(next_is_c.begin(), next_is_c.end(),
                                          [](const auto& a, const auto& b) { return a.second.size() < b.second.size(); });
  ASSERT_NE(victim_it, next_is_c.end()) << "no vehicle for which shard-c ranks next";
  const std::string victim = victim_it->first;
  const std::vector<std::string> to_c = victim_it->second;
  const std::size_t victim_index = static_cast<std::size_t>(victim.back() - 'a');
  const std::string victim_instance = activeInstance(victim_index);
  std::map<std::string, TrajectoryData> last;
  for (const std::string& v : to_c) last[v] = *station_->latest(v);
  mark = station_->trajectory_log.size();
  ASSERT_NO_FATAL_FAILURE(killShard(victim_index));

  // shard-c resumes each of them: the next revision of the same plan, from its new instance.
  const auto resumed_by_c = [&](const std::string& v) { return written_since(v, mark, new_c); };
  ASSERT_TRUE(station_->pumpUntil([&] { return std::all_of(to_c.begin(), to_c.end(), resumed_by_c); }, 10.0))
      << "the restarted shard-c should take over " << to_c.size() << " vehicles of " << victim << "\n" << logs();
  for (const std::string& v : to_c) {
    const TrajectoryData* first_new = nullptr;
    for (std::size_t i = mark; i < station_->trajectory_log.size() && !first_new; ++i) {
      const TrajectoryData& t = station_->trajectory_log[i];
      if (t.vehicle_id == v && t.source_instance != victim_instance) first_new = &t;
    }
    ASSERT_NE(first_new, nullptr);
    EXPECT_EQ(first_new->source_instance, new_c) << v;
    EXPECT_EQ(first_new->plan_id, last[v].plan_id) << v;
    EXPECT_EQ(first_new->revision, last[v].revision + 1) << v << ": shard-c's first revision";
  }
  std::cout << "[ shard ] " << to_c.size() << " vehicles of " << victim << " taken over by the restarted shard-c\n";

  // Settled: one trajectory writer per vehicle, and one status writer per vehicle's request.
  const std::size_t settled_mark = station_->trajectory_log.size();
  station_->pumpUntil([] { return false; }, 1.5);
  for (const std::string& v : vehicles) {
    EXPECT_LE(trajectoryWriters(v, settled_mark).size(), 1u) << v << " written by two daemons after the move";
    EXPECT_EQ(statusWritersOf("req-" + v).size(), 1u) << v;
  }
}


// A shard paused (SIGSTOP) for 3 s, six times its liveliness lease, while it owns vehicles in
// flight: the others take them over meanwhile and replan one of them around an obstacle. When it
// runs again (SIGCONT) it must not publish any of them (nor answer for them), and no (plan id,
// revision) may ever reach the ground station with two different trajectories.
TEST_F(ShardE2E, AShardPausedPastItsLeasePublishesNoneOfTheVehiclesItLostAndNoRevisionHasTwoContents) {
  ASSERT_NO_FATAL_FAILURE(startGroup(232, 3));
  std::vector<std::string> vehicles;
  for (int i = 0; i < 6; ++i) vehicles.push_back("p-" + std::to_string(100 + i));
  ASSERT_NO_FATAL_FAILURE(sendMissions(vehicles, 0));

  // The shard with the most vehicles is paused.
  std::map<std::string, std::vector<std::string>> vehicles_of;  // service id -> its vehicles
  for (const std::string& v : vehicles) {
    const std::set<std::string> writers = statusWriters(v);
    ASSERT_EQ(writers.size(), 1u) << v << "\n" << logs();
    vehicles_of[*writers.begin()].push_back(v);
  }
  const auto paused_it = std::max_element(vehicles_of.begin(), vehicles_of.end(),
                                          [](const auto& a, const auto& b) { return a.second.size() < b.second.size(); });
  const std::string paused = paused_it->first;
  const std::vector<std::string> lost = paused_it->second;
  const std::size_t paused_index = static_cast<std::size_t>(paused.back() - 'a');
  const std::string paused_instance = activeInstance(paused_index);
  ASSERT_FALSE(paused_instance.empty()) << shards_[paused_index].err();
  const std::string& watched = lost.front();  // the vehicle the obstacles block

  // An obstacle on the vehicle's trajectory in force, at least 20 s and distance_m ahead of where
  // it is now (within the replanning horizon): its owner replans around it.
  const auto blockAhead = [&](std::uint64_t id, double distance_m) {
    const TrajectoryData* current = station_->lastReceived(watched);
    ASSERT_NE(current, nullptr);
    const std::optional<BlockAhead> block = testing::blockAhead(*current, id, distance_m, utcNowNs());
    ASSERT_TRUE(block) << "the trajectory of " << watched << " does not reach " << distance_m << " m further";
    EXPECT_TRUE(station_->obstacles->write(block->update).ok());
  };
  // The newest revision of `v` at the station, and whether one newer than `revision` has come,
  // from another daemon than the paused one when `others_only`.
  const auto newestRevision = [&](const std::string& v) {
    const TrajectoryData* t = station_->latest(v);
    return t ? t->revision : 0u;
  };
  const auto revisionAfter = [&](const std::string& v, std::uint32_t revision, bool others_only) {
    return std::any_of(station_->trajectory_log.begin(), station_->trajectory_log.end(), [&](const TrajectoryData& t) {
      return t.vehicle_id == v && t.revision > revision && (!others_only || t.source_instance != paused_instance);
    });
  };

  std::map<std::string, std::uint32_t> before_pause;
  for (const std::string& v : lost) before_pause[v] = newestRevision(v);
  const auto pause_started = Clock::now();
  shards_[paused_index].signal(SIGSTOP);
  // Its peers take every one of its vehicles over (their next revisions reach the station).
  ASSERT_TRUE(station_->pumpUntil(
      [&] {
        return std::all_of(lost.begin(), lost.end(),
                           [&](const auto& v) { return revisionAfter(v, before_pause[v], true); });
      },
      30.0))
      << "the vehicles of the paused " << paused << " were not taken over\n" << logs();
  // ... and one of them is replanned by its new owner around an obstacle, still during the pause.
  const std::uint32_t taken_revision = newestRevision(watched);
  ASSERT_NO_FATAL_FAILURE(blockAhead(1, 200.0));
  ASSERT_TRUE(station_->pumpUntil([&] { return revisionAfter(watched, taken_revision, true); }, 30.0))
      << watched << " was not replanned around the obstacle\n" << logs();
  station_->pumpUntil([&] { return Clock::now() - pause_started >= std::chrono::seconds(3); }, 10.0);
  const std::size_t resumed_mark = station_->trajectory_log.size();
  const std::size_t resumed_status_mark = station_->status_log.size();
  const double paused_s = std::chrono::duration<double>(Clock::now() - pause_started).count();
  shards_[paused_index].signal(SIGCONT);

  // Running again (its heartbeat reaches the station), every daemon, the paused one included,
  // reads a second obstacle ahead of the watched vehicle, and its owner answers it.
  const std::int64_t resumed_ns = utcNowNs();
  const auto beatSince = [&](const std::string& service_id, std::int64_t since_ns) {
    const auto beat = station_->heartbeat_of.find(service_id);
    return beat != station_->heartbeat_of.end() && beat->second.stamp_utc_ns >= since_ns;
  };
  ASSERT_TRUE(station_->pumpUntil([&] { return beatSince(paused, resumed_ns); }, 20.0))
      << paused << " did not heartbeat after SIGCONT\n" << logs();
  const std::int64_t second_obstacle_ns = utcNowNs();
  ASSERT_NO_FATAL_FAILURE(blockAhead(2, 400.0));
  // (Whatever happens from here, the checks below run: they say what went wrong.)
  EXPECT_TRUE(station_->pumpUntil(
      [&] {
        return std::any_of(station_->trajectory_log.begin() + static_cast<std::ptrdiff_t>(resumed_mark),
                           station_->trajectory_log.end(), [&](const TrajectoryData& t) {
                             return t.vehicle_id == watched && t.created_utc_ns >= second_obstacle_ns;
                           });
      },
      30.0))
      << watched << " was not replanned around the second obstacle";
  // Every daemon holds both obstacles, then heartbeats once more: the replanning cycle each ran
  // at once for the second one is over.
  for (std::size_t i = 0; i < 3; ++i) {
    const std::string id = serviceId(i);
    EXPECT_TRUE(station_->pumpUntil(
        [&] { return beatSince(id, second_obstacle_ns) && station_->heartbeat_of[id].obstacles >= 2; }, 20.0))
        << id << " never held the second obstacle";
    const std::int64_t held_ns = station_->heartbeat_of[id].stamp_utc_ns;
    EXPECT_TRUE(station_->pumpUntil([&] { return beatSince(id, held_ns + 1); }, 20.0)) << id;
  }

  // No (plan id, revision) with two different trajectories, ever.
  std::map<std::pair<std::string, std::uint32_t>, const TrajectoryData*> first_of;
  for (const TrajectoryData& t : station_->trajectory_log) {
    const auto [it, inserted] = first_of.emplace(std::make_pair(t.plan_id, t.revision), &t);
    if (inserted) continue;
    const TrajectoryData& earlier = *it->second;
    EXPECT_EQ(contentHash(earlier), contentHash(t))
        << "plan " << t.plan_id << " revision " << t.revision << " stands for two trajectories: " << durationS(earlier)
        << " s from " << earlier.source_instance << " and " << durationS(t) << " s from " << t.source_instance;
  }
  // The paused shard publishes none of the vehicles it lost, and answers for none of them.
  for (std::size_t i = resumed_mark; i < station_->trajectory_log.size(); ++i) {
    const TrajectoryData& t = station_->trajectory_log[i];
    if (std::find(lost.begin(), lost.end(), t.vehicle_id) == lost.end()) continue;
    EXPECT_NE(t.source_instance, paused_instance)
        << paused << " published " << t.vehicle_id << " (plan " << t.plan_id << " revision " << t.revision
        << ") after its pause although its peers had taken it over";
  }
  for (std::size_t i = resumed_status_mark; i < station_->status_log.size(); ++i) {
    const PlanStatusData& s = station_->status_log[i];
    if (std::find(lost.begin(), lost.end(), s.vehicle_id) == lost.end()) continue;
    EXPECT_NE(s.service_id, paused) << paused << " answered for " << s.vehicle_id << " after its pause";
  }
  EXPECT_NE(shards_[paused_index].err().find("event=shard_new_life cause=stall"), std::string::npos)
      << paused << " did not notice its pause\n" << shards_[paused_index].err();
  std::cout << "[ shard ] " << paused << " paused " << paused_s << " s with " << lost.size() << " vehicles; "
            << (station_->trajectory_log.size() - resumed_mark) << " trajectories after it ran again\n";
  if (HasFailure() || std::getenv("SKYROUTE_E2E_LOGS")) std::cout << logs();
}

}  // namespace
}  // namespace skyroute::testing
