#include "service/sqlite_db.hpp"

#include <sqlite3.h>
#include <zlib.h>

#include <array>
#include <cstdint>
#include <cstring>

namespace skyroute {

namespace {

Error sqliteError(sqlite3* db, const std::string& path, const std::string& doing) {
  const char* message = db ? sqlite3_errmsg(db) : "out of memory";
  return make_error(ErrorCode::kParseError, path, path + ": " + doing + ": " + message);
}

void rowChecksum(sqlite3_context* context, int argc, sqlite3_value** argv) {
  uLong crc = crc32(0L, Z_NULL, 0);
  const auto add = [&crc](const void* bytes, std::size_t n) {
    crc = crc32(crc, static_cast<const Bytef*>(bytes), static_cast<uInt>(n));
  };
  for (int i = 0; i < argc; ++i) {
    const int type = sqlite3_value_type(argv[i]);
    const auto tag = static_cast<unsigned char>(type);
    add(&tag, 1);
    std::array<unsigned char, 8> little{};
    const auto put = [&little](std::uint64_t v) {
      for (std::size_t b = 0; b < 8; ++b) little[b] = static_cast<unsigned char>(v >> (8 * b));
    };
    if (type == SQLITE_INTEGER) {
      put(static_cast<std::uint64_t>(sqlite3_value_int64(argv[i])));
      add(little.data(), little.size());
    } else if (type == SQLITE_FLOAT) {
      const double value = sqlite3_value_double(argv[i]);
      std::uint64_t bits = 0;
      static_assert(sizeof bits == sizeof value);
      std::memcpy(&bits, &value, sizeof bits);
      put(bits);
      add(little.data(), little.size());
    } else if (type != SQLITE_NULL) {
      const void* bytes = sqlite3_value_blob(argv[i]);
      const auto n = static_cast<std::size_t>(sqlite3_value_bytes(argv[i]));
      put(n);
      add(little.data(), little.size());
      if (n > 0) add(bytes, n);
    }
  }
  sqlite3_result_int64(context, static_cast<sqlite3_int64>(crc));
}

}  // namespace

SqliteStatement::SqliteStatement(sqlite3* db, sqlite3_stmt* statement, std::string path)
    : db_(db), statement_(statement), path_(std::move(path)) {}

SqliteStatement::~SqliteStatement() {
  if (statement_) sqlite3_finalize(statement_);
}

SqliteStatement::SqliteStatement(SqliteStatement&& other) noexcept
    : db_(other.db_), statement_(other.statement_), path_(std::move(other.path_)) {
  other.statement_ = nullptr;
}

SqliteStatement& SqliteStatement::bind(int index, const std::string& text) {
  sqlite3_bind_text(statement_, index, text.data(), static_cast<int>(text.size()), SQLITE_TRANSIENT);
  return *this;
}

SqliteStatement& SqliteStatement::bindBlob(int index, const std::string& bytes) {
  sqlite3_bind_blob(statement_, index, bytes.data(), static_cast<int>(bytes.size()), SQLITE_TRANSIENT);
  return *this;
}

SqliteStatement& SqliteStatement::bind(int index, std::int64_t value) {
  sqlite3_bind_int64(statement_, index, value);
  return *this;
}

Result<bool> SqliteStatement::step() {
  const int rc = sqlite3_step(statement_);
  if (rc == SQLITE_ROW) return true;
  sqlite3_reset(statement_);
  sqlite3_clear_bindings(statement_);
  if (rc == SQLITE_DONE) return false;
  return sqliteError(db_, path_, "reading or writing the journal");
}

Status SqliteStatement::run() {
  for (;;) {
    auto row = step();
    if (!row.ok()) return row.error();
    if (!*row) return Status::success();
  }
}

std::int64_t SqliteStatement::integer(int column) const { return sqlite3_column_int64(statement_, column); }

std::string SqliteStatement::text(int column) const {
  const void* data = sqlite3_column_blob(statement_, column);
  const int size = sqlite3_column_bytes(statement_, column);
  return data ? std::string(static_cast<const char*>(data), static_cast<std::size_t>(size)) : std::string();
}

bool SqliteStatement::isNull(int column) const { return sqlite3_column_type(statement_, column) == SQLITE_NULL; }

Result<std::unique_ptr<SqliteDb>> SqliteDb::open(const std::string& path) {
  sqlite3* db = nullptr;
  const int rc = sqlite3_open_v2(path.c_str(), &db, SQLITE_OPEN_READWRITE | SQLITE_OPEN_CREATE | SQLITE_OPEN_NOMUTEX,
                                 nullptr);
  if (rc != SQLITE_OK) {
    Error e = sqliteError(db, path, "cannot open");
    e.code = ErrorCode::kFileNotFound;
    sqlite3_close(db);
    return e;
  }
  sqlite3_busy_timeout(db, 2000);
  return std::unique_ptr<SqliteDb>(new SqliteDb(db, path));
}

SqliteDb::~SqliteDb() { sqlite3_close(db_); }

Status SqliteDb::exec(const std::string& sql) {
  if (sqlite3_exec(db_, sql.c_str(), nullptr, nullptr, nullptr) != SQLITE_OK) return error("running SQL");
  return Status::success();
}

Result<SqliteStatement> SqliteDb::prepare(const std::string& sql) {
  sqlite3_stmt* statement = nullptr;
  if (sqlite3_prepare_v2(db_, sql.c_str(), -1, &statement, nullptr) != SQLITE_OK) return error("preparing a query");
  return SqliteStatement(db_, statement, path_);
}

Error SqliteDb::error(const std::string& doing) const { return sqliteError(db_, path_, doing); }

Status SqliteDb::defineRowChecksum() {
  if (sqlite3_create_function_v2(db_, "row_checksum", -1, SQLITE_UTF8 | SQLITE_DETERMINISTIC, nullptr, rowChecksum,
                                 nullptr, nullptr, nullptr) != SQLITE_OK) {
    return error("defining row_checksum");
  }
  return Status::success();
}

bool SqliteDb::lastFailureWasFull() const { return (sqlite3_extended_errcode(db_) & 0xff) == SQLITE_FULL; }

}  // namespace skyroute
