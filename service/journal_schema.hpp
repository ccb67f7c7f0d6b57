// The state journal's SQLite schema and its versions. Version 1 kept missions, trajectories and
// obstacles; version 2 adds when each mission was accepted and its flight started, each
// trajectory's and obstacle's end (so ended ones are pruned), no-fly zones, fleet allocations,
// the plan counter and the daemon instance that last opened it; version 3 (current) a shard's
// copy of every request it read and the lives of the shard (shard_coverage.hpp). A journal of
// an older version is migrated in one transaction; a newer one, a file that is not a skyroute
// journal, or a damaged one, is refused with an error naming the file and what is wrong.
#pragma once

#include "planning/core/result.hpp"
#include "service/sqlite_db.hpp"

namespace skyroute {

inline constexpr int kJournalSchemaVersion = 3;

// Checks the file (integrity, schema version), creates the schema in an empty one, migrates an
// older one. Returns the version found (0: the file was new). Errors: kParseError naming the file.
Result<int> prepareJournalSchema(SqliteDb& db);

}  // namespace skyroute
