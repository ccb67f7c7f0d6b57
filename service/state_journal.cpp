#include "service/state_journal.hpp"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <filesystem>
#include <system_error>

#include <nlohmann/json.hpp>

#include "service/journal_codec.hpp"
#include "service/journal_schema.hpp"
#include "service/mission_json.hpp"

namespace skyroute {

using nlohmann::json;

namespace {

constexpr std::int64_t kPruneIntervalNs = 1'000'000'000;

// Runs one statement with its parameters bound by `bind`.
template <typename Bind>
Status runSql(SqliteDb& db, const std::string& sql, const Bind& bind) {
  auto statement = db.prepare(sql);
  if (!statement.ok()) return statement.error();
  bind(*statement);
  return statement->run();
}

Error damagedRow(const SqliteDb& db, const std::string& row, const Error& why) {
  return make_error(ErrorCode::kParseError, db.path(),
                    "state journal " + db.path() + ": " + row + " is damaged (" + why.message +
                        "); skyrouted will not start on it (move the file aside to start with an empty journal)");
}

// Reads every row of `sql`, handing each to `read` (which returns an error for a bad row).
template <typename Read>
Status readRows(SqliteDb& db, const std::string& sql, const Read& read) {
  auto query = db.prepare(sql);
  if (!query.ok()) return query.error();
  for (;;) {
    auto row = query->step();
    if (!row.ok()) return row.error();
    if (!*row) return Status::success();
    if (Status s = read(*query); !s.ok()) {
      while (row.ok() && *row) row = query->step();  // resets the statement
      return s;
    }
  }
}

}  // namespace

std::int64_t flightStartUtcNs(const TrajectoryData& t) {
  if (t.samples.empty()) return 0;
  return t.samples.front().utc_ns - static_cast<std::int64_t>(std::llround(t.samples.front().t_rel_s * 1e9));
}

std::uint64_t planNumber(const std::string& plan_id) {
  const std::size_t dash = plan_id.find_last_of('-');
  const std::string tail = dash == std::string::npos ? plan_id : plan_id.substr(dash + 1);
  if (tail.empty() || tail.size() > 18 || !std::all_of(tail.begin(), tail.end(), [](unsigned char c) { return std::isdigit(c); })) {
    return 0;
  }
  return std::stoull(tail);
}

Result<std::unique_ptr<StateJournal>> StateJournal::open(const std::string& dir) {
  std::error_code ec;
  std::filesystem::create_directories(dir, ec);
  if (ec) {
    return make_error(ErrorCode::kFileNotFound, dir, "state directory " + dir + " cannot be made: " + ec.message());
  }
  auto db = SqliteDb::open((std::filesystem::path(dir) / kFileName).string());
  if (!db.ok()) return db.error();
  auto found = prepareJournalSchema(**db);
  if (!found.ok()) return found.error();
  // WAL: a writer appends and never waits for a reader; synchronous NORMAL syncs at checkpoints,
  // so a committed event survives the process being killed (not a power cut's last moments).
  if (Status s = (*db)->exec("PRAGMA journal_mode = WAL; PRAGMA synchronous = NORMAL;"); !s.ok()) return s.error();
  return std::unique_ptr<StateJournal>(new StateJournal(std::move(*db), *found));
}

template <typename Body>
Status StateJournal::transaction(const Body& body) {
  const auto started = std::chrono::steady_clock::now();
  std::lock_guard lock(mutex_);
  if (Status s = db_->exec("BEGIN IMMEDIATE"); !s.ok()) return s;
  Status outcome = body();
  if (outcome.ok()) outcome = db_->exec("COMMIT");
  if (!outcome.ok()) (void)db_->exec("ROLLBACK");
  const double ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - started).count();
  ++stats_.writes;
  stats_.total_ms += ms;
  stats_.max_ms = std::max(stats_.max_ms, ms);
  return outcome;
}

Status StateJournal::recordAccepted(const MissionRequestData& request, std::int64_t now_utc_ns) {
  const std::string text = missionToJson(request).dump();
  return transaction([&] {
    return runSql(*db_,
                  "INSERT OR REPLACE INTO missions(vehicle_id, request_id, request_json, state, accepted_utc_ns) "
                  "VALUES (?1, ?2, ?3, 'accepted', ?4)",
                  [&](SqliteStatement& s) { s.bind(1, request.vehicle_id).bind(2, request.request_id).bind(3, text).bind(4, now_utc_ns); });
  });
}

