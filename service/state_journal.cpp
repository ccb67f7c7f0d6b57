#include "service/state_journal.hpp"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <filesystem>
#include <system_error>

#include <nlohmann/json.hpp>
#include <spdlog/spdlog.h>

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
  const std::filesystem::path file = std::filesystem::path(dir) / kFileName;
  // SQLite takes an empty file for a new database: a journal cut to nothing (a failed copy, a
  // truncation) would start the daemon silently with nothing. Only a missing file starts empty.
  if (std::filesystem::is_regular_file(file, ec) && std::filesystem::file_size(file, ec) == 0 && !ec) {
    return make_error(ErrorCode::kParseError, file.string(),
                      "state journal " + file.string() +
                          " is empty (0 bytes): it held no state or was cut to nothing; skyrouted will not start on it "
                          "(remove the file to start with an empty journal, or put the right one back)");
  }
  auto db = SqliteDb::open(file.string());
  if (!db.ok()) return db.error();
  auto found = prepareJournalSchema(**db);
  if (!found.ok()) return found.error();
  // WAL: a writer appends and never waits for a reader; synchronous NORMAL syncs at checkpoints,
  // so a committed event survives the process being killed (not a power cut's last moments).
  if (Status s = (*db)->exec("PRAGMA journal_mode = WAL; PRAGMA synchronous = NORMAL;"); !s.ok()) return s.error();
  return std::unique_ptr<StateJournal>(new StateJournal(std::move(*db), *found));
}

template <typename Body>
Status StateJournal::transaction(const Body& body, bool adds) {
  const auto started = std::chrono::steady_clock::now();
  std::lock_guard lock(mutex_);
  const auto attempt = [&](bool& full) {
    Status s = db_->exec("BEGIN IMMEDIATE");
    if (s.ok()) s = body();
    if (s.ok()) s = db_->exec("COMMIT");
    if (!s.ok()) {
      full = db_->lastFailureWasFull();
      (void)db_->exec("ROLLBACK");
    }
    return s;
  };
  bool full = false;
  Status outcome = attempt(full);
  if (!outcome.ok() && full) {
    // The write-ahead log holds every page written since the last checkpoint, old versions of
    // replaced rows too, and is only checkpointed at 1000 pages: on a small disk it can fill the
    // disk by itself. A checkpoint that moves it into the database and truncates it may make room.
    (void)db_->exec("PRAGMA wal_checkpoint(TRUNCATE)");
    outcome = attempt(full);
  }
  const double ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - started).count();
  ++stats_.writes;
  stats_.total_ms += ms;
  stats_.max_ms = std::max(stats_.max_ms, ms);
  if (outcome.ok() && !adds) return outcome;  // a removal says nothing of room for new rows
  const bool was_writable = writable_.exchange(outcome.ok());
  if (was_writable && !outcome.ok()) {
    spdlog::error("event=journal_unavailable path={} disk_full={} message=\"{}\" effect=\"new requests, fleets and cancels "
                  "are refused journal_unavailable and no revision is published until a write succeeds\"",
                  db_->path(), full, outcome.error().message);
  } else if (!was_writable && outcome.ok()) {
    spdlog::info("event=journal_available path={}", db_->path());
  }
  return outcome;
}

Status StateJournal::recordAccepted(const MissionRequestData& request, std::int64_t now_utc_ns) {
  const std::string text = missionToJson(request).dump();
  return transaction([&] {
    return runSql(*db_,
                  "INSERT OR REPLACE INTO missions(vehicle_id, request_id, request_json, state, accepted_utc_ns, checksum) "
                  "VALUES (?1, ?2, ?3, 'accepted', ?4, row_checksum(?1, ?2, ?3, 'accepted', ?4, 0))",
                  [&](SqliteStatement& s) { s.bind(1, request.vehicle_id).bind(2, request.request_id).bind(3, text).bind(4, now_utc_ns); });
  });
}

