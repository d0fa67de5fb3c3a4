#include "db/migrate.h"

#include <stdexcept>
#include <string>
#include <string_view>

#include "engine/summary_fields.h"

namespace napkin::db {
namespace {

// napkin_injury_risk(field, criterion): the risk of the curve of summary
// field `field` (engine/summary_fields.h RiskCurve) at `criterion`; NULL for a NULL
// criterion or an unknown field. Migrations call it to give results computed
// before a curve existed the risk their stored criterion stands for, by the
// engine's own function (schema/008_injury_risk.sql).
void InjuryRiskFunction(sqlite3_context* context, int, sqlite3_value** arguments) {
  const unsigned char* field = sqlite3_value_text(arguments[0]);
  const engine::SummaryField* risk =
      field == nullptr ? nullptr : engine::FindSummaryField(reinterpret_cast<const char*>(field));
  const engine::RiskCurve* curve = risk == nullptr ? nullptr : risk->curve;
  if (curve == nullptr || sqlite3_value_type(arguments[1]) == SQLITE_NULL) {
    sqlite3_result_null(context);
    return;
  }
  sqlite3_result_double(context, curve->risk(sqlite3_value_double(arguments[1])));
}

void RegisterMigrationFunctions(Connection& connection) {
  if (sqlite3_create_function_v2(connection.handle(), "napkin_injury_risk", 2,
                                 SQLITE_UTF8 | SQLITE_DETERMINISTIC | SQLITE_DIRECTONLY, nullptr,
                                 InjuryRiskFunction, nullptr, nullptr, nullptr) != SQLITE_OK)
    throw DatabaseError("cannot register the SQL function napkin_injury_risk.", SQLITE_ERROR);
}

}  // namespace

void CheckMigrationList(std::span<const schema::Migration> migrations) {
  for (std::size_t i = 0; i < migrations.size(); ++i)
    if (migrations[i].version != static_cast<int>(i) + 1)
      throw std::invalid_argument("migration '" + std::string(migrations[i].name) + "' has version " +
                                  std::to_string(migrations[i].version) + ", expected " +
                                  std::to_string(i + 1));
}

int ApplyMigrations(Connection& connection, std::span<const schema::Migration> migrations) {
  CheckMigrationList(migrations);
  int version = static_cast<int>(connection.PragmaInt("user_version"));
  if (version >= static_cast<int>(migrations.size())) return version;
  RegisterMigrationFunctions(connection);

  // Foreign-key enforcement is switched off while migrating (it cannot change
  // inside a transaction) so a migration may rebuild a table the SQLite way
  // (create new, copy, drop old, rename); PRAGMA foreign_key_check then
  // verifies the result before each commit.
  connection.Execute("PRAGMA foreign_keys = OFF");
  try {
    for (;;) {
      Transaction transaction(connection);
      // Read again under the write lock: another process opening the same
      // new catalogue at the same moment may have applied it meanwhile.
      version = static_cast<int>(connection.PragmaInt("user_version"));
      if (version >= static_cast<int>(migrations.size())) break;
      const schema::Migration& migration = migrations[static_cast<std::size_t>(version)];
      connection.Execute(migration.sql);
      {
        auto violations = connection.Prepare("PRAGMA foreign_key_check");
        if (violations->Step())
          throw DatabaseError("migration '" + std::string(migration.name) +
                                  "' leaves a foreign-key violation in table '" + violations->ColumnText(0) +
                                  "'.",
                              SQLITE_CONSTRAINT_FOREIGNKEY);
      }
      // PRAGMA takes no bound parameters; the version is our own integer.
      connection.Execute("PRAGMA user_version = " + std::to_string(migration.version));
      transaction.Commit();
      version = migration.version;
    }
  } catch (...) {
    connection.Execute("PRAGMA foreign_keys = ON");
    throw;
  }
  connection.Execute("PRAGMA foreign_keys = ON");
  return version;
}

}  // namespace napkin::db
