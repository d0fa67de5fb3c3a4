#pragma once
// Thin RAII layer over the SQLite C API, in the spirit of COLMAP's
// database_sqlite: one checking macro around every sqlite3_* call, prepared
// statements created once per connection and reset by a guard after each use,
// and a transaction guard that ROLLS BACK unless committed (COLMAP's commits
// unconditionally).
#include <sqlite3.h>

#include <concepts>
#include <cstddef>
#include <cstdint>
#include <memory>
#include <optional>
#include <span>
#include <stdexcept>
#include <string>
#include <string_view>
#include <type_traits>
#include <unordered_map>
#include <utility>

namespace napkin::db {

// A failed SQLite call. The message names the SQLite error, the function
// called and its context (the SQL text or the file), e.g. "SQLite error
// 'UNIQUE constraint failed: tests.external_id' (2067) in sqlite3_step while
// running 'INSERT ...'". The source location and the text of the failed call
// are kept apart (location()), out of the message users see (README: errors
// never show a source path or source code).
class DatabaseError : public std::runtime_error {
 public:
  DatabaseError(const std::string& message, int code, std::string location = {})
      : std::runtime_error(message), code_(code), location_(std::move(location)) {}
  // Extended SQLite result code.
  int code() const { return code_; }
  // "file:line: call" of the failed call (empty when not thrown by NAPKIN_SQLITE_CHECK), for debugging.
  const std::string& location() const { return location_; }
  // True for lock contention (SQLITE_BUSY / SQLITE_LOCKED): the operation may be retried.
  bool busy() const { return (code_ & 0xff) == SQLITE_BUSY || (code_ & 0xff) == SQLITE_LOCKED; }
  // True when the disk (or the file-size limit) is full: SQLITE_FULL.
  bool full() const { return (code_ & 0xff) == SQLITE_FULL; }
  // True when the file is damaged or not a database: SQLITE_CORRUPT / SQLITE_NOTADB.
  bool corrupt() const { return (code_ & 0xff) == SQLITE_CORRUPT || (code_ & 0xff) == SQLITE_NOTADB; }
  // True when the file or its directory cannot be written: SQLITE_READONLY.
  bool read_only() const { return (code_ & 0xff) == SQLITE_READONLY; }

