#include "service/journal_schema.hpp"

#include <string>

#include "service/journal_codec.hpp"

namespace skyroute {

namespace {

constexpr const char* kCurrentSchema = R"sql(
CREATE TABLE schema_version(version INTEGER NOT NULL);
CREATE TABLE meta(key TEXT PRIMARY KEY, value INTEGER NOT NULL, checksum INTEGER NOT NULL DEFAULT 0);
CREATE TABLE missions(vehicle_id TEXT NOT NULL, request_id TEXT NOT NULL, request_json TEXT NOT NULL,
                      state TEXT NOT NULL, accepted_utc_ns INTEGER NOT NULL DEFAULT 0,
                      flight_start_utc_ns INTEGER NOT NULL DEFAULT 0, checksum INTEGER NOT NULL DEFAULT 0,
                      PRIMARY KEY(vehicle_id, request_id));
CREATE TABLE trajectories(vehicle_id TEXT PRIMARY KEY, plan_id TEXT NOT NULL, revision INTEGER NOT NULL,
                          request_id TEXT NOT NULL, record BLOB NOT NULL, ends_utc_ns INTEGER NOT NULL DEFAULT 0,
                          checksum INTEGER NOT NULL DEFAULT 0);
CREATE TABLE obstacles(obstacle_id INTEGER PRIMARY KEY, update_json TEXT NOT NULL,
                       valid_until_utc_ns INTEGER NOT NULL DEFAULT 0, checksum INTEGER NOT NULL DEFAULT 0);
CREATE TABLE no_fly_zones(zone_id TEXT PRIMARY KEY, zone_json TEXT NOT NULL, valid_until_utc_ns INTEGER NOT NULL,
                          checksum INTEGER NOT NULL DEFAULT 0);
CREATE TABLE fleet_allocations(request_id TEXT PRIMARY KEY, status_json TEXT NOT NULL,
                               checksum INTEGER NOT NULL DEFAULT 0);
CREATE TABLE owner(instance_id TEXT NOT NULL, checksum INTEGER NOT NULL DEFAULT 0);
CREATE TABLE shard_requests(key TEXT PRIMARY KEY, kind TEXT NOT NULL, vehicle_id TEXT NOT NULL,
                            request_id TEXT NOT NULL, request_json TEXT NOT NULL, seen_utc_ns INTEGER NOT NULL,
                            checksum INTEGER NOT NULL DEFAULT 0);
CREATE TABLE shard_lives(started_utc_ns INTEGER PRIMARY KEY, covered_until_utc_ns INTEGER NOT NULL,
                         checksum INTEGER NOT NULL DEFAULT 0);
CREATE TABLE quarantine(id INTEGER PRIMARY KEY AUTOINCREMENT, source_table TEXT NOT NULL, record_key TEXT NOT NULL,
                        reason TEXT NOT NULL, record BLOB, quarantined_utc_ns INTEGER NOT NULL);
)sql";

// Version 3 -> 4: the quarantine table; every record gets its checksum (the column is added
// where it is missing), computed from what it holds now: a record damaged before the migration
// cannot be told.
constexpr const char* kMigrateV3ToV4 = R"sql(
CREATE TABLE IF NOT EXISTS quarantine(id INTEGER PRIMARY KEY AUTOINCREMENT, source_table TEXT NOT NULL,
                                      record_key TEXT NOT NULL, reason TEXT NOT NULL, record BLOB,
                                      quarantined_utc_ns INTEGER NOT NULL);
)sql";

// Version 2 -> 3: a shard's copies of every request it read and its lives (empty for a daemon
// that is no shard, and for a shard's journal written by version 2: it had none).
constexpr const char* kMigrateV2ToV3 = R"sql(
CREATE TABLE shard_requests(key TEXT PRIMARY KEY, kind TEXT NOT NULL, vehicle_id TEXT NOT NULL,
                            request_id TEXT NOT NULL, request_json TEXT NOT NULL, seen_utc_ns INTEGER NOT NULL);
CREATE TABLE shard_lives(started_utc_ns INTEGER PRIMARY KEY, covered_until_utc_ns INTEGER NOT NULL);
)sql";