Status StateJournal::recordTrajectory(const TrajectoryData& t, std::int64_t now_utc_ns) {
  const std::string record = encodeTrajectory(t);
  const std::int64_t ends = t.samples.empty() ? 0 : t.samples.back().utc_ns;
  const auto plan_number = static_cast<std::int64_t>(planNumber(t.plan_id));
  return transaction([&]() -> Status {
    Status s = runSql(*db_,
                      "INSERT OR REPLACE INTO trajectories(vehicle_id, plan_id, revision, request_id, record, ends_utc_ns) "
                      "VALUES (?1, ?2, ?3, ?4, ?5, ?6)",
                      [&](SqliteStatement& q) {
                        q.bind(1, t.vehicle_id).bind(2, t.plan_id).bind(3, static_cast<std::int64_t>(t.revision));
                        q.bind(4, t.request_id).bindBlob(5, record).bind(6, ends);
                      });
    if (s.ok() && t.revision == 0) {
      // A new plan: its mission flies, and any other mission this vehicle flew has ended.
      s = runSql(*db_,
                 "UPDATE missions SET state = 'flying', flight_start_utc_ns = ?3 WHERE vehicle_id = ?1 AND request_id = ?2",
                 [&](SqliteStatement& q) { q.bind(1, t.vehicle_id).bind(2, t.request_id).bind(3, flightStartUtcNs(t)); });
      if (s.ok()) {
        s = runSql(*db_, "DELETE FROM missions WHERE vehicle_id = ?1 AND state = 'flying' AND request_id <> ?2",
                   [&](SqliteStatement& q) { q.bind(1, t.vehicle_id).bind(2, t.request_id); });
      }
      if (s.ok()) {
        s = runSql(*db_,
                   "INSERT INTO meta(key, value) VALUES ('plan_counter', ?1) "
                   "ON CONFLICT(key) DO UPDATE SET value = max(value, excluded.value)",
                   [&](SqliteStatement& q) { q.bind(1, plan_number); });
      }
    }
    if (s.ok() && now_utc_ns - last_prune_utc_ns_ >= kPruneIntervalNs) s = pruneLocked(now_utc_ns);
    return s;
  });
}

Status StateJournal::pruneLocked(std::int64_t now_utc_ns) {
  last_prune_utc_ns_ = now_utc_ns;
  Status s = runSql(*db_,
                    "DELETE FROM missions WHERE state = 'flying' AND vehicle_id IN "
                    "(SELECT vehicle_id FROM trajectories WHERE ends_utc_ns < ?1)",
                    [&](SqliteStatement& q) { q.bind(1, now_utc_ns); });
  if (s.ok()) {
    s = runSql(*db_, "DELETE FROM trajectories WHERE ends_utc_ns < ?1", [&](SqliteStatement& q) { q.bind(1, now_utc_ns); });
  }
  for (const char* table : {"obstacles", "no_fly_zones"}) {
    if (!s.ok()) break;
    s = runSql(*db_, std::string("DELETE FROM ") + table + " WHERE valid_until_utc_ns <> 0 AND valid_until_utc_ns < ?1",
               [&](SqliteStatement& q) { q.bind(1, now_utc_ns); });
  }
  if (s.ok()) {
    s = db_->exec("DELETE FROM fleet_allocations WHERE request_id NOT IN (SELECT request_id FROM trajectories)");
  }
  return s;
}

Status StateJournal::recordRetracted(const std::string& vehicle_id) {
  return transaction([&] {
    return runSql(*db_, "DELETE FROM trajectories WHERE vehicle_id = ?1", [&](SqliteStatement& q) { q.bind(1, vehicle_id); });
  });
}

Status StateJournal::recordFinished(const std::string& vehicle_id, const std::string& request_id) {
  return transaction([&] {
    return runSql(*db_, "DELETE FROM missions WHERE vehicle_id = ?1 AND request_id = ?2",
                  [&](SqliteStatement& q) { q.bind(1, vehicle_id).bind(2, request_id); });
  });
}

Status StateJournal::recordObstacle(const ObstacleUpdateData& update) {
  const auto id = static_cast<std::int64_t>(update.obstacle.id);
  if (update.remove) {
    return transaction([&] {
      return runSql(*db_, "DELETE FROM obstacles WHERE obstacle_id = ?1", [&](SqliteStatement& q) { q.bind(1, id); });
    });
  }
  const std::string text = obstacleRecordToJson(update).dump();
  return transaction([&] {
    return runSql(*db_, "INSERT OR REPLACE INTO obstacles(obstacle_id, update_json, valid_until_utc_ns) VALUES (?1, ?2, ?3)",
                  [&](SqliteStatement& q) { q.bind(1, id).bind(2, text).bind(3, update.valid_until_utc_ns); });
  });
}