 private:
  int code_;
  std::string location_;
};

namespace internal {
[[noreturn]] void ThrowSqliteError(sqlite3* db, int code, const char* call, std::string_view context,
                                   const char* file, int line);

inline int CheckSqlite(sqlite3* db, int code, const char* call, std::string_view context, const char* file,
                       int line) {
  if (code == SQLITE_OK || code == SQLITE_ROW || code == SQLITE_DONE) return code;
  ThrowSqliteError(db, code, call, context, file, line);
}
}  // namespace internal

// Checks the result code of one sqlite3_* call; throws DatabaseError with the
// connection's error message and `context` ("file:line: call text" as its location()).
// Returns the code (SQLITE_OK, SQLITE_ROW or SQLITE_DONE).
#define NAPKIN_SQLITE_CHECK(sqlite_handle, call, context) \
  ::napkin::db::internal::CheckSqlite((sqlite_handle), (call), #call, (context), __FILE__, __LINE__)

// One prepared statement. Owned by its Connection's cache; use through
// Connection::Prepare, whose guard resets it and clears its bindings.
class Statement {
 public:
  Statement(sqlite3* db, std::string_view sql);
  ~Statement();
  Statement(const Statement&) = delete;
  Statement& operator=(const Statement&) = delete;

  // Parameters are 1-based, as in SQLite.
  void Bind(int index, std::nullopt_t);
  void Bind(int index, std::string_view text);
  void Bind(int index, const char* text) { Bind(index, std::string_view(text)); }
  void Bind(int index, const std::string& text) { Bind(index, std::string_view(text)); }
  void Bind(int index, std::span<const std::byte> blob);
  void BindInt64(int index, std::int64_t value);
  // NaN is stored by SQLite as NULL (and reads back as NaN via ColumnDouble).
  void BindDouble(int index, double value);
  template <std::integral T>
  void Bind(int index, T value) {
    BindInt64(index, static_cast<std::int64_t>(value));
  }
  template <std::floating_point T>
  void Bind(int index, T value) {
    BindDouble(index, static_cast<double>(value));
  }
  template <typename E>
  requires std::is_enum_v<E>
  void Bind(int index, E value) { BindInt64(index, static_cast<std::int64_t>(value)); }
  template <typename T>
  void Bind(int index, const std::optional<T>& value) {
    if (value)
      Bind(index, *value);
    else
      Bind(index, std::nullopt);
  }
  // Binds `values` to parameters 1, 2, ...
  template <typename... Values>
  void BindAll(const Values&... values) {
    int index = 0;
    (Bind(++index, values), ...);
  }

  // Advances; true when a row is ready, false when the statement is done.
  bool Step();
  // Steps to completion, expecting no row.
  void Execute();

  int ColumnCount() const;
  std::string ColumnName(int column) const;
  // SQLITE_INTEGER, SQLITE_FLOAT, SQLITE_TEXT, SQLITE_BLOB or SQLITE_NULL.
  int ColumnType(int column) const;
  bool ColumnIsNull(int column) const { return ColumnType(column) == SQLITE_NULL; }
  std::int64_t ColumnInt64(int column) const;
  // NULL reads as NaN (SQLite stores NaN as NULL).
  double ColumnDouble(int column) const;
  std::string ColumnText(int column) const;
  std::optional<std::string> ColumnOptionalText(int column) const;
  // Valid until the next Step/Reset.
  std::span<const std::byte> ColumnBlob(int column) const;

  // Resets and clears bindings; never throws (the error of a failed step was
  // already reported by Step).
  void Reset() noexcept;
  std::string_view sql() const { return sql_; }
  bool in_use = false;  // set by StatementUse: guards against nested reuse

 private:
  sqlite3* db_;
  sqlite3_stmt* statement_ = nullptr;
  std::string sql_;
};

// Scoped use of a cached statement: resets it and clears its bindings on
// destruction, so the next user finds it fresh even after an exception.
class StatementUse {
 public:
  explicit StatementUse(Statement& statement);
  ~StatementUse();
  StatementUse(const StatementUse&) = delete;
  StatementUse& operator=(const StatementUse&) = delete;
  Statement* operator->() { return &statement_; }
  Statement& operator*() { return statement_; }

 private:
  Statement& statement_;
};

struct ConnectionOptions {
  bool read_only = false;       // open without write access (queries only)
  bool durable = true;          // synchronous=FULL: a committed write survives power loss
  int busy_timeout_ms = 30000;  // wait this long for another writer's lock
  // With read_only: open the file immutable (SQLite URI "immutable=1": no
  // locks, no -wal, -shm or journal file created beside it), for a catalogue
  // many processes read at once on a shared file system (`run --results`).
  // Refused (InputError) when a non-empty -wal or -journal file is beside it:
  // an immutable reader would not see those changes.
  bool immutable = false;
  // What the file is to the user, for messages: "catalogue", "results file", "shard".
  std::string what = "catalogue";
};

// Which file a name leads to, after links and URI parsing.
struct FileIdentity {
  std::uint64_t device = 0;
  std::uint64_t inode = 0;
  bool operator==(const FileIdentity&) const = default;
};

// The file `path` leads to (links followed), as the descriptor open(2)
// returns for it tells (opened O_PATH: a named pipe never blocks, and no
// POSIX lock of this process is released when it is closed);
// nullopt when it cannot be opened (e.g. it does not exist). For checks made
// before SQLite opens a file (MergeShard refuses the catalogue itself before
// anything is created beside it).
std::optional<FileIdentity> IdentifyFile(const std::string& path);

// An open SQLite database. ":memory:" opens a private in-memory database.
// Not thread-safe: use one connection per thread (WAL lets several
// connections, threads or processes, share one file).
class Connection {
 public:
  // Throws InputError (one sentence naming `path`) when the file cannot be
  // opened, is not a regular file (a folder, named pipe, device or socket:
  // refused before SQLite opens it, and again on the descriptor SQLite
  // opened, so nothing is ever created beside it), is not an SQLite
  // database, or is read-only while write access was asked for. A read-only
  // connection to a file this process may write is opened read-write with
  // PRAGMA query_only, so that closing the last connection removes the -wal
  // and -shm files (db/README.md "Opening").
  static Connection Open(const std::string& path, const ConnectionOptions& options = {});
  ~Connection();
  Connection(Connection&& other) noexcept;
  Connection& operator=(Connection&& other) noexcept;
  Connection(const Connection&) = delete;
  Connection& operator=(const Connection&) = delete;

  sqlite3* handle() const { return db_; }
  const std::string& path() const { return path_; }
  bool in_memory() const { return path_ == ":memory:" || path_.empty(); }
  bool read_only() const { return read_only_; }
  // Device and inode of the main database file SQLite opened (its
  // descriptor, seen as it was opened); nullopt for an in-memory database.
  std::optional<FileIdentity> FileIdentityOf() const;

  // Runs SQL without parameters (one or more statements: DDL, PRAGMA).
  void Execute(std::string_view sql);
  // The statement for `sql`, prepared on first use and cached for the life
  // of the connection; reset when the returned guard goes out of scope.
  StatementUse Prepare(std::string_view sql);
  // Value of a PRAGMA that returns one integer, e.g. "user_version".
  std::int64_t PragmaInt(std::string_view pragma);
  std::int64_t LastInsertRowId() const;
  int Changes() const;
  bool InTransaction() const;

 private:
  Connection() = default;
  void Close() noexcept;

  sqlite3* db_ = nullptr;
  std::string path_;
  bool read_only_ = false;
  std::optional<FileIdentity> identity_;  // of the main file SQLite opened
  std::unordered_map<std::string, std::unique_ptr<Statement>> statements_;
};

// A transaction that rolls back unless Commit() is called, so an exception
// leaves the database as it was. Write transactions start with BEGIN
// IMMEDIATE (take the write lock up front; under WAL a deferred transaction
// that later writes can fail with SQLITE_BUSY without waiting). Inside an
// open transaction it nests as a SAVEPOINT.
class Transaction {
 public:
  enum class Mode { kImmediate, kDeferred };
  explicit Transaction(Connection& connection, Mode mode = Mode::kImmediate);
  ~Transaction();
  Transaction(const Transaction&) = delete;
  Transaction& operator=(const Transaction&) = delete;
  void Commit();

 private:
  Connection& connection_;
  bool savepoint_ = false;
  bool finished_ = false;
};

}  // namespace napkin::db
