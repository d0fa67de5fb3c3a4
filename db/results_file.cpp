// ResultsFile: the catalogue read by many, the results file written by one
// shard (db/results_file.h).
#include "db/results_file.h"

#include <sys/stat.h>

#include <filesystem>

#include "common/error.h"
#include "db/catalogue_internal.h"

namespace napkin::db {

namespace {

// The rows `select` returns go into `table` of `target` with the same
// columns in the same order (both catalogues have the same schema version),
// keys kept. A row whose key is already in `target` must have the same value
// in column `content_column` (a hash or a name); one of another key with the
// same unique values is refused too. `name_column` names the row in
// messages. Returns the number of rows inserted.
std::int64_t CopyRows(Statement& select, Connection& target, const std::string& table,
                      const std::string& content_column, const std::string& name_column,
                      const std::string& conflict_prefix) {
  const int columns = select.ColumnCount();
  int content_index = -1;
  int name_index = -1;
  for (int c = 0; c < columns; ++c) {
    if (select.ColumnName(c) == content_column) content_index = c;
    if (select.ColumnName(c) == name_column) name_index = c;
  }
  if (select.ColumnName(0) != "id" || content_index < 0 || name_index < 0)
    throw std::logic_error("CopyRows: unexpected columns of table " + table);
  std::string insert_sql = "INSERT INTO " + table + " VALUES (";
  for (int c = 0; c < columns; ++c) insert_sql += (c == 0 ? "?" : ", ?") + std::to_string(c + 1);
  insert_sql += ")";
  const std::string existing_sql = "SELECT " + content_column + " FROM " + table + " WHERE id = ?1";

  // The error for the row `select` is on: its content differs from the target's row of its id.
  const auto conflict = [&] {
    const std::string what = table == "tests" ? "test" : table == "arrays" ? "array" : "series";
    return InputError(conflict_prefix + " (its " + what + " '" + select.ColumnText(name_index) +
                      "' differs).");
  };
  std::int64_t inserted = 0;
  while (select.Step()) {
    {
      auto existing = target.Prepare(existing_sql);
      existing->BindInt64(1, select.ColumnInt64(0));
      if (existing->Step()) {
        if (existing->ColumnText(0) != select.ColumnText(content_index)) throw conflict();
        continue;
      }
    }
    auto insert = target.Prepare(insert_sql);
    for (int c = 0; c < columns; ++c) {
      switch (select.ColumnType(c)) {
        case SQLITE_NULL:
          insert->Bind(c + 1, std::nullopt);
          break;
        case SQLITE_INTEGER:
          insert->BindInt64(c + 1, select.ColumnInt64(c));
          break;
        case SQLITE_FLOAT:
          insert->BindDouble(c + 1, select.ColumnDouble(c));
          break;
        case SQLITE_TEXT:
          insert->Bind(c + 1, select.ColumnText(c));
          break;
        default:
          insert->Bind(c + 1, select.ColumnBlob(c));
          break;
      }
    }
    try {
      insert->Execute();
    } catch (const DatabaseError& error) {
      // A unique value (external id, content hash, name) under another key.
      if ((error.code() & 0xff) == SQLITE_CONSTRAINT) throw conflict();
      throw;
    }
    ++inserted;
  }
  return inserted;
}

}  // namespace

Catalogue ResultsFile::OpenSharedCatalogue(const std::string& path) {
  CatalogueOptions options;
  options.read_only = true;
  options.immutable = true;
  return Catalogue::Open(path, options);
}

Catalogue ResultsFile::Open(const std::string& results_path, const Catalogue& catalogue,
                            const CatalogueOptions& options) {
  namespace fs = std::filesystem;
  std::error_code error;
  if (fs::is_directory(results_path, error))
    throw InputError("results file '" + results_path + "' is a directory; name a file in it, e.g. '" +
                     (fs::path(results_path) / "shard-0.db").string() + "'.");
  const fs::path directory = fs::path(results_path).parent_path();
  if (!directory.empty() && !fs::is_directory(directory, error))
    throw InputError("the directory '" + directory.string() + "' of results file '" + results_path +
                     "' does not exist.");
  struct stat status {};
  const std::optional<FileIdentity> catalogue_file = catalogue.connection_.FileIdentityOf();
  if (catalogue_file && ::stat(results_path.c_str(), &status) == 0 &&
      FileIdentity{static_cast<std::uint64_t>(status.st_dev), static_cast<std::uint64_t>(status.st_ino)} ==
          *catalogue_file)
    throw InputError("results file '" + results_path + "' is the catalogue '" + catalogue.connection_.path() +
                     "' itself; name a new file for the results.");
  // A results file left by an earlier run (to be resumed) is checked before
  // anything is written into it; its damage is its own, not the catalogue's.
  if (fs::is_regular_file(results_path, error) && fs::file_size(results_path, error) > 0) {
    const InputError damaged(
        "results file '" + results_path +
        "' is damaged (SQLite finds a malformed page) and was left as it was; it holds "
        "only what `run --results` wrote, so move it aside and run the shard again into a "
        "new results file (the catalogue '" +
        catalogue.connection_.path() + "' is not affected).");
    try {
      ConnectionOptions probe_options;
      probe_options.read_only = true;
      probe_options.what = "results file";
      Connection probe = Connection::Open(results_path, probe_options);
      if (!internal::PassesQuickCheck(probe)) throw damaged;
    } catch (const DatabaseError& failure) {
      if (failure.corrupt()) throw damaged;
      throw;
    }
  }
  CatalogueOptions results_options = options;
  results_options.what = "results file";
  Catalogue results = Catalogue::Open(results_path, results_options);
  if (results.schema_version() != catalogue.schema_version())
    throw InputError("results file '" + results_path + "' has schema version " +
                     std::to_string(results.schema_version()) + ", the catalogue '" +
                     catalogue.connection_.path() + "' " + std::to_string(catalogue.schema_version()) + ".");
  return results;
}

std::int64_t ResultsFile::CopyTests(Catalogue& catalogue, Catalogue& results, const JobScope& scope) {
  const std::string conflict_prefix = "results file '" + results.connection_.path() +
                                      "' was written for another catalogue than '" +
                                      catalogue.connection_.path() + "'; give this one a new results file";
  Transaction transaction(results.connection_);
  // The arrays and series the scope's tests name, keyed as in the catalogue.
  struct Named {
    const char* table;
    const char* test_column;
    const char* unique_column;
    const char* label_column;
  };
  for (const Named& named : {Named{"arrays", "array_id", "definition_hash", "name"},
                             Named{"series", "series_id", "name", "name"}}) {
    auto rows = catalogue.connection_.Prepare(
        "WITH " + internal::JobScopeCte(scope) + " SELECT * FROM " + named.table + " WHERE id IN (SELECT t." +
        named.test_column + " FROM tests AS t JOIN scope ON scope.test_id = t.id) ORDER BY id");
    internal::BindJobScope(*rows, scope);
    CopyRows(*rows, results.connection_, named.table, named.unique_column, named.label_column,
             conflict_prefix);
  }
  std::int64_t copied = 0;
  {
    auto tests = catalogue.connection_.Prepare(
        "WITH " + internal::JobScopeCte(scope) +
        " SELECT * FROM tests WHERE id IN (SELECT test_id FROM scope) ORDER BY id");
    internal::BindJobScope(*tests, scope);
    copied = CopyRows(*tests, results.connection_, "tests", "content_hash", "external_id", conflict_prefix);
  }
  transaction.Commit();
  return copied;
}

}  // namespace napkin::db