Status StateJournal::recordNoFlyZone(const NoFlyZoneData& zone) {
  if (zone.remove) {
    return transaction([&] {
      return runSql(*db_, "DELETE FROM no_fly_zones WHERE zone_id = ?1", [&](SqliteStatement& q) { q.bind(1, zone.zone_id); });
    });
  }
  const std::string text = noFlyZoneToJson(zone).dump();
  return transaction([&] {
    return runSql(*db_, "INSERT OR REPLACE INTO no_fly_zones(zone_id, zone_json, valid_until_utc_ns) VALUES (?1, ?2, ?3)",
                  [&](SqliteStatement& q) { q.bind(1, zone.zone_id).bind(2, text).bind(3, zone.valid_until_utc_ns); });
  });
}

Status StateJournal::recordFleet(const FleetStatusData& status) {
  const std::string text = fleetStatusToJson(status).dump();
  return transaction([&] {
    return runSql(*db_, "INSERT OR REPLACE INTO fleet_allocations(request_id, status_json) VALUES (?1, ?2)",
                  [&](SqliteStatement& q) { q.bind(1, status.request_id).bind(2, text); });
  });
}

Status StateJournal::recordOwner(const std::string& instance_id) {
  return transaction([&]() -> Status {
    if (Status s = db_->exec("DELETE FROM owner"); !s.ok()) return s;
    return runSql(*db_, "INSERT INTO owner(instance_id) VALUES (?1)", [&](SqliteStatement& q) { q.bind(1, instance_id); });
  });
}

Status StateJournal::recordShardRequest(const JournaledRequest& copy) {
  const bool fleet = copy.fleet.has_value();
  const std::string text = fleet ? fleetToJson(*copy.fleet).dump() : missionToJson(*copy.mission).dump();
  const std::string vehicle = fleet ? std::string() : copy.mission->vehicle_id;
  const std::string request = fleet ? copy.fleet->request_id : copy.mission->request_id;
  return transaction([&] {
    return runSql(*db_,
                  "INSERT OR REPLACE INTO shard_requests(key, kind, vehicle_id, request_id, request_json, seen_utc_ns) "
                  "VALUES (?1, ?2, ?3, ?4, ?5, ?6)",
                  [&](SqliteStatement& q) {
                    q.bind(1, copy.key).bind(2, std::string(fleet ? "fleet" : "mission")).bind(3, vehicle);
                    q.bind(4, request).bind(5, text).bind(6, copy.seen_utc_ns);
                  });
  });
}

Status StateJournal::forgetShardRequests(const std::vector<std::string>& keys) {
  if (keys.empty()) return Status::success();
  return transaction([&]() -> Status {
    for (const std::string& key : keys) {
      Status s = runSql(*db_, "DELETE FROM shard_requests WHERE key = ?1", [&](SqliteStatement& q) { q.bind(1, key); });
      if (!s.ok()) return s;
    }
    return Status::success();
  });
}

Status StateJournal::forgetShardMission(const std::string& vehicle_id, const std::string& request_id) {
  return transaction([&] {
    return runSql(*db_,
                  "DELETE FROM shard_requests WHERE kind = 'mission' AND (?1 = '' OR vehicle_id = ?1) "
                  "AND (?2 = '' OR request_id = ?2)",
                  [&](SqliteStatement& q) { q.bind(1, vehicle_id).bind(2, request_id); });
  });
}

Status StateJournal::beginShardLife(std::int64_t started_utc_ns) {
  return transaction([&]() -> Status {
    Status s = runSql(*db_, "INSERT OR REPLACE INTO shard_lives(started_utc_ns, covered_until_utc_ns) VALUES (?1, 0)",
                      [&](SqliteStatement& q) { q.bind(1, started_utc_ns); });
    if (!s.ok()) return s;
    return runSql(*db_,
                  "DELETE FROM shard_lives WHERE started_utc_ns NOT IN "
                  "(SELECT started_utc_ns FROM shard_lives ORDER BY started_utc_ns DESC LIMIT ?1)",
                  [&](SqliteStatement& q) { q.bind(1, static_cast<std::int64_t>(kMaxPastCoverage + 1)); });
  });
}

Status StateJournal::recordShardCoverage(std::int64_t started_utc_ns, std::int64_t covered_until_utc_ns) {
  return transaction([&] {
    return runSql(*db_,
                  "UPDATE shard_lives SET covered_until_utc_ns = max(covered_until_utc_ns, ?2) WHERE started_utc_ns = ?1",
                  [&](SqliteStatement& q) { q.bind(1, started_utc_ns).bind(2, covered_until_utc_ns); });
  });
}

