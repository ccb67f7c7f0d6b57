// The state journal's SQLite schema and its versions. Version 1 kept missions, trajectories and
// obstacles; version 2 adds when each mission was accepted and its flight started, each
// trajectory's and obstacle's end (so ended ones are pruned), no-fly zones, fleet allocations,
// the plan counter and the daemon instance that last opened it; version 3 a shard's copy of every
// request it read and the lives of the shard (shard_coverage.hpp); version 4 (current) a checksum
// in every record (row_checksum, sqlite_db.hpp) and the quarantine table, where records that are
// damaged or would be refused today are moved (state_journal.hpp). A journal of an older version
// is migrated in one transaction; a newer one, a file that is not a skyroute journal, or a
// damaged one, is refused with an error naming the file and what is wrong.
#pragma once

#include <string>
#include <vector>

#include "planning/core/result.hpp"
#include "service/sqlite_db.hpp"

namespace skyroute {

inline constexpr int kJournalSchemaVersion = 4;

// A table of records: its key columns (what a log line names), the column kept in the quarantine,
// and the SQL expression of a row's checksum over its columns (written with every row, checked
// when it is read).
struct JournalTable {
  const char* name;
  std::vector<const char*> key_columns;
  const char* payload_column;
  const char* checksum;
};
const std::vector<JournalTable>& journalTables();
const JournalTable& journalTable(const std::string& name);

// Defines row_checksum on the connection, checks the file (integrity, schema version), creates
// the schema in an empty one, migrates an older one. Returns the version found (0: the file was new). Errors: kParseError naming the file.
Result<int> prepareJournalSchema(SqliteDb& db);

}  // namespace skyroute
