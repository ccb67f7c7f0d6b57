// The daemon's state journal: what skyrouted needs to come back after a crash, in SQLite (WAL),
// one transaction per event, written before the event is published (write-ahead):
//   missions      every accepted request as accepted, until it fails, is cancelled, replaced by a
//                 newer mission of its vehicle, or its trajectory ends ("accepted" until its first
//                 trajectory, then "flying");
//   trajectories  each vehicle's current trajectory, its revision and every sample as published;
//   obstacles, no-fly zones in force (ended ones pruned), fleet allocations whose trajectories
//                 are still current, and the plan counter (plan ids never repeat after a restart);
//   shard_requests in a shard group, a copy of every request the shard read, whoever plans it:
//                 one per vehicle (its latest mission request) and per fleet still some
//                 vehicle's latest plan, forgotten on cancel;
//   shard_lives    when each of the shard's recent lives started and up to when it had read
//                 every request (shard_coverage.hpp).
// Rows are replaced in place, so the journal's size follows the vehicles and obstacles in force,
// not the daemon's age. Thread-safe: the engine's threads write, each call one transaction; a
// write that fails (a full disk) makes the journal unwritable until one succeeds (writable()).
// Every row carries a checksum; a damaged row is quarantined at load, never returned.
// Schema versions and what a refused file looks like: journal_schema.hpp.
#pragma once

#include <atomic>
#include <chrono>
#include <cstdint>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <vector>

#include "planning/core/result.hpp"
#include "service/mission_types.hpp"
#include "service/no_fly_zone_data.hpp"
#include "service/shard_coverage.hpp"
#include "service/sqlite_db.hpp"

namespace skyroute {

// A shard's copy of a request it read (docs/dds.md "Shards"): the key its router files it under,
// and when it arrived (which members may own it depends on that).
struct JournaledRequest {
  std::string key;
  std::int64_t seen_utc_ns = 0;
  std::optional<MissionRequestData> mission;
  std::optional<FleetRequestData> fleet;
};

// A record taken out of the journal's tables into its quarantine table (docs/journal.md
// "Damaged and refused records"): its table, its key (the table's key columns, in order) and why.
struct QuarantinedRecord {
  std::string table;
  std::vector<std::string> key;
  std::string reason;
};

// What a journal holds, as recovery reads it (ended trajectories and obstacles left out).
struct JournalState {
  struct Mission {
    MissionRequestData request;
    bool flying = false;  // its trajectory was published (else: accepted, never planned)
    std::int64_t flight_start_utc_ns = 0;  // when its first trajectory starts (0: not known)
  };
  std::vector<Mission> missions;                 // in the order they were accepted
  std::vector<TrajectoryData> trajectories;      // one per vehicle, as last published
  std::vector<ObstacleUpdateData> obstacles;
  std::vector<NoFlyZoneData> zones;
  std::vector<FleetStatusData> fleets;           // succeeded fleets with a current trajectory
  std::uint64_t plan_counter = 0;                // the highest plan number used so far
  std::string owner_instance_id;                 // the daemon instance that last opened it ("" = none)
  std::vector<JournaledRequest> shard_requests;  // a shard's copies, in the order they arrived
  std::vector<CoverageInterval> shard_lives;     // a shard's earlier lives, oldest first
  std::vector<QuarantinedRecord> quarantined;    // damaged records load() took out, not in the above
};

// Takes out of `state` what depends on a quarantined record, and appends those records: the
// trajectory of a quarantined mission (same vehicle and request), and the flying missions of a
// vehicle whose trajectory was quarantined (their flight cannot be resumed without it).
void quarantineDependents(JournalState& state, std::vector<QuarantinedRecord>& records);

// How long the write transactions took (the replanning cycle waits for the revision's).
struct JournalWriteStats {
  std::uint64_t writes = 0;
  double total_ms = 0.0;
  double max_ms = 0.0;
};

class StateJournal {
 public:
  static constexpr const char* kFileName = "journal.sqlite";
  // Opens DIR/journal.sqlite (creating DIR and the file when absent), checks and migrates it
  // (journal_schema.hpp). Errors name the file: kFileNotFound when it cannot be made or opened,
  // kParseError when it is damaged, not a journal, or from a newer skyrouted.
  static Result<std::unique_ptr<StateJournal>> open(const std::string& dir);

  const std::string& path() const { return db_->path(); }
  int foundSchemaVersion() const { return found_version_; }  // 0: the file was new

