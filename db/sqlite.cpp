#include "db/sqlite.h"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <array>
#include <atomic>
#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <limits>
#include <mutex>
#include <utility>
#include <vector>

#include "common/error.h"
#include "util/unique_fd.h"

namespace napkin::db {

namespace internal {

void ThrowSqliteError(sqlite3* db, int code, const char* call, std::string_view context, const char* file,
                      int line) {
  const int extended = db != nullptr ? sqlite3_extended_errcode(db) : code;
  const char* message = db != nullptr ? sqlite3_errmsg(db) : sqlite3_errstr(code);
  std::string text = "SQLite error '";
  text += message;
  // The function called, without its arguments: the call as written in
  // the source stays out of the message (README: errors never show source
  // code); location() keeps it, for debugging.
  const std::string_view call_text(call);
  text += "' (" + std::to_string(extended) + ") in ";
  text += call_text.substr(0, call_text.find('('));
  if (!context.empty()) {
    // One line: the first line of the SQL (or the file name), shortened.
    std::string_view shown = context.substr(0, context.find('\n'));
    const bool cut = shown.size() < context.size() || shown.size() > 100;
    text += " while running '";
    text += shown.substr(0, 100);
    text += cut ? "...'" : "'";
  }
  text += ".";
  throw DatabaseError(text, extended != 0 ? extended : code,
                      std::string(file) + ":" + std::to_string(line) + ": " + call);
}

}  // namespace internal

// ---------------------------------------------------------------- Statement

Statement::Statement(sqlite3* db, std::string_view sql) : db_(db), sql_(sql) {
  // PERSISTENT: the statement lives as long as the connection.
  NAPKIN_SQLITE_CHECK(db_,
                      sqlite3_prepare_v3(db_, sql_.data(), static_cast<int>(sql_.size()),
                                         SQLITE_PREPARE_PERSISTENT, &statement_, nullptr),
                      sql_);
}

Statement::~Statement() { sqlite3_finalize(statement_); }

void Statement::Bind(int index, std::nullopt_t) {
  NAPKIN_SQLITE_CHECK(db_, sqlite3_bind_null(statement_, index), sql_);
}

void Statement::Bind(int index, std::string_view text) {
  NAPKIN_SQLITE_CHECK(
      db_, sqlite3_bind_text64(statement_, index, text.data(), text.size(), SQLITE_TRANSIENT, SQLITE_UTF8),
      sql_);
}

void Statement::Bind(int index, std::span<const std::byte> blob) {
  // A zero-length blob must still be a BLOB, not NULL: pass a valid pointer.
  static const std::byte kEmpty{};
  const void* data = blob.empty() ? static_cast<const void*>(&kEmpty) : blob.data();
  NAPKIN_SQLITE_CHECK(db_, sqlite3_bind_blob64(statement_, index, data, blob.size(), SQLITE_TRANSIENT), sql_);
}

void Statement::BindInt64(int index, std::int64_t value) {
  NAPKIN_SQLITE_CHECK(db_, sqlite3_bind_int64(statement_, index, value), sql_);
}

void Statement::BindDouble(int index, double value) {
  NAPKIN_SQLITE_CHECK(db_, sqlite3_bind_double(statement_, index, value), sql_);
}

bool Statement::Step() { return NAPKIN_SQLITE_CHECK(db_, sqlite3_step(statement_), sql_) == SQLITE_ROW; }

void Statement::Execute() {
  while (Step()) {
  }
}

int Statement::ColumnCount() const { return sqlite3_column_count(statement_); }

std::string Statement::ColumnName(int column) const {
  const char* name = sqlite3_column_name(statement_, column);
  return name != nullptr ? name : "";
}

int Statement::ColumnType(int column) const { return sqlite3_column_type(statement_, column); }

std::int64_t Statement::ColumnInt64(int column) const { return sqlite3_column_int64(statement_, column); }

double Statement::ColumnDouble(int column) const {
  if (ColumnIsNull(column)) return std::numeric_limits<double>::quiet_NaN();
  return sqlite3_column_double(statement_, column);
}

std::string Statement::ColumnText(int column) const {
  const auto* text = reinterpret_cast<const char*>(sqlite3_column_text(statement_, column));
  const int size = sqlite3_column_bytes(statement_, column);
  return text != nullptr ? std::string(text, static_cast<std::size_t>(size)) : std::string();
}

std::optional<std::string> Statement::ColumnOptionalText(int column) const {
  if (ColumnIsNull(column)) return std::nullopt;
  return ColumnText(column);
}

std::span<const std::byte> Statement::ColumnBlob(int column) const {
  const void* data = sqlite3_column_blob(statement_, column);
  const int size = sqlite3_column_bytes(statement_, column);
  if (data == nullptr || size <= 0) return {};
  return {static_cast<const std::byte*>(data), static_cast<std::size_t>(size)};
}

void Statement::Reset() noexcept {
  sqlite3_reset(statement_);
  sqlite3_clear_bindings(statement_);
}

StatementUse::StatementUse(Statement& statement) : statement_(statement) {
  if (statement_.in_use)
    throw std::logic_error("statement '" + std::string(statement_.sql()) + "' is already in use");
  statement_.in_use = true;
}

StatementUse::~StatementUse() {
  statement_.Reset();
  statement_.in_use = false;
}

// --------------------------------------------------------------- Connection

namespace {

// ------------------------------------------------------- what is opened
//
// The catalogue (and a results file, a shard) must be a regular file or a
// name not yet taken (docs/formats.md "The catalogue file"). The decision is
// taken on what is opened, not on a path looked at before: napkin opens the
// name itself (O_PATH: a named pipe does not block) and refuses what
// fstat says is no regular file before SQLite sees it; then SQLite opens the
// name, and the descriptor *SQLite* opened is checked again, so a name
// swapped in between (for a pipe, a device, another file) is refused before
// a single byte is read or written, and nothing is created beside it (SQLite
// creates its journal, -wal and -shm files only on the first read or write).
//
// To see that descriptor, napkin hooks the "open" system call of SQLite's
// unix VFS (sqlite3_vfs::xSetSystemCall, SQLite "OS Interface") once per
// process. Outside Connection::Open the hook calls SQLite's own open
// unchanged; while this thread is in sqlite3_open_v2 it adds O_NONBLOCK (so
// a pipe swapped in cannot block SQLite's open either) and records the
// identity (fstat) of each file opened. A handle to the name as a path
// (/proc/self/fd/N) is no alternative: SQLite derives the journal's name from
// the name it is given.

struct OpenedFile {
  std::string name;
  struct stat status {};
};

using PosixOpen = int (*)(const char*, int, int);
std::atomic<PosixOpen> g_sqlite_open{nullptr};
// While this thread is in sqlite3_open_v2: the files SQLite opened.
thread_local std::vector<OpenedFile>* t_opened = nullptr;

int OpenRecorded(const char* name, int flags, int mode) {
  const PosixOpen sqlite_open = g_sqlite_open.load();
  if (t_opened == nullptr) return sqlite_open(name, flags, mode);
  const int fd = sqlite_open(name, flags | O_NONBLOCK, mode);
  OpenedFile opened;
  if (fd >= 0 && ::fstat(fd, &opened.status) == 0) {
    opened.name = name;
    t_opened->push_back(std::move(opened));
  }
  return fd;
}

// Installs OpenRecorded in SQLite's unix VFS, once; false when the VFS
// offers no system-call hook (then only the check before SQLite opens, and
// the name's identity after, apply).
bool HookSqliteOpen() {
  static std::once_flag once;
  static bool hooked = false;
  std::call_once(once, [] {
    sqlite3_initialize();
    sqlite3_vfs* vfs = sqlite3_vfs_find("unix");
    if (vfs == nullptr || vfs->iVersion < 3 || vfs->xGetSystemCall == nullptr ||
        vfs->xSetSystemCall == nullptr)
      return;
    const sqlite3_syscall_ptr original = vfs->xGetSystemCall(vfs, "open");
    if (original == nullptr) return;
    g_sqlite_open.store(reinterpret_cast<PosixOpen>(original));
    hooked =
        vfs->xSetSystemCall(vfs, "open", reinterpret_cast<sqlite3_syscall_ptr>(&OpenRecorded)) == SQLITE_OK;
  });
  return hooked;
}

// Records the files this thread's SQLite opens while it lives.
class RecordOpens {
 public:
  RecordOpens() { t_opened = &opened_; }
  ~RecordOpens() { t_opened = nullptr; }
  RecordOpens(const RecordOpens&) = delete;
  RecordOpens& operator=(const RecordOpens&) = delete;
  const std::vector<OpenedFile>& opened() const { return opened_; }