// Version 1 -> 2: the new columns and tables; each trajectory's end and each obstacle's end of
// validity read from its record. A flight's start stays 0 (unknown): recovery then takes its
// current trajectory's start.
constexpr const char* kMigrateV1ToV2 = R"sql(
ALTER TABLE missions ADD COLUMN accepted_utc_ns INTEGER NOT NULL DEFAULT 0;
ALTER TABLE missions ADD COLUMN flight_start_utc_ns INTEGER NOT NULL DEFAULT 0;
ALTER TABLE trajectories ADD COLUMN ends_utc_ns INTEGER NOT NULL DEFAULT 0;
ALTER TABLE obstacles ADD COLUMN valid_until_utc_ns INTEGER NOT NULL DEFAULT 0;
CREATE TABLE meta(key TEXT PRIMARY KEY, value INTEGER NOT NULL);
CREATE TABLE no_fly_zones(zone_id TEXT PRIMARY KEY, zone_json TEXT NOT NULL, valid_until_utc_ns INTEGER NOT NULL);
CREATE TABLE fleet_allocations(request_id TEXT PRIMARY KEY, status_json TEXT NOT NULL);
CREATE TABLE owner(instance_id TEXT NOT NULL);
)sql";

Error refused(const SqliteDb& db, const std::string& what) {
  return make_error(ErrorCode::kParseError, db.path(),
                    "state journal " + db.path() + ": " + what +
                        "; skyrouted will not start on it (move the file aside to start with an empty journal)");
}

// "ok", or the first problem SQLite's quick check reports; an error when the file is no database.
Result<std::string> quickCheck(SqliteDb& db) {
  auto check = db.prepare("PRAGMA quick_check");
  if (!check.ok()) return check.error();
  auto row = check->step();
  if (!row.ok()) return row.error();
  std::string verdict = *row ? check->text(0) : "ok";
  while (row.ok() && *row) row = check->step();
  return verdict;
}

Result<std::int64_t> countOf(SqliteDb& db, const std::string& sql) {
  auto query = db.prepare(sql);
  if (!query.ok()) return query.error();
  auto row = query->step();
  if (!row.ok()) return row.error();
  const std::int64_t n = *row ? query->integer(0) : 0;
  if (*row) (void)query->step();
  return n;
}

Status migrateV1ToV2(SqliteDb& db) {
  if (Status s = db.exec(kMigrateV1ToV2); !s.ok()) return s;
  auto trajectories = db.prepare("SELECT vehicle_id, record FROM trajectories");
  auto set_end = db.prepare("UPDATE trajectories SET ends_utc_ns = ?2 WHERE vehicle_id = ?1");
  if (!trajectories.ok()) return trajectories.error();
  if (!set_end.ok()) return set_end.error();
  std::vector<std::pair<std::string, std::int64_t>> ends;
  for (auto row = trajectories->step(); row.ok() && *row; row = trajectories->step()) {
    auto decoded = decodeTrajectory(trajectories->text(1));
    if (!decoded.ok()) return refused(db, "vehicle '" + trajectories->text(0) + "': " + decoded.error().message);
    ends.emplace_back(trajectories->text(0), decoded->samples.empty() ? 0 : decoded->samples.back().utc_ns);
  }
  for (const auto& [vehicle, end] : ends) {
    if (Status s = set_end->bind(1, vehicle).bind(2, end).run(); !s.ok()) return s;
  }
  auto obstacles = db.prepare("SELECT obstacle_id, update_json FROM obstacles");
  auto set_until = db.prepare("UPDATE obstacles SET valid_until_utc_ns = ?2 WHERE obstacle_id = ?1");
  if (!obstacles.ok()) return obstacles.error();
  if (!set_until.ok()) return set_until.error();
  std::vector<std::pair<std::int64_t, std::int64_t>> untils;
  for (auto row = obstacles->step(); row.ok() && *row; row = obstacles->step()) {
    const auto parsed = nlohmann::json::parse(obstacles->text(1), nullptr, false);
    auto update = obstacleRecordFromJson(parsed);
    if (!update.ok()) return refused(db, "obstacle " + std::to_string(obstacles->integer(0)) + ": " + update.error().message);
    untils.emplace_back(obstacles->integer(0), update->valid_until_utc_ns);
  }
  for (const auto& [id, until] : untils) {
    if (Status s = set_until->bind(1, id).bind(2, until).run(); !s.ok()) return s;
  }
  return Status::success();
}

}  // namespace