  // A request accepted for planning (before its acceptance is published).
  Status recordAccepted(const MissionRequestData& request, std::int64_t now_utc_ns);
  // A vehicle's new trajectory or revision (before it is published): its mission becomes flying,
  // an older mission of the vehicle ends. Prunes what ended by now_utc_ns (at most once a second).
  Status recordTrajectory(const TrajectoryData& trajectory, std::int64_t now_utc_ns);
  // A fleet's trajectories (each as recordTrajectory) and its allocation, in one transaction: all
  // of them are recorded, or none.
  Status recordFleetPlan(const std::vector<TrajectoryData>& trajectories, const FleetStatusData& status,
                         std::int64_t now_utc_ns);
  // A cancel (either id may be empty: any), before it takes effect: the missions it names and
  // their trajectories are removed.
  Status recordCancel(const std::string& vehicle_id, const std::string& request_id);
  // The vehicle's trajectory no longer holds (its mission was cancelled).
  Status recordRetracted(const std::string& vehicle_id);
  // The request failed or was cancelled: it will not be planned again.
  Status recordFinished(const std::string& vehicle_id, const std::string& request_id);
  Status recordObstacle(const ObstacleUpdateData& update);
  Status recordNoFlyZone(const NoFlyZoneData& zone);
  // A fleet's allocation (kept while one of its trajectories is current).
  Status recordFleet(const FleetStatusData& status);
  // The daemon instance (ServiceInstance::instance_id) now writing the journal. After a crash its
  // successor knows the dead instance, which discovery still lists for a lease, by this id.
  Status recordOwner(const std::string& instance_id);

  // A shard's copy of a request it read (replacing the copy under the same key).
  Status recordShardRequest(const JournaledRequest& copy);
  // Copies the shard no longer keeps (plan keys), and the mission copy a cancel names (either id
  // may be empty: any).
  Status forgetShardRequests(const std::vector<std::string>& keys);
  Status forgetShardMission(const std::string& vehicle_id, const std::string& request_id);
  // A shard's new life, started at started_utc_ns: only the newest kMaxPastCoverage earlier lives
  // are kept. Then, as it goes, up to when it has read every request.
  Status beginShardLife(std::int64_t started_utc_ns);
  Status recordShardCoverage(std::int64_t started_utc_ns, std::int64_t covered_until_utc_ns);

  // Everything in force at now_utc_ns, after pruning what ended. A record whose checksum does not
  // match what it holds, or that does not decode, is not returned: it is moved to the quarantine
  // table (with what depends on it, quarantineDependents), logged by table and key
  // (event=journal_record_quarantined) and listed in JournalState::quarantined; the rest is read.
  // Errors: the file cannot be read.
  Result<JournalState> load(std::int64_t now_utc_ns);
  // Moves the records to the quarantine table, each with its reason, in one transaction, and logs
  // each. A move that fails (a full disk) is logged: the records are left out of the recovery
  // all the same, and found again at the next start.
  Status quarantine(const std::vector<QuarantinedRecord>& records, std::int64_t now_utc_ns);

  JournalWriteStats writeStats() const;
  // False while writes fail (the last write failed: a full disk, an I/O error); true again after
  // the next write that adds a row and succeeds. Transitions are logged (event=journal_unavailable / _available).
  bool writable() const { return writable_.load(); }

 private:
  StateJournal(std::unique_ptr<SqliteDb> db, int found_version) : db_(std::move(db)), found_version_(found_version) {}
  // Runs `body` in one transaction (rolled back when it fails) and times it. A transaction that
  // only removes rows (`adds` false) can succeed on a full disk: it marks the journal unwritable
  // when it fails, but does not mark it writable again.
  template <typename Body>
  Status transaction(const Body& body, bool adds = true);
  Status pruneLocked(std::int64_t now_utc_ns);
  Status writeTrajectoryLocked(const TrajectoryData& trajectory);

  mutable std::mutex mutex_;
  std::unique_ptr<SqliteDb> db_;
  int found_version_ = 0;
  std::int64_t last_prune_utc_ns_ = 0;
  JournalWriteStats stats_;
  std::atomic<bool> writable_{true};
};

// When a trajectory's flight started: its first sample's time less that sample's time since the start.
std::int64_t flightStartUtcNs(const TrajectoryData& trajectory);

// The number at the end of a plan id ("uav-1-17" -> 17), 0 when there is none.
std::uint64_t planNumber(const std::string& plan_id);

}  // namespace skyroute
