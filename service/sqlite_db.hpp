// A thin owner of one SQLite connection and its prepared statements, for the state journal:
// errors come back as Error values naming the database file and SQLite's own message, never as
// exceptions or codes to look up.
#pragma once

#include <cstdint>
#include <memory>
#include <string>

#include "planning/core/result.hpp"

struct sqlite3;
struct sqlite3_stmt;

namespace skyroute {

class SqliteStatement {
 public:
  SqliteStatement(sqlite3* db, sqlite3_stmt* statement, std::string path);
  ~SqliteStatement();
  SqliteStatement(SqliteStatement&& other) noexcept;
  SqliteStatement& operator=(SqliteStatement&&) = delete;
  SqliteStatement(const SqliteStatement&) = delete;
  SqliteStatement& operator=(const SqliteStatement&) = delete;

  // Parameters count from 1, as in SQL's ?1, ?2.
  SqliteStatement& bind(int index, const std::string& text);
  SqliteStatement& bindBlob(int index, const std::string& bytes);
  SqliteStatement& bind(int index, std::int64_t value);
  // Steps once: true while a row is there; an error names the file. Statements are reset after
  // their last row, so one can run again with new parameters.
  Result<bool> step();
  Status run();  // steps to the end

  std::int64_t integer(int column) const;
  std::string text(int column) const;   // also a blob's bytes
  bool isNull(int column) const;

 private:
  sqlite3* db_;
  sqlite3_stmt* statement_;
  std::string path_;
};

class SqliteDb {
 public:
  // Opens (creating when absent) the file read-write. Errors name the file.
  static Result<std::unique_ptr<SqliteDb>> open(const std::string& path);
  ~SqliteDb();
  SqliteDb(const SqliteDb&) = delete;
  SqliteDb& operator=(const SqliteDb&) = delete;

  const std::string& path() const { return path_; }
  Status exec(const std::string& sql);  // one or more statements, no parameters, rows ignored
  Result<SqliteStatement> prepare(const std::string& sql);
  // An error naming the file, what was being done and SQLite's last message.
  Error error(const std::string& doing) const;
  // Whether the last failure was the disk (or the file's size limit) being full: SQLITE_FULL.
  bool lastFailureWasFull() const;
  // Defines the SQL function row_checksum(a, b, ...) on this connection: the CRC-32 (zlib) of its
  // arguments, each taken as a type tag, its length and its bytes (integers as 8 little-endian
  // bytes, text and blobs as they are, NULL as the tag alone), so ('ab', 'c') and ('a', 'bc')
  // differ. A record's checksum is written with it and checked against it when read.
  Status defineRowChecksum();

 private:
  SqliteDb(sqlite3* db, std::string path) : db_(db), path_(std::move(path)) {}
  sqlite3* db_;
  std::string path_;
};

}  // namespace skyroute