const std::vector<JournalTable>& journalTables() {
  static const std::vector<JournalTable> tables = {
      {"missions", {"vehicle_id", "request_id"}, "request_json",
       "row_checksum(vehicle_id, request_id, request_json, state, accepted_utc_ns, flight_start_utc_ns)"},
      {"trajectories", {"vehicle_id"}, "record",
       "row_checksum(vehicle_id, plan_id, revision, request_id, record, ends_utc_ns)"},
      {"obstacles", {"obstacle_id"}, "update_json", "row_checksum(obstacle_id, update_json, valid_until_utc_ns)"},
      {"no_fly_zones", {"zone_id"}, "zone_json", "row_checksum(zone_id, zone_json, valid_until_utc_ns)"},
      {"fleet_allocations", {"request_id"}, "status_json", "row_checksum(request_id, status_json)"},
      {"meta", {"key"}, "value", "row_checksum(key, value)"},
      {"owner", {"instance_id"}, "instance_id", "row_checksum(instance_id)"},
      {"shard_requests", {"key"}, "request_json",
       "row_checksum(key, kind, vehicle_id, request_id, request_json, seen_utc_ns)"},
      {"shard_lives", {"started_utc_ns"}, "covered_until_utc_ns", "row_checksum(started_utc_ns, covered_until_utc_ns)"},
  };
  return tables;
}

const JournalTable& journalTable(const std::string& name) {
  for (const JournalTable& t : journalTables()) {
    if (name == t.name) return t;
  }
  return journalTables().front();  // never: callers name the tables above
}

Result<int> prepareJournalSchema(SqliteDb& db) {
  if (Status s = db.defineRowChecksum(); !s.ok()) return s.error();
  auto verdict = quickCheck(db);
  if (!verdict.ok()) return refused(db, "not a readable SQLite database (" + verdict.error().message + ")");
  if (*verdict != "ok") return refused(db, "the database is damaged (" + *verdict + ")");
  auto tables = countOf(db, "SELECT count(*) FROM sqlite_master WHERE type = 'table'");
  if (!tables.ok()) return refused(db, tables.error().message);
  if (*tables == 0) {
    if (Status s = db.exec(std::string("BEGIN;") + kCurrentSchema + "INSERT INTO schema_version VALUES (" +
                           std::to_string(kJournalSchemaVersion) + "); COMMIT;");
        !s.ok()) {
      return s.error();
    }
    return 0;
  }
  auto has_version = countOf(db, "SELECT count(*) FROM sqlite_master WHERE type = 'table' AND name = 'schema_version'");
  if (!has_version.ok()) return refused(db, has_version.error().message);
  if (*has_version == 0) return refused(db, "not a skyroute state journal (it has no schema_version table)");
  auto rows = countOf(db, "SELECT count(*) FROM schema_version");
  auto version = countOf(db, "SELECT max(version) FROM schema_version");
  if (!rows.ok() || !version.ok() || *rows != 1) {
    return refused(db, "its schema_version table must hold exactly one version");
  }
  if (*version > kJournalSchemaVersion) {
    return refused(db, "written with journal schema version " + std::to_string(*version) +
                           " by a newer skyrouted; this one reads versions 1 to " +
                           std::to_string(kJournalSchemaVersion));
  }
  if (*version < 1) return refused(db, "schema version " + std::to_string(*version) + " is not a valid version");
  if (*version == kJournalSchemaVersion) return static_cast<int>(*version);
  if (Status s = db.exec("BEGIN IMMEDIATE"); !s.ok()) return s.error();
  Status migrated = *version < 2 ? migrateV1ToV2(db) : Status::success();
  if (migrated.ok() && *version < 3) migrated = db.exec(kMigrateV2ToV3);
  if (migrated.ok()) migrated = db.exec(kMigrateV3ToV4);
  for (const JournalTable& table : journalTables()) {
    if (!migrated.ok()) break;
    auto has = countOf(db, std::string("SELECT count(*) FROM pragma_table_info('") + table.name + "') WHERE name = 'checksum'");
    if (!has.ok()) migrated = has.error();
    if (migrated.ok() && *has == 0) {
      migrated = db.exec(std::string("ALTER TABLE ") + table.name + " ADD COLUMN checksum INTEGER NOT NULL DEFAULT 0");
    }
    if (migrated.ok()) migrated = db.exec(std::string("UPDATE ") + table.name + " SET checksum = " + table.checksum);
  }
  if (migrated.ok()) migrated = db.exec("UPDATE schema_version SET version = 4");
  if (!migrated.ok()) {
    (void)db.exec("ROLLBACK");
    return migrated.error();
  }
  if (Status s = db.exec("COMMIT"); !s.ok()) return s.error();
  return static_cast<int>(*version);
}

}  // namespace skyroute