Status StateJournal::recordTrajectory(const TrajectoryData& t, std::int64_t now_utc_ns) {
  return transaction([&]() -> Status {
    Status s = writeTrajectoryLocked(t);
    if (s.ok() && now_utc_ns - last_prune_utc_ns_ >= kPruneIntervalNs) s = pruneLocked(now_utc_ns);
    return s;
  });
}

Status StateJournal::recordFleetPlan(const std::vector<TrajectoryData>& trajectories, const FleetStatusData& status,
                                     std::int64_t now_utc_ns) {
  const std::string text = fleetStatusToJson(status).dump();
  return transaction([&]() -> Status {
    for (const TrajectoryData& t : trajectories) {
      if (Status s = writeTrajectoryLocked(t); !s.ok()) return s;
    }
    Status s = runSql(*db_, "INSERT OR REPLACE INTO fleet_allocations(request_id, status_json, checksum) VALUES (?1, ?2, row_checksum(?1, ?2))",
                      [&](SqliteStatement& q) { q.bind(1, status.request_id).bind(2, text); });
    if (s.ok() && now_utc_ns - last_prune_utc_ns_ >= kPruneIntervalNs) s = pruneLocked(now_utc_ns);
    return s;
  });
}

Status StateJournal::recordCancel(const std::string& vehicle_id, const std::string& request_id) {
  return transaction([&]() -> Status {
    Status s = runSql(*db_,
                      "DELETE FROM trajectories WHERE EXISTS (SELECT 1 FROM missions m WHERE m.vehicle_id = "
                      "trajectories.vehicle_id AND m.request_id = trajectories.request_id AND (?1 = '' OR m.vehicle_id = ?1) "
                      "AND (?2 = '' OR m.request_id = ?2))",
                      [&](SqliteStatement& q) { q.bind(1, vehicle_id).bind(2, request_id); });
    if (!s.ok()) return s;
    return runSql(*db_, "DELETE FROM missions WHERE (?1 = '' OR vehicle_id = ?1) AND (?2 = '' OR request_id = ?2)",
                  [&](SqliteStatement& q) { q.bind(1, vehicle_id).bind(2, request_id); });
  }, /*adds=*/false);
}

Status StateJournal::writeTrajectoryLocked(const TrajectoryData& t) {
  const std::string record = encodeTrajectory(t);
  const std::int64_t ends = t.samples.empty() ? 0 : t.samples.back().utc_ns;
  const auto plan_number = static_cast<std::int64_t>(planNumber(t.plan_id));
  {
    Status s = runSql(*db_,
                      "INSERT OR REPLACE INTO trajectories(vehicle_id, plan_id, revision, request_id, record, ends_utc_ns, "
                      "checksum) VALUES (?1, ?2, ?3, ?4, ?5, ?6, row_checksum(?1, ?2, ?3, ?4, ?5, ?6))",
                      [&](SqliteStatement& q) {
                        q.bind(1, t.vehicle_id).bind(2, t.plan_id).bind(3, static_cast<std::int64_t>(t.revision));
                        q.bind(4, t.request_id).bindBlob(5, record).bind(6, ends);
                      });
    if (s.ok() && t.revision == 0) {
      // A new plan: its mission flies, and any other mission this vehicle flew has ended.
      s = runSql(*db_,
                 "UPDATE missions SET state = 'flying', flight_start_utc_ns = ?3, checksum = row_checksum(vehicle_id, "
                 "request_id, request_json, 'flying', accepted_utc_ns, ?3) WHERE vehicle_id = ?1 AND request_id = ?2",
                 [&](SqliteStatement& q) { q.bind(1, t.vehicle_id).bind(2, t.request_id).bind(3, flightStartUtcNs(t)); });
      if (s.ok()) {
        s = runSql(*db_, "DELETE FROM missions WHERE vehicle_id = ?1 AND state = 'flying' AND request_id <> ?2",
                   [&](SqliteStatement& q) { q.bind(1, t.vehicle_id).bind(2, t.request_id); });
      }
      if (s.ok()) {
        s = runSql(*db_,
                   "INSERT INTO meta(key, value, checksum) VALUES ('plan_counter', ?1, row_checksum('plan_counter', ?1)) "
                   "ON CONFLICT(key) DO UPDATE SET value = max(value, excluded.value), "
                   "checksum = row_checksum(key, max(value, excluded.value))",
                   [&](SqliteStatement& q) { q.bind(1, plan_number); });
      }
    }
    return s;
  }
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
  }, /*adds=*/false);
}