Result<JournalState> StateJournal::load(std::int64_t now_utc_ns) {
  if (Status s = transaction([&] { return pruneLocked(now_utc_ns); }); !s.ok()) return s.error();
  std::lock_guard lock(mutex_);
  JournalState state;
  Status s = readRows(*db_,
                      "SELECT vehicle_id, request_id, request_json, state, flight_start_utc_ns FROM missions "
                      "ORDER BY accepted_utc_ns, rowid",
                      [&](SqliteStatement& q) -> Status {
                        const std::string row = "mission '" + q.text(1) + "' of vehicle '" + q.text(0) + "'";
                        auto request = missionFromJson(json::parse(q.text(2), nullptr, false));
                        if (!request.ok()) return damagedRow(*db_, row, request.error());
                        request->vehicle_id = q.text(0);
                        request->request_id = q.text(1);
                        state.missions.push_back(
                            JournalState::Mission{std::move(*request), q.text(3) == "flying", q.integer(4)});
                        return Status::success();
                      });
  if (s.ok()) {
    s = readRows(*db_, "SELECT vehicle_id, record FROM trajectories ORDER BY vehicle_id", [&](SqliteStatement& q) -> Status {
      auto t = decodeTrajectory(q.text(1));
      if (!t.ok()) return damagedRow(*db_, "the trajectory of vehicle '" + q.text(0) + "'", t.error());
      state.trajectories.push_back(std::move(*t));
      return Status::success();
    });
  }
  if (s.ok()) {
    s = readRows(*db_, "SELECT obstacle_id, update_json FROM obstacles ORDER BY obstacle_id", [&](SqliteStatement& q) -> Status {
      auto u = obstacleRecordFromJson(json::parse(q.text(1), nullptr, false));
      if (!u.ok()) return damagedRow(*db_, "obstacle " + q.text(0), u.error());
      state.obstacles.push_back(std::move(*u));
      return Status::success();
    });
  }
  if (s.ok()) {
    s = readRows(*db_, "SELECT zone_id, zone_json FROM no_fly_zones ORDER BY zone_id", [&](SqliteStatement& q) -> Status {
      auto z = noFlyZoneFromJson(json::parse(q.text(1), nullptr, false));
      if (!z.ok()) return damagedRow(*db_, "no-fly zone '" + q.text(0) + "'", z.error());
      state.zones.push_back(std::move(*z));
      return Status::success();
    });
  }
  if (s.ok()) {
    s = readRows(*db_, "SELECT request_id, status_json FROM fleet_allocations ORDER BY request_id", [&](SqliteStatement& q) -> Status {
      auto f = fleetStatusFromJson(json::parse(q.text(1), nullptr, false));
      if (!f.ok()) return damagedRow(*db_, "fleet '" + q.text(0) + "'", f.error());
      state.fleets.push_back(std::move(*f));
      return Status::success();
    });
  }
  if (s.ok()) {
    s = readRows(*db_, "SELECT value FROM meta WHERE key = 'plan_counter'", [&](SqliteStatement& q) -> Status {
      state.plan_counter = static_cast<std::uint64_t>(std::max<std::int64_t>(0, q.integer(0)));
      return Status::success();
    });
  }
  if (s.ok()) {
    s = readRows(*db_, "SELECT instance_id FROM owner", [&](SqliteStatement& q) -> Status {
      state.owner_instance_id = q.text(0);
      return Status::success();
    });
  }
  if (s.ok()) {
    s = readRows(*db_,
                 "SELECT key, kind, request_json, seen_utc_ns, vehicle_id, request_id FROM shard_requests "
                 "ORDER BY seen_utc_ns, rowid",
                 [&](SqliteStatement& q) -> Status {
                   JournaledRequest copy;
                   copy.key = q.text(0);
                   copy.seen_utc_ns = q.integer(3);
                   const json parsed = json::parse(q.text(2), nullptr, false);
                   const std::string row = "the shard's copy of request '" + q.text(5) + "'";
                   if (q.text(1) == "fleet") {
                     auto fleet = fleetFromJson(parsed);
                     if (!fleet.ok()) return damagedRow(*db_, row, fleet.error());
                     copy.fleet = std::move(*fleet);
                   } else {
                     auto mission = missionFromJson(parsed);
                     if (!mission.ok()) return damagedRow(*db_, row, mission.error());
                     mission->vehicle_id = q.text(4);
                     mission->request_id = q.text(5);
                     copy.mission = std::move(*mission);
                   }
                   state.shard_requests.push_back(std::move(copy));
                   return Status::success();
                 });
  }
  if (s.ok()) {
    s = readRows(*db_, "SELECT started_utc_ns, covered_until_utc_ns FROM shard_lives ORDER BY started_utc_ns",
                 [&](SqliteStatement& q) -> Status {
                   state.shard_lives.push_back(CoverageInterval{q.integer(0), q.integer(1)});
                   return Status::success();
                 });
  }
  // Plan ids of a journal migrated from version 1 (no counter kept) are above every current one.
  for (const TrajectoryData& t : state.trajectories) state.plan_counter = std::max(state.plan_counter, planNumber(t.plan_id));
  if (!s.ok()) return s.error();
  return state;
}

JournalWriteStats StateJournal::writeStats() const {
  std::lock_guard lock(mutex_);
  return stats_;
}

}  // namespace skyroute
