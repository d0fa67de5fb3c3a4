#include "app/failure.h"

#include <fmt/format.h>

#include <new>

#include "common/error.h"
#include "db/sqlite.h"
#include "engine/pipeline.h"

namespace napkin::app {

Failure DescribeFailure(const std::exception_ptr& error, const std::string& db_path) {
  try {
    std::rethrow_exception(error);
  } catch (const UsageError& usage) {
    return {FailureCategory::kUsage, usage.what()};
  } catch (const engine::ScreeningFailure& screening) {
    return {FailureCategory::kScreening, screening.what(), screening.findings()};
  } catch (const NotFoundError& missing) {
    return {FailureCategory::kNotFound, missing.what()};
  } catch (const InputError& input) {
    return {FailureCategory::kInput, input.what()};
  } catch (const db::DatabaseError& database) {
    if (database.busy())
      return {FailureCategory::kCatalogueBusy,
              // Any SQLite client may hold the lock (sqlite3, a backup tool), not only napkin; SQLite's own
              // text ("database is locked ... in probe while running 'lab.db'") adds nothing to this.
              fmt::format(
                  "catalogue '{}' is busy: another process (a napkin command, sqlite3 or any other SQLite "
                  "client) has held its lock longer than the wait allows; run the command again when that "
                  "process has finished.",
                  db_path)};
    if (database.full())
      return {FailureCategory::kCatalogue,
              fmt::format(
                  "catalogue '{}' could not be written: the disk holding it is full; free space there (or "
                  "move the catalogue to a larger disk) and run the command again, the work committed "
                  "before is kept.",
                  db_path)};
    if (database.corrupt())
      return {FailureCategory::kCatalogue,
              fmt::format(
                  "catalogue '{}' is damaged (SQLite finds a malformed page); restore it from a backup, or "
                  "save what is readable with `sqlite3 {} .recover | sqlite3 recovered.db`.",
                  db_path, db_path)};
    if (database.read_only())
      return {
          FailureCategory::kCatalogue,
          fmt::format("catalogue '{}' cannot be written: the file or its directory is read-only; make both "
                      "writable, or copy the catalogue to a writable directory.",
                      db_path)};
    return {FailureCategory::kCatalogue, fmt::format("catalogue '{}': {}", db_path, database.what())};
  } catch (const std::bad_alloc&) {
    return {
        FailureCategory::kOutOfMemory,
        "out of memory; process fewer tests at once (run --threads 1) or free memory, then run the command "
        "again."};
  } catch (const std::exception& internal) {
    return {FailureCategory::kInternal,
            fmt::format("internal error: {}; this is a bug in napkin, please report it with the command line "
                        "that caused it.",
                        internal.what())};
  } catch (...) {
    return {
        FailureCategory::kInternal,
        "internal error: an unknown exception; this is a bug in napkin, please report it with the command "
        "line that caused it."};
  }
}

}  // namespace napkin::app