Status StateJournal::recordFinished(const std::string& vehicle_id, const std::string& request_id) {
  return transaction([&] {
    return runSql(*db_, "DELETE FROM missions WHERE vehicle_id = ?1 AND request_id = ?2",
                  [&](SqliteStatement& q) { q.bind(1, vehicle_id).bind(2, request_id); });
  }, /*adds=*/false);
}

Status StateJournal::recordObstacle(const ObstacleUpdateData& update) {
  const auto id = static_cast<std::int64_t>(update.obstacle.id);
  if (update.remove) {
    return transaction(
        [&] { return runSql(*db_, "DELETE FROM obstacles WHERE obstacle_id = ?1", [&](SqliteStatement& q) { q.bind(1, id); }); },
        /*adds=*/false);
  }
  const std::string text = obstacleRecordToJson(update).dump();
  return transaction([&] {
    return runSql(*db_, "INSERT OR REPLACE INTO obstacles(obstacle_id, update_json, valid_until_utc_ns, checksum) "
                  "VALUES (?1, ?2, ?3, row_checksum(?1, ?2, ?3))",
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
    return runSql(*db_, "INSERT OR REPLACE INTO no_fly_zones(zone_id, zone_json, valid_until_utc_ns, checksum) "
                  "VALUES (?1, ?2, ?3, row_checksum(?1, ?2, ?3))",
                  [&](SqliteStatement& q) { q.bind(1, zone.zone_id).bind(2, text).bind(3, zone.valid_until_utc_ns); });
  });
}

Status StateJournal::recordFleet(const FleetStatusData& status) {
  const std::string text = fleetStatusToJson(status).dump();
  return transaction([&] {
    return runSql(*db_, "INSERT OR REPLACE INTO fleet_allocations(request_id, status_json, checksum) VALUES (?1, ?2, row_checksum(?1, ?2))",
                  [&](SqliteStatement& q) { q.bind(1, status.request_id).bind(2, text); });
  });
}

Status StateJournal::recordOwner(const std::string& instance_id) {
  return transaction([&]() -> Status {
    if (Status s = db_->exec("DELETE FROM owner"); !s.ok()) return s;
    return runSql(*db_, "INSERT INTO owner(instance_id, checksum) VALUES (?1, row_checksum(?1))", [&](SqliteStatement& q) { q.bind(1, instance_id); });
  });
}

Status StateJournal::recordShardRequest(const JournaledRequest& copy) {
  const bool fleet = copy.fleet.has_value();
  const std::string text = fleet ? fleetToJson(*copy.fleet).dump() : missionToJson(*copy.mission).dump();
  const std::string vehicle = fleet ? std::string() : copy.mission->vehicle_id;
  const std::string request = fleet ? copy.fleet->request_id : copy.mission->request_id;
  return transaction([&] {
    return runSql(*db_,
                  "INSERT OR REPLACE INTO shard_requests(key, kind, vehicle_id, request_id, request_json, seen_utc_ns, "
                  "checksum) VALUES (?1, ?2, ?3, ?4, ?5, ?6, row_checksum(?1, ?2, ?3, ?4, ?5, ?6))",
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
  }, /*adds=*/false);
}

Status StateJournal::forgetShardMission(const std::string& vehicle_id, const std::string& request_id) {
  return transaction([&] {
    return runSql(*db_,
                  "DELETE FROM shard_requests WHERE kind = 'mission' AND (?1 = '' OR vehicle_id = ?1) "
                  "AND (?2 = '' OR request_id = ?2)",
                  [&](SqliteStatement& q) { q.bind(1, vehicle_id).bind(2, request_id); });
  }, /*adds=*/false);
}

Status StateJournal::beginShardLife(std::int64_t started_utc_ns) {
  return transaction([&]() -> Status {
    Status s = runSql(*db_, "INSERT OR REPLACE INTO shard_lives(started_utc_ns, covered_until_utc_ns, checksum) "
                      "VALUES (?1, 0, row_checksum(?1, 0))",
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
                  "UPDATE shard_lives SET covered_until_utc_ns = max(covered_until_utc_ns, ?2), checksum = "
                  "row_checksum(started_utc_ns, max(covered_until_utc_ns, ?2)) WHERE started_utc_ns = ?1",
                  [&](SqliteStatement& q) { q.bind(1, started_utc_ns).bind(2, covered_until_utc_ns); });
  });
}

Result<JournalState> StateJournal::load(std::int64_t now_utc_ns) {
  if (Status s = transaction([&] { return pruneLocked(now_utc_ns); }, /*adds=*/false); !s.ok()) {
    // A full disk must not keep the daemon from recovering what it holds: the ended rows are read
    // too (an ended flight is found finished at once), and pruned at a later write.
    spdlog::warn("event=journal_prune_failed path={} message=\"{}\"", db_->path(), s.error().message);
  }
  JournalState state;
  std::vector<QuarantinedRecord> damaged;
  {
    std::lock_guard lock(mutex_);
    // Each query ends with the row's checksum check and its key columns. A row that fails either
    // check is quarantined, never returned.
    const auto read = [&](const std::string& table_name, const std::string& columns, const std::string& order,
                          const auto& take) -> Status {
      const JournalTable& table = journalTable(table_name);
      const int n_columns = static_cast<int>(std::count(columns.begin(), columns.end(), ',')) + 1;
      std::string keys;
      for (const char* k : table.key_columns) keys += std::string(", ") + k;
      return readRows(*db_,
                      "SELECT " + columns + ", checksum = " + table.checksum + keys + " FROM " + table_name + order,
                      [&](SqliteStatement& q) -> Status {
                        std::vector<std::string> key;
                        for (std::size_t k = 0; k < table.key_columns.size(); ++k) {
                          key.push_back(q.text(n_columns + 1 + static_cast<int>(k)));
                        }
                        if (q.integer(n_columns) != 1) {
                          damaged.push_back({table_name, key, "checksum mismatch: the record is damaged"});
                          return Status::success();
                        }
                        if (std::optional<std::string> why = take(q)) damaged.push_back({table_name, key, *why});
                        return Status::success();
                      });
    };
    // A decoding error: the reason to quarantine; nothing when the row was taken.
    using Why = std::optional<std::string>;
    Status s = read("missions", "vehicle_id, request_id, request_json, state, flight_start_utc_ns",
                    " ORDER BY accepted_utc_ns, rowid", [&](SqliteStatement& q) -> Why {
                      auto request = missionFromJson(json::parse(q.text(2), nullptr, false));
                      if (!request.ok()) return "the request does not decode: " + request.error().describe();
                      request->vehicle_id = q.text(0);
                      request->request_id = q.text(1);
                      state.missions.push_back(JournalState::Mission{std::move(*request), q.text(3) == "flying", q.integer(4)});
                      return std::nullopt;
                    });
    if (s.ok()) {
      s = read("trajectories", "vehicle_id, record", " ORDER BY vehicle_id", [&](SqliteStatement& q) -> Why {
        auto t = decodeTrajectory(q.text(1));
        if (!t.ok()) return "the trajectory does not decode: " + t.error().message;
        state.trajectories.push_back(std::move(*t));
        return std::nullopt;
      });
    }
    if (s.ok()) {
      s = read("obstacles", "obstacle_id, update_json", " ORDER BY obstacle_id", [&](SqliteStatement& q) -> Why {
        auto u = obstacleRecordFromJson(json::parse(q.text(1), nullptr, false));
        if (!u.ok()) return "the obstacle update does not decode: " + u.error().describe();
        state.obstacles.push_back(std::move(*u));
        return std::nullopt;
      });
    }
    if (s.ok()) {
      s = read("no_fly_zones", "zone_id, zone_json", " ORDER BY zone_id", [&](SqliteStatement& q) -> Why {
        auto z = noFlyZoneFromJson(json::parse(q.text(1), nullptr, false));
        if (!z.ok()) return "the no-fly zone does not decode: " + z.error().describe();
        state.zones.push_back(std::move(*z));
        return std::nullopt;
      });
    }
    if (s.ok()) {
      s = read("fleet_allocations", "request_id, status_json", " ORDER BY request_id", [&](SqliteStatement& q) -> Why {
        auto f = fleetStatusFromJson(json::parse(q.text(1), nullptr, false));
        if (!f.ok()) return "the fleet's answer does not decode: " + f.error().describe();
        state.fleets.push_back(std::move(*f));
        return std::nullopt;
      });
    }
    if (s.ok()) {
      s = read("meta", "value", " WHERE key = 'plan_counter'", [&](SqliteStatement& q) -> Why {
        state.plan_counter = static_cast<std::uint64_t>(std::max<std::int64_t>(0, q.integer(0)));
        return std::nullopt;
      });
    }
    if (s.ok()) {
      s = read("owner", "instance_id", "", [&](SqliteStatement& q) -> Why {
        state.owner_instance_id = q.text(0);
        return std::nullopt;
      });
    }
    if (s.ok()) {
      s = read("shard_requests", "key, kind, request_json, seen_utc_ns, vehicle_id, request_id",
               " ORDER BY seen_utc_ns, rowid", [&](SqliteStatement& q) -> Why {
                 JournaledRequest copy;
                 copy.key = q.text(0);
                 copy.seen_utc_ns = q.integer(3);
                 const json parsed = json::parse(q.text(2), nullptr, false);
                 if (q.text(1) == "fleet") {
                   auto fleet = fleetFromJson(parsed);
                   if (!fleet.ok()) return "the fleet request does not decode: " + fleet.error().describe();
                   copy.fleet = std::move(*fleet);
                 } else {
                   auto mission = missionFromJson(parsed);
                   if (!mission.ok()) return "the request does not decode: " + mission.error().describe();
                   mission->vehicle_id = q.text(4);
                   mission->request_id = q.text(5);
                   copy.mission = std::move(*mission);
                 }
                 state.shard_requests.push_back(std::move(copy));
                 return std::nullopt;
               });
    }
    if (s.ok()) {
      s = read("shard_lives", "started_utc_ns, covered_until_utc_ns", " ORDER BY started_utc_ns",
               [&](SqliteStatement& q) -> Why {
                 state.shard_lives.push_back(CoverageInterval{q.integer(0), q.integer(1)});
                 return std::nullopt;
               });
    }
    if (!s.ok()) {
      return make_error(ErrorCode::kParseError, db_->path(),
                        "state journal " + db_->path() + ": its tables cannot be read (" + s.error().message +
                            "); skyrouted will not start on it (move the file aside to start with an empty journal)");
    }
  }
  // Plan ids of a journal migrated from version 1 (no counter kept) are above every current one.
  for (const TrajectoryData& t : state.trajectories) state.plan_counter = std::max(state.plan_counter, planNumber(t.plan_id));
  if (!damaged.empty()) {
    quarantineDependents(state, damaged);
    (void)quarantine(damaged, now_utc_ns);
    state.quarantined = std::move(damaged);
  }
  return state;
}

namespace {

// A key as a log line shows it: at most 80 characters, control characters escaped, so a hostile
// id can neither flood nor forge the log.
std::string printableKey(const std::vector<std::string>& key) {
  std::string joined;
  for (const std::string& part : key) joined += (joined.empty() ? "" : "/") + part;
  std::string out;
  for (std::size_t i = 0; i < joined.size() && out.size() < 80; ++i) {
    const auto c = static_cast<unsigned char>(joined[i]);
    if (c < 0x20 || c == 0x7f || c == '"' || c == '\\') {
      out += fmt::format("\\x{:02x}", c);
    } else {
      out += static_cast<char>(c);
    }
  }
  if (out.size() >= 80 && joined.size() > 80) out += "...(" + std::to_string(joined.size()) + " characters)";
  return out;
}

}  // namespace

Status StateJournal::quarantine(const std::vector<QuarantinedRecord>& records, std::int64_t now_utc_ns) {
  if (records.empty()) return Status::success();
  Status moved = transaction([&]() -> Status {
    for (const QuarantinedRecord& r : records) {
      const JournalTable& table = journalTable(r.table);
      std::string where;
      for (std::size_t k = 0; k < table.key_columns.size(); ++k) {
        where += std::string(k == 0 ? " WHERE " : " AND ") + table.key_columns[k] + " = ?" + std::to_string(k + 5);
      }
      const auto bind_key = [&](SqliteStatement& q) {
        for (std::size_t k = 0; k < table.key_columns.size() && k < r.key.size(); ++k) {
          q.bind(static_cast<int>(k + 5), r.key[k]);
        }
      };
      Status s = runSql(*db_,
                        std::string("INSERT INTO quarantine(source_table, record_key, reason, record, quarantined_utc_ns) "
                                    "SELECT ?1, ?2, ?3, ") +
                            table.payload_column + ", ?4 FROM " + r.table + where,
                        [&](SqliteStatement& q) {
                          q.bind(1, r.table).bind(2, json(r.key).dump(-1, ' ', false, json::error_handler_t::replace));
                          q.bind(3, r.reason).bind(4, now_utc_ns);
                          bind_key(q);
                        });
      if (s.ok()) s = runSql(*db_, "DELETE FROM " + r.table + where, bind_key);
      if (!s.ok()) return s;
    }
    return Status::success();
  });
  for (const QuarantinedRecord& r : records) {
    spdlog::error("event=journal_record_quarantined table={} key=\"{}\" reason=\"{}\" moved={}", r.table,
                  printableKey(r.key), r.reason, moved.ok());
  }
  if (!moved.ok()) {
    spdlog::error("event=journal_write_failed what=quarantine message=\"{}\"", moved.error().message);
  }
  return moved;
}

void quarantineDependents(JournalState& state, std::vector<QuarantinedRecord>& records) {
  for (std::size_t i = 0; i < records.size(); ++i) {  // records grows: dependents of dependents too
    const QuarantinedRecord r = records[i];
    if (r.table == "missions" && r.key.size() == 2) {
      std::erase_if(state.trajectories, [&](const TrajectoryData& t) {
        if (t.vehicle_id != r.key[0] || t.request_id != r.key[1]) return false;
        records.push_back({"trajectories", {t.vehicle_id}, "its mission was quarantined"});
        return true;
      });
    } else if (r.table == "trajectories" && r.key.size() == 1) {
      std::erase_if(state.missions, [&](const JournalState::Mission& m) {
        if (!m.flying || m.request.vehicle_id != r.key[0]) return false;
        records.push_back({"missions", {m.request.vehicle_id, m.request.request_id},
                           "its trajectory was quarantined: the flight cannot be resumed"});
        return true;
      });
    }
  }
  // A record listed twice (a mission and its trajectory each refused) is moved once.
  std::vector<QuarantinedRecord> unique;
  for (QuarantinedRecord& r : records) {
    const bool seen = std::any_of(unique.begin(), unique.end(),
                                  [&](const QuarantinedRecord& u) { return u.table == r.table && u.key == r.key; });
    if (!seen) unique.push_back(std::move(r));
  }
  records = std::move(unique);
}

JournalWriteStats StateJournal::writeStats() const {
  std::lock_guard lock(mutex_);
  return stats_;
}

}  // namespace skyroute