 private:
  std::vector<OpenedFile> opened_;
};

// "a directory", "a named pipe (FIFO)", ... for a file that is no regular file.
std::string KindOf(mode_t mode) {
  if (S_ISDIR(mode)) return "a directory";
  if (S_ISFIFO(mode)) return "a named pipe (FIFO)";
  if (S_ISCHR(mode)) return "a character device";
  if (S_ISBLK(mode)) return "a block device";
  if (S_ISSOCK(mode)) return "a socket";
  return "no regular file";
}

InputError NotAFile(const ConnectionOptions& options, const std::string& path, mode_t mode) {
  return InputError(options.what + " '" + path + "' is " + KindOf(mode) +
                    ", not a file; give the name of a regular file, or a name not yet taken.");
}

FileIdentity IdentityOf(const struct stat& status) {
  return {static_cast<std::uint64_t>(status.st_dev), static_cast<std::uint64_t>(status.st_ino)};
}

// Opens `path` for a look at what it is, links followed as SQLite follows
// them. O_PATH: the open never blocks (a named pipe) and reads nothing, and
// closing the descriptor releases none of this process's POSIX locks on the
// file (closing any other descriptor of a file drops them all, those of
// SQLite's connections to it included: fcntl(2), "Advisory record locking").
int OpenToIdentify(const std::string& path) { return ::open(path.c_str(), O_PATH | O_CLOEXEC); }

// Whether the file exists and nobody may write it. Checked in addition to
// sqlite3_db_readonly because a privileged user (root in a container) can
// write a write-protected file, and the protection expresses intent.
bool IsWriteProtected(const std::string& path) {
  std::error_code error;
  const auto status = std::filesystem::status(path, error);
  if (error || !std::filesystem::is_regular_file(status)) return false;
  using std::filesystem::perms;
  return (status.permissions() & (perms::owner_write | perms::group_write | perms::others_write)) ==
         perms::none;
}

// The directory that holds the file `path` names.
std::filesystem::path DirectoryOf(const std::string& path) {
  const std::filesystem::path parent = std::filesystem::path(path).parent_path();
  return parent.empty() ? std::filesystem::path(".") : parent;
}

// Whether this process may create files in `directory`: access(2) applies
// the effective user's permissions and refuses a read-only file system.
bool MayCreateFilesIn(const std::filesystem::path& directory) {
  return ::access(directory.c_str(), W_OK) == 0;
}

// The URI that opens `path` as an immutable database (SQLite "URI
// Filenames": no locks and no -shm file), '%', '?' and '#' percent-encoded.
std::string ImmutableUri(const std::string& path) {
  std::string uri = "file:";
  for (const char c : path) {
    if (c == '%' || c == '?' || c == '#') {
      char escaped[4];
      std::snprintf(escaped, sizeof escaped, "%%%02X", static_cast<unsigned>(static_cast<unsigned char>(c)));
      uri += escaped;
    } else {
      uri += c;
    }
  }
  return uri + "?immutable=1";
}

// SQLITE_TRACE_PROFILE: "sql profile <ms> ms: <statement with its values>" per statement run.
int ProfileStatement(unsigned type, void*, void* statement, void* nanoseconds) {
  if (type != SQLITE_TRACE_PROFILE) return 0;
  auto* prepared = static_cast<sqlite3_stmt*>(statement);
  char* expanded = sqlite3_expanded_sql(prepared);
  const double ms = static_cast<double>(*static_cast<sqlite3_int64*>(nanoseconds)) / 1e6;
  std::fprintf(stderr, "sql profile %.3f ms: %.300s\n", ms,
               expanded != nullptr ? expanded : sqlite3_sql(prepared));
  sqlite3_free(expanded);
  return 0;
}

}  // namespace

std::optional<FileIdentity> IdentifyFile(const std::string& path) {
  const util::UniqueFd file(OpenToIdentify(path));
  struct stat status {};
  if (file.get() < 0 || ::fstat(file.get(), &status) != 0) return std::nullopt;
  return IdentityOf(status);
}

Connection Connection::Open(const std::string& path, const ConnectionOptions& options) {
  Connection connection;
  connection.path_ = path;
  connection.read_only_ = options.read_only;
  const bool plain_file = !connection.in_memory() && path.rfind("file:", 0) != 0;
  // What the name leads to, decided on a descriptor (see "what is opened"
  // above), kept open until SQLite has opened the file so its identity
  // cannot pass to another file meanwhile. A name not yet taken is created
  // by SQLite (for writing) or refused by it (for reading).
  const util::UniqueFd named(plain_file ? OpenToIdentify(path) : -1);
  std::optional<struct stat> named_status;
  if (named.get() >= 0) {
    struct stat status {};
    if (::fstat(named.get(), &status) == 0) named_status = status;
    if (named_status && !S_ISREG(named_status->st_mode)) throw NotAFile(options, path, named_status->st_mode);
  }
  const bool exists = named_status.has_value();

  // SQLite keeps its journal (the -wal and -shm files of a WAL catalogue)
  // beside the catalogue, so writing needs a writable directory. Reading a
  // WAL catalogue needs one too, to create the -shm file, unless the file
  // is opened immutable: right when the directory is read-only and there is
  // no -wal file, since then no process can be writing it (SQLite "WAL
  // mode", read-only databases).
  const std::filesystem::path directory = DirectoryOf(path);
  std::error_code error;
  const bool directory_read_only =
      plain_file && std::filesystem::is_directory(directory, error) && !MayCreateFilesIn(directory);
  if (directory_read_only && !options.read_only)
    throw InputError("cannot write " + options.what + " '" + path + "': its directory '" +
                     directory.string() +
                     "' is read-only and SQLite keeps its journal beside the catalogue; make the directory "
                     "writable or copy the catalogue to a writable directory.");
  const std::string wal_path = path + "-wal";
  const bool wal_present = std::filesystem::exists(wal_path, error);
  if (options.immutable) {
    if (!options.read_only) throw std::invalid_argument("Connection::Open: immutable needs read_only");
    if (!plain_file)
      throw InputError(options.what + " '" + path +
                       "' must be named by its file name (not a URI) to be read shared.");
    if (!exists) throw InputError(options.what + " '" + path + "' does not exist.");
    // An immutable reader sees only the main file: changes still in a
    // write-ahead log (or a hot rollback journal) would be silently missing.
    const std::array<std::string, 2> logs = {wal_path, path + "-journal"};
    const auto unwritten = std::find_if(logs.begin(), logs.end(), [&](const std::string& log) {
      return std::filesystem::exists(log, error) && std::filesystem::file_size(log, error) > 0;
    });
    if (unwritten != logs.end())
      throw InputError(options.what + " '" + path + "' has changes not yet written into it (in '" +
                       *unwritten + "'); let the process writing it finish, or run `sqlite3 '" + path +
                       "' 'PRAGMA wal_checkpoint(TRUNCATE)'` where it is writable, then run the command "
                       "again.");
  }
  const bool immutable = (options.immutable || (directory_read_only && !wal_present)) && exists;
  // A read-only connection cannot remove the -wal and -shm files it makes
  // when it closes (it may not checkpoint), so reading alone would leave
  // them behind. Reading a file this process may write opens it read-write
  // with PRAGMA query_only (no statement can change it): closing the last
  // connection then checkpoints nothing new and removes both, while a
  // connection of another process keeps them (db/README.md "Opening").
  const bool query_only = options.read_only && !immutable && exists && plain_file &&
                          ::access(path.c_str(), W_OK) == 0 && !IsWriteProtected(path);
  int flags = (options.read_only && !query_only ? SQLITE_OPEN_READONLY
               : options.read_only              ? SQLITE_OPEN_READWRITE
                                                : SQLITE_OPEN_READWRITE | SQLITE_OPEN_CREATE) |
              SQLITE_OPEN_NOMUTEX;
  std::string file_name = path;
  if (immutable) {
    file_name = ImmutableUri(path);
    flags |= SQLITE_OPEN_URI;
  }
  const bool hooked = !connection.in_memory() && HookSqliteOpen();
  int opened = SQLITE_OK;
  std::vector<OpenedFile> sqlite_opened;
  {
    const RecordOpens record;
    opened = sqlite3_open_v2(file_name.c_str(), &connection.db_, flags, nullptr);
    sqlite_opened = record.opened();
  }
  if (opened != SQLITE_OK) {
    const std::string reason =
        connection.db_ != nullptr ? sqlite3_errmsg(connection.db_) : sqlite3_errstr(opened);
    throw InputError("cannot open " + options.what + " '" + path + "' (" + reason + ").");
  }
  if (!connection.in_memory()) {
    // The file SQLite opened: the descriptor it got when the hook saw it,
    // else (no hook, or a descriptor SQLite reused) what its name leads to now.
    const char* main_file = sqlite3_db_filename(connection.db_, "main");
    std::optional<struct stat> sqlite_status;
    if (hooked && main_file != nullptr)
      for (const OpenedFile& file : sqlite_opened)
        if (file.name == main_file) sqlite_status = file.status;
    if (!sqlite_status && main_file != nullptr && *main_file != '\0') {
      struct stat status {};
      if (::stat(main_file, &status) == 0) sqlite_status = status;
    }
    if (sqlite_status) {
      if (!S_ISREG(sqlite_status->st_mode)) throw NotAFile(options, path, sqlite_status->st_mode);
      if (named_status && IdentityOf(*sqlite_status) != IdentityOf(*named_status))
        throw InputError(options.what + " '" + path +
                         "' was replaced by another file while it was being opened; run the command again.");
      connection.identity_ = IdentityOf(*sqlite_status);
    }
  }
  NAPKIN_SQLITE_CHECK(connection.db_, sqlite3_extended_result_codes(connection.db_, 1), path);
  NAPKIN_SQLITE_CHECK(connection.db_, sqlite3_busy_timeout(connection.db_, options.busy_timeout_ms), path);
  if (query_only) connection.Execute("PRAGMA query_only = ON");
  // NAPKIN_SQL_PROFILE=1: each statement's time on standard error, for
  // finding the statement whose cost grows with the catalogue
  // (docs/developing.md "Profiling the catalogue").
  if (const char* profile = std::getenv("NAPKIN_SQL_PROFILE"); profile != nullptr && *profile == '1')
    sqlite3_trace_v2(connection.db_, SQLITE_TRACE_PROFILE, &ProfileStatement, nullptr);

  // SQLite reads the header lazily: the first statement tells whether this
  // is a database at all.
  const int probe =
      sqlite3_exec(connection.db_, "SELECT count(*) FROM sqlite_master", nullptr, nullptr, nullptr);
  if ((probe & 0xff) == SQLITE_NOTADB)
    throw InputError("'" + path + "' is not a napkin catalogue (not an SQLite database).");
  if (probe != SQLITE_OK && directory_read_only && wal_present)
    throw InputError("cannot read " + options.what + " '" + path + "': its directory '" + directory.string() +
                     "' is read-only and holds its unfinished write-ahead log '" + wal_path +
                     "'; make the directory writable and run the command again.");
  NAPKIN_SQLITE_CHECK(connection.db_, probe, path);

  if (!options.read_only && !connection.in_memory() &&
      (sqlite3_db_readonly(connection.db_, "main") == 1 || IsWriteProtected(path)))
    throw InputError(options.what + " '" + path + "' is read-only.");

  connection.Execute("PRAGMA foreign_keys = ON");
  return connection;
}

std::optional<FileIdentity> Connection::FileIdentityOf() const { return identity_; }

void Connection::Close() noexcept {
  statements_.clear();  // finalize before close
  if (db_ != nullptr) sqlite3_close_v2(db_);
  db_ = nullptr;
}

Connection::~Connection() { Close(); }

Connection::Connection(Connection&& other) noexcept
    : db_(std::exchange(other.db_, nullptr)),
      path_(std::move(other.path_)),
      read_only_(other.read_only_),
      identity_(other.identity_),
      statements_(std::move(other.statements_)) {}

Connection& Connection::operator=(Connection&& other) noexcept {
  if (this != &other) {
    Close();
    db_ = std::exchange(other.db_, nullptr);
    path_ = std::move(other.path_);
    read_only_ = other.read_only_;
    identity_ = other.identity_;
    statements_ = std::move(other.statements_);
  }
  return *this;
}

void Connection::Execute(std::string_view sql) {
  const std::string text(sql);  // sqlite3_exec needs a NUL-terminated string
  NAPKIN_SQLITE_CHECK(db_, sqlite3_exec(db_, text.c_str(), nullptr, nullptr, nullptr), sql);
}

StatementUse Connection::Prepare(std::string_view sql) {
  auto found = statements_.find(std::string(sql));
  if (found == statements_.end())
    found = statements_.emplace(std::string(sql), std::make_unique<Statement>(db_, sql)).first;
  return StatementUse(*found->second);
}

std::int64_t Connection::PragmaInt(std::string_view pragma) {
  auto statement = Prepare("PRAGMA " + std::string(pragma));
  if (!statement->Step())
    throw DatabaseError("PRAGMA " + std::string(pragma) + " returned no value.", SQLITE_ERROR);
  return statement->ColumnInt64(0);
}

std::int64_t Connection::LastInsertRowId() const { return sqlite3_last_insert_rowid(db_); }

int Connection::Changes() const { return sqlite3_changes(db_); }

bool Connection::InTransaction() const { return sqlite3_get_autocommit(db_) == 0; }

// -------------------------------------------------------------- Transaction

Transaction::Transaction(Connection& connection, Mode mode) : connection_(connection) {
  savepoint_ = connection_.InTransaction();
  if (savepoint_)
    connection_.Execute("SAVEPOINT napkin_nested");
  else
    connection_.Execute(mode == Mode::kImmediate ? "BEGIN IMMEDIATE" : "BEGIN DEFERRED");
}

Transaction::~Transaction() {
  if (finished_) return;
  // Roll back; errors are ignored because SQLite may already have rolled the
  // transaction back itself (e.g. after SQLITE_FULL), and a destructor must
  // not throw.
  const char* sql = savepoint_ ? "ROLLBACK TO napkin_nested; RELEASE napkin_nested" : "ROLLBACK";
  sqlite3_exec(connection_.handle(), sql, nullptr, nullptr, nullptr);
}

void Transaction::Commit() {
  if (finished_) throw std::logic_error("transaction committed twice");
  connection_.Execute(savepoint_ ? "RELEASE napkin_nested" : "COMMIT");
  finished_ = true;
}

}  // namespace napkin::db
